/* The scene: everything a frame needs, as parsed from JSON (docs/scene-format.md) or taken
 * from a built-in scene. Lengths are world units; angles degrees; colours linear RGB. */
#ifndef C5_SCENE_H
#define C5_SCENE_H

#include <stddef.h>
#include <stdint.h>

#include "err.h"
#include "vec.h"
#include "volume.h"

#define C5_MAX_VOLUMES 8
#define C5_MAX_TF_POINTS 64
#define C5_MAX_LIGHTS 8
#define C5_MAX_SURFACES 32
#define C5_MAX_CAMERA_KEYS 64
#define C5_MAX_IMAGE_DIM 4096
#define C5_MAX_FRAMES 10000
#define C5_MAX_BOUNCES 16
/* Samples along the grid's diagonal at the render step, at most: a ray's sampling work is
 * bounded (2^20 is about 1000 samples per voxel across the largest board grid, 512^3);
 * c5_supervol_build refuses a scene past it (docs/scene-format.md). */
#define C5_MAX_RAY_SAMPLES (1 << 20)

/* ---- volumes ---------------------------------------------------------------------- */

typedef enum { C5_SRC_FILE, C5_SRC_GENERATOR } c5_source_kind;

typedef enum {
    C5_GEN_MARSCHNER_LOBB, /* params: f_m (6), alpha (0.25) */
    C5_GEN_BLOBS,          /* params: count (12), seed (1): smooth Gaussian blobs, a CT-like stand-in */
    C5_GEN_CLOUD,          /* params: seed (1): value-noise fBm inside a soft ellipsoid */
    C5_GEN_SPHERE,         /* params: radius (0.4, fraction of the smallest extent), value (200) */
    C5_GEN_CONSTANT,       /* params: value (0) */
    C5_GEN_RAMP,           /* params: axis (0): value rises 0..255 along the axis */
} c5_generator;

typedef struct {
    c5_source_kind kind;
    /* file */
    char path[1024];       /* resolved against the scene file's folder */
    c5_raw_spec raw;       /* raw only; dims/type 0 = from the Open SciVis name */
    int has_window;        /* uint16 only: map [window[0], window[1]] linearly onto 0..255 */
    double window[2];      /* default: the file's own min..max */
    /* generator */
    c5_generator generator;
    size_t gen_dims[3];
    double f_m, alpha, radius, value;
    int count, axis;
    uint64_t seed;
    /* placement: voxel (0,0,0) of this source lands on grid voxel offset[] */
    long offset[3];
} c5_volume_desc;

/* The super volume: one 8-bit grid holding every placed volume (the board's memory model).
 * Voxel (i,j,k) is centred at origin + (i+0.5, j+0.5, k+0.5) * spacing. */
typedef struct {
    int has_center;        /* 1: `center` given, origin derived from it; 0: `origin` */
    c5_vec3 origin;        /* world position of the grid's low corner; default (0,0,0) */
    c5_vec3 center;        /* world position of the grid's centre */
    c5_vec3 spacing;       /* voxel size, default (1,1,1); every component in [1e-6, 1e6] */
    int has_spacing;       /* 1: `spacing` given in the scene (it wins over a file's own) */
    double size;           /* > 0: scale spacing uniformly so the largest world extent of the
                              grid is `size` (a replaced volume keeps the scene's framing) */
    size_t dims[3];        /* default 0: the bounding box of the placed volumes */
    unsigned fill;         /* value of grid voxels no volume covers, 0..255; default 0 */
} c5_grid_desc;

/* ---- classification and shading ---------------------------------------------------- */

typedef struct {
    int n_opacity;
    double opacity[C5_MAX_TF_POINTS][2];  /* (scalar 0..255, alpha 0..1), x strictly rising */
    int n_color;
    double color[C5_MAX_TF_POINTS][4];    /* (scalar, r, g, b), x strictly rising */
    double unit_distance;                 /* alpha is per this length; 0 (default): min spacing */
    double ambient, diffuse, specular, specular_power; /* defaults 0.3 0.7 0.2 20 */
} c5_tf_desc;

/* ---- lights, surfaces --------------------------------------------------------------- */

typedef enum { C5_LIGHT_POINT, C5_LIGHT_DIRECTIONAL } c5_light_kind;

typedef struct {
    c5_light_kind kind;
    c5_vec3 position;   /* point */
    c5_vec3 direction;  /* directional: the direction light travels, normalised on load */
    double intensity;   /* default 1 */
    int shadows;        /* default 0: surface hits spawn shadow rays towards it */
} c5_light;

typedef struct {
    c5_vec3 color;       /* diffuse colour, default (0.8,0.8,0.8) */
    double ambient;      /* default 0.1 */
    double diffuse;      /* default 0.9 */
    double reflectivity; /* 0..1, default 0 */
    double transparency; /* 0..1, default 0; reflectivity + transparency <= 1 */
    double ior;          /* [0.001, 1000], default 1.5 (docs/scene-format.md, "Valid ranges") */
} c5_material;

typedef enum { C5_SURF_PLANE, C5_SURF_RECT, C5_SURF_SPHERE } c5_surface_kind;

typedef struct {
    c5_surface_kind kind;
    c5_vec3 point;   /* plane: a point on it; rect: one corner; sphere: the centre */
    c5_vec3 normal;  /* plane: normalised on load (rect: derived as normalize(u x v)) */
    c5_vec3 u, v;    /* rect: the two edges from the corner, perpendicular, non-zero */
    double radius;   /* sphere, > 0 */
    c5_material mat;
} c5_surface;

/* ---- camera ------------------------------------------------------------------------- */

typedef struct {
    c5_vec3 eye, target, up; /* up default (0,0,1); must not be parallel to target-eye */
    double fov_deg;          /* vertical field of view, 0 < fov < 180; default 30 */
} c5_camera;

typedef struct {
    int n_keys;                       /* 0: no path, the camera stands still */
    c5_camera keys[C5_MAX_CAMERA_KEYS];
    int frames;                       /* frames over the path, >= 1; default 1 */
} c5_camera_path;

/* ---- render settings ---------------------------------------------------------------- */

typedef struct {
    int width, height;      /* pixels, 1..C5_MAX_IMAGE_DIM; default 256x256 (JSON: camera.width/height) */
    double step;            /* sample step, world units; 0 (default): the smallest spacing */
    double max_opacity;     /* early termination, (0,1]; default 0.99 */
    int max_bounces;        /* reflect/refract generations, 0..C5_MAX_BOUNCES; default 3 */
    double min_weight;      /* rays lighter than this in every channel are not spawned; default 1/256 */
    c5_vec3 background;     /* default (0,0,0) */
    int shading;            /* 1 (default): Phong-shade volume samples when there are lights */
} c5_render_settings;

/* ---- the scene ---------------------------------------------------------------------- */

typedef struct {
    char name[128];
    char source[1100];     /* the parser's WHAT (a file path, "built-in scene NAME"): later
                              checks (c5_supervol_build) name the scene with it */
    int n_volumes;
    c5_volume_desc volumes[C5_MAX_VOLUMES];
    c5_grid_desc grid;
    c5_tf_desc tf;
    int n_lights;
    c5_light lights[C5_MAX_LIGHTS];
    int n_surfaces;
    c5_surface surfaces[C5_MAX_SURFACES];
    c5_camera camera;
    c5_camera_path path;
    c5_render_settings render;
} c5_scene;

/* Parses and validates a scene. `base_dir` resolves relative volume paths (NULL: cwd).
 * `what` names the source in messages (a file name, or "built-in scene NAME").
 * Every error names the JSON path of the offending key, e.g. "scene.json: camera.fov:
 * must be a number in (0, 180), got 190". Unknown keys are errors. */
int c5_scene_parse(const char *json_text, const char *base_dir, const char *what,
                   c5_scene *out, c5_err *err);
int c5_scene_load_file(const char *path, c5_scene *out, c5_err *err);

/* The camera of frame `frame` (0-based) of the scene's path, or the fixed camera. */
c5_camera c5_scene_camera_at(const c5_scene *s, int frame);
int c5_scene_frames(const c5_scene *s);
/* 0, or -1 with "WHAT: camera_path: frame F of N: ..." when the camera of some frame
 * cannot frame a view: keys that are each valid can blend into the eye on the target or an
 * up parallel to the view. The parser calls it; so must whoever changes path.frames. */
int c5_scene_check_path(const c5_scene *s, const char *what, c5_err *err);

#endif
