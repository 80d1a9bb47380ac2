/* The scenes of the numerical stability suite (stab_scenes.h): docs/stability.md says what
 * each one stresses. */
#include "stab_scenes.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "harness.h"

char stab_msg[1024];

int stab_fail(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(stab_msg, sizeof stab_msg, fmt, ap);
    va_end(ap);
    return -1;
}

int stab_load(stab_scene *sc, const char *fmt, ...)
{
    char text[4096];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    c5_err err;
    if (c5_scene_parse(c5t_json(text), NULL, "stability", &sc->s, &err) != 0 ||
        c5_supervol_build(&sc->s, &sc->sv, &err) != 0)
        return stab_fail("scene: %s", err.msg);
    return 0;
}

void stab_headlight(stab_scene *sc)
{
    if (sc->s.n_lights > 0 && sc->s.lights[0].kind == C5_LIGHT_POINT)
        sc->s.lights[0].position = sc->s.camera.eye;
}

void stab_camera(stab_scene *sc, c5_vec3 eye, c5_vec3 target, c5_vec3 up)
{
    sc->s.camera.eye = eye;
    sc->s.camera.target = target;
    sc->s.camera.up = up;
    stab_headlight(sc);
}

const c5_vec3 STAB_UP_Z = {0, 0, 1}, STAB_UP_Y = {0, 1, 0};

/* Loads, then puts the headlight at the eye. */
#define LOAD_LIT(sc, ...)                      \
    do {                                       \
        if (stab_load(sc, __VA_ARGS__) != 0)   \
            return -1;                         \
        stab_headlight(sc);                    \
        return 0;                              \
    } while (0)

/* ---- stiff transfer functions ----------------------------------------------------------- */

/* Opacity jumps from 0 at scalar 127 to 1 at 128 across a ramp (17 a voxel): the table is
 * linear between entries, so alpha changes by 1 per scalar unit there, and the model's
 * scalar error (UQ8.8 rounding, the position's error from the SQ1.14 direction: ~2^-15 x
 * distance) goes into alpha at that slope. */
int stab_scene_stiff_jump(stab_scene *sc)
{
    LOAD_LIT(sc, "{'volumes': [{'generator': 'ramp', 'dims': [16, 16, 16], 'axis': 0}],"
                 " 'transfer_function': {'opacity': [[0, 0], [127, 0], [128, 1], [255, 1]],"
                 "   'color': [[0, 1, 0.5, 0.2], [255, 0.2, 0.5, 1]]}, " HEADLIGHT ", " CAM(32, 30) "}");
}

/* Extinction x step far above 1: opacity per unit_distance 0.02 with the step 1 (50 units a
 * step), so every sample above the threshold is opaque to double precision. */
int stab_scene_stiff_extinction(stab_scene *sc)
{
    LOAD_LIT(sc, "{'volumes': [{'generator': 'blobs', 'dims': [16, 16, 16], 'seed': 3}],"
                 " 'transfer_function': {'opacity': [[0, 0], [60, 0], [61, 0.5], [255, 0.9]],"
                 "   'color': [[0, 1, 0.5, 0.2], [255, 0.2, 0.5, 1]], 'unit_distance': 0.02},"
                 " " HEADLIGHT ", " CAM(32, 30) "}");
}

/* A step edge 0 | 255 between voxels: the largest central difference (255) and gradient
 * (SQ8.8 stays below 256, no saturation). */
int stab_scene_step_edge(stab_scene *sc)
{
    if (stab_load(sc, "{'volumes': [{'generator': 'constant', 'dims': [16, 16, 16]}],"
                      " 'transfer_function': {'opacity': [[0, 0], [127, 0], [128, 0.6], [255, 0.6]],"
                      "   'color': [[0, 1, 1, 1], [255, 1, 0.8, 0.6]]}, " HEADLIGHT ", " CAM(32, 30) "}") != 0)
        return -1;
    stab_headlight(sc);
    for (size_t k = 0; k < 16; k++) /* 0 below x = 8, 255 from there, in a slab |z - 8| < 5 */
        for (size_t j = 0; j < 16; j++)
            for (size_t i = 8; i < 16; i++)
                sc->sv.v[(k * 16 + j) * 16 + i] = k > 3 && k < 13 ? 255 : 0;
    return 0;
}

/* ---- the Marschner-Lobb signal ---------------------------------------------------------- */

/* The classic 41^3 test signal (f_m 6, alpha 0.25) through a thin tent around 128: the
 * worst case for interpolation and gradient precision; shaded, step 1/2 voxel. */
int stab_scene_marschner_lobb(stab_scene *sc)
{
    LOAD_LIT(sc, "{'volumes': [{'generator': 'marschner_lobb', 'dims': [41, 41, 41], 'f_m': 6, 'alpha': 0.25}],"
                 " 'transfer_function': {'opacity': [[0, 0], [104, 0], [128, 0.3], [152, 0], [255, 0]],"
                 "   'color': [[0, 0.2, 0.3, 0.9], [128, 0.95, 0.95, 0.95], [255, 1, 0.3, 0.1]]},"
                 " " HEADLIGHT ","
                 " 'camera': {'eye': [100, -55, 75], 'target': [20.5, 20.5, 20.5], 'fov': 34, 'width': 40,"
                 "   'height': 40}, 'render': {'step': 0.5, 'max_opacity': 1}}");
}

/* ---- rays along axes, cell faces, edges and corners ------------------------------------- */

/* 17x17 images: the centre pixel's ray is exactly the view axis. Every camera below puts
 * that ray (and, for the axis-parallel ones, a column or row of rays) on a cell face, a
 * cell edge, a voxel face or through a cell corner of the 2x2x2 split. */
int stab_scene_axis_rays(stab_scene *sc)
{
    LOAD_LIT(sc, "{'volumes': [{'generator': 'blobs', 'dims': [16, 16, 16], 'seed': 5}], " TF_SOFT ", " HEADLIGHT
                 ", " CAM(17, 20) "}");
}

const stab_cam stab_axis_cams[STAB_N_AXIS_CAMS] = {
    {"+x along the cell edge y=z=8", {-20, 8, 8}, {0, 8, 8}, {0, 0, 1}},
    {"+y in the cell face x=8", {8, -20, 5.25}, {8, 0, 5.25}, {0, 0, 1}},
    {"-z along the cell edge x=y=8", {8, 8, 40}, {8, 8, 0}, {0, 1, 0}},
    {"+x along voxel faces y=3 z=11", {-20, 3, 11}, {0, 3, 11}, {0, 0, 1}},
    {"diagonal through the cell corner", {-12, -12, -12}, {8, 8, 8}, {0, 0, 1}},
    {"diagonal into the grid's edge", {-10, -10, 8}, {0, 0, 8}, {0, 0, 1}},
    {"-x along the grid's high face", {40, 8, 16}, {16, 8, 16}, {0, 1, 0}},
};

/* ---- grazing hits on planes ------------------------------------------------------------- */

/* A diffuse, partly reflective floor z = 0 (the grid's bottom face) lit by a shadow-casting
 * light, seen from just above it, from inside its plane (the middle row is exactly
 * parallel: no hit) and from just below. */
int stab_scene_grazing(stab_scene *sc)
{
    return stab_load(sc, "{'volumes': [{'generator': 'blobs', 'dims': [16, 16, 16], 'seed': 2}], " TF_SOFT ","
                         " 'lights': [{'type': 'point', 'position': [8, 8, 30], 'shadows': true}],"
                         " 'surfaces': [{'type': 'plane', 'point': [0, 0, 0], 'normal': [0, 0, 1],"
                         "   'material': {'color': [0.9, 0.8, 0.6], 'reflectivity': 0.3}}],"
                         " 'camera': {'eye': [-40, 8, 0.05], 'target': [40, 8, 0], 'fov': 30, 'width': 32,"
                         " 'height': 32}, 'render': {'background': [0.1, 0.2, 0.3]}}");
}

/* The eye 1e-4 above the floor finds floor hits 1e-4 / sin(angle) ahead, many closer than the
 * spawned rays' 1/64 voxel: eye rays take any hit at t > 0 (rtl_model/proc/processor.c
 * c5_proc_new_ray), as cref does. */
const double stab_grazing_heights[STAB_N_GRAZING] = {0.05, 1e-4, 0, -0.02};

void stab_grazing_camera(stab_scene *sc, int i)
{
    double h = stab_grazing_heights[i];
    stab_camera(sc, v3(-40, 8, h), v3(40, 8, h > 0 ? 0 : h), STAB_UP_Z);
}

/* ---- total internal reflection ---------------------------------------------------------- */

/* A fully transparent bubble (ior 0.6 < 1) in front of the volume: rays entering it beyond
 * the critical angle asin(0.6) reflect totally; a glass ball (ior 1.5) beside it refracts.
 * Neither reflects by its material, so every reflected ray is a TIR ray. */
int stab_scene_tir(stab_scene *sc)
{
    LOAD_LIT(sc, "{'volumes': [{'generator': 'blobs', 'dims': [16, 16, 16], 'seed': 4}], " TF_SOFT ", " HEADLIGHT
                 ", 'surfaces': ["
                 "  {'type': 'sphere', 'center': [4, -8, 8], 'radius': 4,"
                 "   'material': {'transparency': 1, 'reflectivity': 0, 'ior': 0.6}},"
                 "  {'type': 'sphere', 'center': [12.5, -8, 8], 'radius': 3.5,"
                 "   'material': {'transparency': 1, 'reflectivity': 0, 'ior': 1.5}}],"
                 " 'camera': {'eye': [8, -40, 8], 'target': [8, 8, 8], 'fov': 30, 'width': 40, 'height': 40},"
                 " 'render': {'max_bounces': 6, 'background': [0.3, 0.3, 0.35]}}");
}

/* ---- two parallel mirrors --------------------------------------------------------------- */

/* Perfect mirrors z = -1 and z = 17 around the volume, min_weight 0: only the bounce limit
 * (15, the packet's generation field) ends a ray. */
int stab_scene_mirrors(stab_scene *sc)
{
    return stab_load(sc, "{'volumes': [{'generator': 'blobs', 'dims': [16, 16, 16], 'seed': 6}], " TF_SOFT ","
                         " 'surfaces': ["
                         "  {'type': 'plane', 'point': [0, 0, -1], 'normal': [0, 0, 1],"
                         " 'material': {'reflectivity': 1}},"
                         "  {'type': 'plane', 'point': [0, 0, 17], 'normal': [0, 0, -1],"
                         " 'material': {'reflectivity': 1}}],"
                         " 'camera': {'eye': [-20, 8, 8], 'target': [8, 8, 5], 'fov': 50, 'width': 24, 'height': 24},"
                         " 'render': {'max_bounces': 15, 'min_weight': 0, 'background': [0.2, 0.3, 0.4]}}");
}

/* ---- the camera inside the volume, on cell boundaries ----------------------------------- */

/* Rays that start inside the grid: their first sample is at the eye. On a boundary the eye's
 * cell is decided by half-open boxes in both renderers. */
int stab_scene_camera_inside(stab_scene *sc)
{
    LOAD_LIT(sc, "{'volumes': [{'generator': 'blobs', 'dims': [16, 16, 16], 'seed': 7}], " TF_SOFT ", " HEADLIGHT
                 ", " CAM(24, 70) "}");
}

const stab_cam stab_inside_cams[STAB_N_INSIDE_CAMS] = {
    {"eye inside a cell", {6.3, 7.1, 9.4}, {16, 12, 3}, {0, 0, 1}},
    {"eye on the corner of 8 cells", {8, 8, 8}, {16, 12, 3}, {0, 0, 1}},
    {"eye on the cell face x=8", {8, 4.5, 4.5}, {0, 9, 12}, {0, 0, 1}},
    {"eye on the grid's low face", {0, 8, 8}, {16, 8, 8}, {0, 0, 1}},
    {"eye on the grid's high face", {16, 8, 8}, {0, 8, 8}, {0, 0, 1}},
    {"eye on the grid's corner", {0, 0, 0}, {16, 16, 16}, {0, 0, 1}},
};

/* ---- fields of view of 0.5 and 170 degrees ---------------------------------------------- */

/* 0.5 degrees from 4000 voxels away (geom coordinates near their 8000 limit): neighbouring
 * pixels' directions differ by ~3 SQ1.14 steps, whose rounding (2^-15 rad) moves a ray by
 * up to 0.12 voxel at that distance: the error is the blobs' value change over 0.1 voxel. */
int stab_scene_fov_narrow(stab_scene *sc)
{
    LOAD_LIT(sc, "{'volumes': [{'generator': 'blobs', 'dims': [24, 24, 24], 'seed': 8}], " TF_SOFT ", " HEADLIGHT
                 ", 'camera': {'eye': [-3988, 12, 12], 'target': [12, 12, 12], 'fov': 0.5, 'width': 32,"
                 "   'height': 32}}");
}

int stab_scene_fov_wide(stab_scene *sc)
{
    LOAD_LIT(sc, "{'volumes': [{'generator': 'blobs', 'dims': [24, 24, 24], 'seed': 8}], " TF_SOFT ", " HEADLIGHT
                 ", 'camera': {'eye': [12, -2, 12], 'target': [12, 12, 12], 'fov': 170, 'width': 32,"
                 "   'height': 32}}");
}

/* ---- degenerate and extreme volume shapes ----------------------------------------------- */

int stab_scene_volume_1(stab_scene *sc)
{
    LOAD_LIT(sc, "{'volumes': [{'generator': 'constant', 'dims': [1, 1, 1], 'value': 200}], " TF_SOFT ", " HEADLIGHT
                 ", 'camera': {'eye': [3, -4, 2.5], 'target': [0.5, 0.5, 0.5], 'width': 24, 'height': 24},"
                 " 'render': {'step': 0.25}}");
}

int stab_scene_volume_rod(stab_scene *sc)
{
    LOAD_LIT(sc, "{'volumes': [{'generator': 'ramp', 'dims': [1, 1, 64], 'axis': 2}], " TF_SOFT ", " HEADLIGHT
                 ", 'camera': {'eye': [30, -40, 32], 'target': [0.5, 0.5, 32], 'fov': 20, 'width': 25,"
                 "   'height': 25}, 'render': {'step': 0.25}}");
}

int stab_scene_volume_slab(stab_scene *sc)
{
    LOAD_LIT(sc, "{'volumes': [{'generator': 'blobs', 'dims': [512, 512, 1], 'seed': 9}], " TF_SOFT ", " HEADLIGHT
                 ", 'camera': {'eye': [256, -300, 400], 'target': [256, 256, 0.5], 'fov': 60, 'width': 32,"
                 "   'height': 32}}");
}

/* ---- all-zero and all-255 volumes ------------------------------------------------------- */

/* All zero with alpha 0 at table entries 0 and 1 (a sample between entries 0 and 1 could
 * see entry 1's alpha, so the emptiness flags look at both): every cell and block is
 * leaped, the image is the background. */
const stab_constant_case stab_constant_cases[STAB_N_CONSTANT] = {
    {"all 0, alpha(0) = 0", 0, "[[0, 0], [1, 0], [255, 0.5]]"},
    {"all 0, alpha(0) = 0.05", 0, "[[0, 0.05], [255, 0.5]]"},
    {"all 255, alpha(255) = 0.1", 255, "[[0, 0], [255, 0.1]]"},
    {"all 255, alpha(255) = 1", 255, "[[0, 0], [254, 0], [255, 1]]"},
};

int stab_scene_constant(stab_scene *sc, int i)
{
    LOAD_LIT(sc, "{'volumes': [{'generator': 'constant', 'dims': [16, 16, 16], 'value': %d}],"
                 " 'transfer_function': {'opacity': %s, 'color': [[0, 0.9, 0.5, 0.2], [255, 0.3, 0.6, 1]]},"
                 " " HEADLIGHT ", " CAM(24, 30) ", 'render': {'background': [0.3, 0.3, 0.3]}}",
             stab_constant_cases[i].value, stab_constant_cases[i].opacity);
}

/* ---- saturation ------------------------------------------------------------------------- */

/* Ray colour: a constant volume shaded by ambient 15.9 (the limit is 16) gives every ray
 * ~15 in red and green. */
int stab_scene_sat_ray_colour(stab_scene *sc)
{
    LOAD_LIT(sc, "{'volumes': [{'generator': 'constant', 'dims': [16, 16, 16], 'value': 200}],"
                 " 'transfer_function': {'opacity': [[0, 0.3], [255, 0.3]], 'color': [[0, 1, 0.9, 0.05],"
                 " [255, 1, 0.9, 0.05]], 'shading': {'ambient': 15.9, 'diffuse': 15.9, 'specular': 15.9}}, "
                 HEADLIGHT ", " CAM(24, 30) "}");
}

/* Shadow-ray radiance: a floor lit only through shadow rays by a light of intensity 15.9:
 * up to 12.7 per ray. */
int stab_scene_sat_shadow(stab_scene *sc)
{
    return stab_load(sc, "{'lights': [{'type': 'point', 'position': [0, 0, 2], 'intensity': 15.9, 'shadows': true}],"
                         " 'surfaces': [{'type': 'plane', 'point': [0, 0, 0], 'normal': [0, 0, 1],"
                         "   'material': {'color': [1, 0.5, 0.1], 'ambient': 0, 'diffuse': 1}}],"
                         " 'camera': {'eye': [0, -20, 14], 'target': [0, 0, 0], 'fov': 80, 'width': 32,"
                         " 'height': 32}}");
}

/* A floor under 8 non-shadow lights of intensity 15.9 with diffuse 15.9: near 2000 in cref; the
 * model's light_term saturates at 16 - 2^-12 (UQ4.12). */
int stab_scene_sat_frame_acc(stab_scene *sc)
{
    char lights[1024] = "";
    for (int i = 0; i < 8; i++) /* 8 lights (the maximum), intensity just below the format's 16 */
        snprintf(lights + strlen(lights), sizeof lights - strlen(lights),
                 "%s{'type': 'point', 'position': [%d, %d, 6], 'intensity': 15.9}", i ? ", " : "", 4 * (i % 4) - 6,
                 8 * (i / 4) - 4);
    return stab_load(sc, "{'lights': [%s], 'surfaces': [{'type': 'plane', 'point': [0, 0, 0], 'normal': [0, 0, 1],"
                         "   'material': {'color': [1, 1, 1], 'ambient': 15.9, 'diffuse': 15.9}}],"
                         " 'camera': {'eye': [0, -20, 14], 'target': [0, 0, 0], 'fov': 60, 'width': 24,"
                         " 'height': 24}}",
                     lights);
}
