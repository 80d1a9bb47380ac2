/* The scenes of the numerical stability suite, shared by tests/test_stability.c
 * (the board model against cref) and tests/test_cref_precision.c (cref in double against
 * cref in long double). Each builder parses its scene, builds the super volume and applies
 * the case's edits; it returns 0, or -1 with the reason in stab_msg. Free with
 * c5_supervol_free(&sc->sv). */
#ifndef C5_STAB_SCENES_H
#define C5_STAB_SCENES_H

#include "scene.h"
#include "supervol.h"

typedef struct {
    c5_scene s;
    c5_supervol sv;
} stab_scene;

/* The last failure's reason (stab_fail). */
extern char stab_msg[1024];
int stab_fail(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* Parses a scene written with ' for " (printf format) and builds its super volume. */
int stab_load(stab_scene *sc, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* The scene's first light, a point light, goes to the eye (HEADLIGHT below). */
void stab_headlight(stab_scene *sc);
/* Moves the camera, and the headlight with it. */
void stab_camera(stab_scene *sc, c5_vec3 eye, c5_vec3 target, c5_vec3 up);

/* Pieces of scenes (written with ' for "). */
#define TF_SOFT "'transfer_function': {'opacity': [[0, 0], [40, 0], [200, 0.5], [255, 0.8]]," \
                " 'color': [[0, 0.9, 0.4, 0.1], [128, 0.5, 0.8, 0.3], [255, 0.2, 0.4, 1]]}"
/* A point light that stab_headlight moves to the eye: two-sided shading flips the normal where N.V changes sign, and
 * with the light beside the eye N.L is then ~0 on both sides, so the flip is continuous.
 * With the light elsewhere a sample whose N.V is within rounding of 0 is lit from the
 * other side in one renderer: an honest but discontinuous error that would hide the
 * geometry these cases are about. */
#define HEADLIGHT "'lights': [{'type': 'point', 'position': [0, 0, 0]}]"
#define CAM(w, fov) "'camera': {'eye': [-30, -20, 25], 'target': [8, 8, 8], 'fov': " #fov \
                    ", 'width': " #w ", 'height': " #w "}"

extern const c5_vec3 STAB_UP_Z, STAB_UP_Y;

/* A camera of a case with several (eye, target, up). */
typedef struct {
    const char *label;
    c5_vec3 eye, target, up;
} stab_cam;

/* Stiff transfer functions: opacity 0 -> 1 between scalars 127 and 128 on a ramp; opacity
 * per unit_distance 0.02 at step 1 (extinction x step 50); a step edge 0 | 255. */
int stab_scene_stiff_jump(stab_scene *sc);
int stab_scene_stiff_extinction(stab_scene *sc);
int stab_scene_step_edge(stab_scene *sc);
/* The Marschner-Lobb signal, 41^3, f_m 6, alpha 0.25, a thin tent TF, shaded, step 1/2. */
int stab_scene_marschner_lobb(stab_scene *sc);
/* 17x17, then each of stab_axis_cams (stab_camera): rays along axes, cell faces, edges, corners. */
int stab_scene_axis_rays(stab_scene *sc);
#define STAB_N_AXIS_CAMS 7
extern const stab_cam stab_axis_cams[STAB_N_AXIS_CAMS];
/* A reflective floor z = 0 lit by a shadow light, seen from stab_grazing_heights[i]
 * (stab_grazing_camera). */
int stab_scene_grazing(stab_scene *sc);
#define STAB_N_GRAZING 4
extern const double stab_grazing_heights[STAB_N_GRAZING];
void stab_grazing_camera(stab_scene *sc, int i);
/* A transparent bubble of ior 0.6 and a glass ball of ior 1.5: every reflected ray is TIR. */
int stab_scene_tir(stab_scene *sc);
/* Perfect mirrors z = -1 and z = 17, min_weight 0, max_bounces 15. */
int stab_scene_mirrors(stab_scene *sc);
/* Eyes inside the grid and on cell and grid boundaries: stab_inside_cams (up z). */
int stab_scene_camera_inside(stab_scene *sc);
#define STAB_N_INSIDE_CAMS 6
extern const stab_cam stab_inside_cams[STAB_N_INSIDE_CAMS];
/* fov 0.5 from 4000 voxels; fov 170 next to the volume. */
int stab_scene_fov_narrow(stab_scene *sc);
int stab_scene_fov_wide(stab_scene *sc);
/* Degenerate shapes: 1^3, 1x1x64, 512x512x1. */
int stab_scene_volume_1(stab_scene *sc);
int stab_scene_volume_rod(stab_scene *sc);
int stab_scene_volume_slab(stab_scene *sc);
/* All-0 and all-255 volumes: case i of stab_constant_cases. */
typedef struct {
    const char *label;
    int value;
    const char *opacity;
} stab_constant_case;
#define STAB_N_CONSTANT 4
extern const stab_constant_case stab_constant_cases[STAB_N_CONSTANT];
int stab_scene_constant(stab_scene *sc, int i);
/* Saturation-heavy: ambient 15.9 on a constant volume (ray colour ~15); a floor lit by a
 * shadow light of intensity 15.9; a floor under 8 lights of 15.9 with diffuse 15.9 (~2000). */
int stab_scene_sat_ray_colour(stab_scene *sc);
int stab_scene_sat_shadow(stab_scene *sc);
int stab_scene_sat_frame_acc(stab_scene *sc);

#endif
