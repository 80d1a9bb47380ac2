/* The peer benchmark's conventions (../shared/bench/peer-vtk/README.md, render_vtk.py):
 * its cameras, its transfer-function files and its two synthetic phantoms, reproduced so
 * that cube5 cast and VTK draw the same frames from the same data.
 *
 * Each part follows the Python operation for operation, because the goal is the same bits,
 * not merely the same mathematics:
 *   cameras   make_cameras() in double, in the Python's order (libm cos/sin/sqrt);
 *   TF files  load_tf() + build_property(), with the defaults build_property() applies;
 *   phantoms  synthetic_volume() in float32 as numpy 1.24 evaluates it, with libm's sinf
 *             and cosf in place of numpy's own float32 ones (which differ by an ulp for some
 *             arguments): the shell phantom and ml at n = 64 are identical to numpy's, ml at
 *             n = 256 differs by one in 64 voxels. The benchmarks hand VTK our raw file, so
 *             both renderers always see the same voxels. */
#include "cast_peer.h"

#include <errno.h>
#include <jansson.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rng.h"

/* ---- cameras ------------------------------------------------------------------------- */

/* The Python's _cross() and _norm(), term for term (so that signed zeros match too). */
static void cross3(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static void normalize3(double v[3])
{
    double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    v[0] /= n, v[1] /= n, v[2] /= n;
}

/* volume_geometry(): centre and bounding-sphere radius of the point-data bounds. */
static void peer_geometry(const size_t dims[3], const double spacing[3], double center[3], double *radius)
{
    double ext[3];
    for (int a = 0; a < 3; a++) {
        ext[a] = (double)(dims[a] - 1) * spacing[a];
        center[a] = 0.5 * ext[a];
    }
    *radius = 0.5 * sqrt(ext[0] * ext[0] + ext[1] * ext[1] + ext[2] * ext[2]);
}

/* One view from two uniform draws: a direction uniform on the sphere. */
static void peer_direction(uint64_t *rng, double d[3])
{
    double u1 = c5_uniform(rng);
    double u2 = c5_uniform(rng);
    double z = 1.0 - 2.0 * u1;
    double phi = 2.0 * M_PI * u2;
    double s = sqrt(fmax(0.0, 1.0 - z * z));
    d[0] = s * cos(phi), d[1] = s * sin(phi), d[2] = z;
}

void c5_peer_cameras(const size_t dims[3], const double spacing[3], int n, uint64_t seed, double distance_factor,
                     double view_angle_deg, c5_cast_camera *out)
{
    double center[3], radius, d[3];
    peer_geometry(dims, spacing, center, &radius);
    double dist = distance_factor * radius;
    double tan_half = tan(view_angle_deg / 2.0 * (M_PI / 180.0));
    uint64_t rng = seed;
    for (int i = 0; i < n; i++) {
        c5_cast_camera *c = &out[i];
        peer_direction(&rng, d);
        /* Near the poles (0,0,1) is almost parallel to the view: the Python switches to y. */
        const double up0[3] = {0.0, fabs(d[2]) > 0.99 ? 1.0 : 0.0, fabs(d[2]) > 0.99 ? 0.0 : 1.0};
        for (int a = 0; a < 3; a++) {
            c->eye[a] = center[a] + dist * d[a];
            c->focal[a] = center[a];
            c->f[a] = -d[a];
        }
        cross3(c->f, up0, c->right);
        normalize3(c->right);
        cross3(c->right, c->f, c->up);
        c->tan_half = tan_half;
    }
}

/* ---- transfer-function files --------------------------------------------------------- */

/* build_property()'s fallbacks, which are VTK's vtkVolumeProperty defaults. */
#define PEER_AMBIENT 0.3
#define PEER_DIFFUSE 0.7
#define PEER_SPECULAR 0.2
#define PEER_SPECULAR_POWER 10.0
#define MAX_TF_FILE_BYTES ((size_t)1 << 20)

typedef struct {
    const char *label; /* the file (or built-in) named in every message */
    c5_err *err;
} tf_ctx;

/* "LABEL: KEY: problem". */
__attribute__((format(printf, 3, 4))) static int tf_fail(tf_ctx *c, const char *key, const char *fmt, ...)
{
    char problem[768];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(problem, sizeof problem, fmt, ap);
    va_end(ap);
    return c5_fail(c->err, "%s: %s: %s", c->label, key, problem);
}

/* A finite number in [lo, hi]; `what` names it within `key` ("x", "alpha", ...) or is NULL. */
static int tf_number(tf_ctx *c, const char *key, const char *what, const json_t *v, double lo, double hi,
                     double *out)
{
    const char *w = what ? what : "", *sep = what ? " " : "";
    if (!json_is_number(v))
        return tf_fail(c, key, "%s%smust be a number", w, sep);
    double x = json_number_value(v);
    if (!isfinite(x))
        return tf_fail(c, key, "%s%smust be finite", w, sep);
    if (!(x >= lo && x <= hi)) {
        if (isinf(hi))
            return tf_fail(c, key, "%s%smust be >= %.15g, got %.15g", w, sep, lo, x);
        return tf_fail(c, key, "%s%smust be in [%.15g, %.15g], got %.15g", w, sep, lo, hi, x);
    }
    *out = x;
    return 0;
}

/* Control points: 1..C5_MAX_TF_POINTS arrays [x, v1, ...] of `cols` numbers, x in [0,255]
 * and strictly rising (VTK would silently merge or reorder them), the rest in [0,1]. */
static int tf_points(tf_ctx *c, const json_t *root, const char *key, int cols, const char *const names[],
                     double pts[][4], int *n)
{
    const json_t *arr = json_object_get(root, key);
    if (!arr)
        return tf_fail(c, key, "missing (required)");
    size_t count = json_is_array(arr) ? json_array_size(arr) : 0;
    if (!json_is_array(arr) || count < 1 || count > C5_MAX_TF_POINTS)
        return tf_fail(c, key, "must be an array of 1 to %d points", C5_MAX_TF_POINTS);
    for (size_t i = 0; i < count; i++) {
        char k[64];
        snprintf(k, sizeof k, "%s[%zu]", key, i);
        const json_t *p = json_array_get(arr, i);
        if (!json_is_array(p) || json_array_size(p) != (size_t)cols)
            return tf_fail(c, k, "must be an array of %d numbers", cols);
        for (int j = 0; j < cols; j++)
            if (tf_number(c, k, names[j], json_array_get(p, (size_t)j), 0.0, j ? 1.0 : 255.0, &pts[i][j]))
                return -1;
        if (i > 0 && !(pts[i][0] > pts[i - 1][0]))
            return tf_fail(c, k, "x must rise strictly (%.15g after %.15g)", pts[i][0], pts[i - 1][0]);
    }
    *n = (int)count;
    return 0;
}

/* A key the peer accepts but whose only value cube5 can honour is `want` (n numbers). */
static int tf_fixed_vector(tf_ctx *c, const json_t *root, const char *key, const double *want, size_t n,
                           const char *why)
{
    const json_t *v = json_object_get(root, key);
    if (!v)
        return 0;
    int ok = json_is_array(v) && json_array_size(v) == n;
    for (size_t i = 0; ok && i < n; i++) {
        const json_t *e = json_array_get(v, i);
        ok = json_is_number(e) && json_number_value(e) == want[i];
    }
    if (ok)
        return 0;
    char *text = json_dumps(v, JSON_COMPACT | JSON_ENCODE_ANY);
    int rc = tf_fail(c, key, "must be %s, got %s", why, text ? text : "?");
    free(text);
    return rc;
}

static int tf_check_keys(tf_ctx *c, const json_t *obj, const char *where, const char *const *known)
{
    const char *k;
    const json_t *v;
    json_object_foreach((json_t *)obj, k, v) {
        int found = 0;
        for (const char *const *q = known; *q && !found; q++)
            found = !strcmp(k, *q);
        if (!found)
            return where ? tf_fail(c, where, "unknown key \"%s\"", k) : tf_fail(c, k, "unknown key");
    }
    return 0;
}

/* name and description are free text, but must be text. */
static int tf_strings(tf_ctx *c, const json_t *root)
{
    static const char *const keys[] = {"name", "description"};
    for (int i = 0; i < 2; i++) {
        const json_t *v = json_object_get(root, keys[i]);
        if (v && !json_is_string(v))
            return tf_fail(c, keys[i], "must be a string");
    }
    return 0;
}

/* The peer reads "nearest" too, but cube5 cast reconstructs trilinearly only. */
static int tf_interpolation(tf_ctx *c, const json_t *root)
{
    const json_t *v = json_object_get(root, "interpolation");
    if (!v)
        return 0;
    if (!json_is_string(v))
        return tf_fail(c, "interpolation", "must be the string \"linear\"");
    if (!strcmp(json_string_value(v), "nearest"))
        return tf_fail(c, "interpolation", "\"nearest\" is not supported (cube5 cast interpolates trilinearly); "
                                           "use \"linear\"");
    if (strcmp(json_string_value(v), "linear"))
        return tf_fail(c, "interpolation", "must be \"linear\", got \"%s\"", json_string_value(v));
    return 0;
}

/* An optional number >= 0 with a default; obj may be NULL (all defaults). */
static int tf_opt_number(tf_ctx *c, const json_t *obj, const char *key, const char *label_key, double dflt,
                         double *out)
{
    const json_t *v = obj ? json_object_get(obj, key) : NULL;
    if (!v) {
        *out = dflt;
        return 0;
    }
    return tf_number(c, label_key, NULL, v, 0.0, INFINITY, out);
}

/* The "shading" block, each key defaulting on its own as in build_property(). */
static int tf_shading(tf_ctx *c, const json_t *root, c5_tf_desc *tf)
{
    static const char *const keys[] = {"ambient", "diffuse", "specular", "specular_power", NULL};
    const struct {
        const char *label;
        double dflt, *out;
    } field[] = {
        {"shading.ambient", PEER_AMBIENT, &tf->ambient},
        {"shading.diffuse", PEER_DIFFUSE, &tf->diffuse},
        {"shading.specular", PEER_SPECULAR, &tf->specular},
        {"shading.specular_power", PEER_SPECULAR_POWER, &tf->specular_power},
    };
    const json_t *sh = json_object_get(root, "shading");
    if (sh && !json_is_object(sh))
        return tf_fail(c, "shading", "must be an object");
    if (sh && tf_check_keys(c, sh, "shading", keys))
        return -1;
    for (int i = 0; i < 4; i++)
        if (tf_opt_number(c, sh, keys[i], field[i].label, field[i].dflt, field[i].out))
            return -1;
    return 0;
}

/* Everything but the JSON syntax: root is an object. */
static int tf_from_json(tf_ctx *c, const json_t *root, double min_spacing, c5_tf_desc *tf)
{
    static const char *const keys[] = {"name",    "description", "scalar_range", "opacity_unit_distance_voxels",
                                       "interpolation", "opacity", "color", "shading",
                                       "background", NULL};
    static const char *const opacity_names[] = {"x", "alpha"};
    static const char *const color_names[] = {"x", "r", "g", "b"};
    static const double range[2] = {0, 255}, black[3] = {0, 0, 0};
    double pts[C5_MAX_TF_POINTS][4], unit_voxels;
    if (tf_check_keys(c, root, NULL, keys) || tf_strings(c, root) ||
        tf_fixed_vector(c, root, "scalar_range", range, 2, "[0, 255] (uint8 scalars)") ||
        tf_fixed_vector(c, root, "background", black, 3, "[0, 0, 0] (cube5 cast draws over black)") ||
        tf_interpolation(c, root))
        return -1;
    if (tf_points(c, root, "opacity", 2, opacity_names, pts, &tf->n_opacity))
        return -1;
    for (int i = 0; i < tf->n_opacity; i++)
        tf->opacity[i][0] = pts[i][0], tf->opacity[i][1] = pts[i][1];
    if (tf_points(c, root, "color", 4, color_names, pts, &tf->n_color))
        return -1;
    memcpy(tf->color, pts, (size_t)tf->n_color * sizeof tf->color[0]);
    const json_t *u = json_object_get(root, "opacity_unit_distance_voxels");
    if (u && tf_number(c, "opacity_unit_distance_voxels", NULL, u, 0.0, INFINITY, &unit_voxels))
        return -1;
    if (u && unit_voxels == 0.0)
        return tf_fail(c, "opacity_unit_distance_voxels", "must be > 0");
    tf->unit_distance = (u ? unit_voxels : 1.0) * min_spacing;
    return tf_shading(c, root, tf);
}

int c5_peer_tf_parse(const char *json_text, const char *label, double min_spacing, c5_tf_desc *out, c5_err *err)
{
    tf_ctx c = {label ? label : "transfer function", err};
    if (!json_text)
        return c5_fail(err, "%s: no text", c.label);
    if (!(isfinite(min_spacing) && min_spacing > 0))
        return c5_fail(err, "%s: the smallest spacing must be > 0, got %.15g", c.label, min_spacing);
    json_error_t je;
    json_t *root = json_loads(json_text, JSON_REJECT_DUPLICATES, &je);
    if (!root)
        return c5_fail(err, "%s: line %d, column %d: %s", c.label, je.line, je.column, je.text);
    /* Built in a scratch copy: *out changes only on success. */
    c5_tf_desc *tf = calloc(1, sizeof *tf);
    int rc;
    if (!tf)
        rc = c5_fail(err, "%s: out of memory", c.label);
    else if (!json_is_object(root))
        rc = c5_fail(err, "%s: the top level must be an object", c.label);
    else
        rc = tf_from_json(&c, root, min_spacing, tf);
    if (rc == 0)
        *out = *tf;
    free(tf);
    json_decref(root);
    return rc;
}

/* The peer's two presets, byte for byte (tf_default.json, tf_ml.json of peer-vtk), so that
 * neither a run nor a test needs the peer's folder. */
static const char tf_default_json[] =
    "{\n"
    "  \"name\": \"default\",\n"
    "  \"description\": \"Semi-transparent CT-style TF for uint8 volumes: air (<40) transparent, "
    "faint reddish soft tissue / engine casing, orange semi-transparent mid range, "
    "ivory-to-white opaque-ish dense material (bone, "
    "metal). Tuned on engine (block ~128-160 semi-transparent, "
    "dense parts ~200-255 bright) and a CT head (skin ~64-80 faint, bone visible through it).\",\n"
    "  \"scalar_range\": [0, 255],\n"
    "  \"opacity_unit_distance_voxels\": 1.0,\n"
    "  \"interpolation\": \"linear\",\n"
    "  \"opacity\": [[0, 0.0], [40, 0.0], [60, 0.002], [90, 0.004], [115, 0.01], [140, 0.03], [170, "
    "0.1], [210, 0.3], [255, 0.6]],\n"
    "  \"color\": [[0, 0.0, 0.0, 0.0], [40, 0.5, 0.1, 0.06], [80, 0.8, 0.3, 0.18], [125, 0.95, 0.6, "
    "0.35], [170, 1.0, 0.88, 0.7], [255, 1.0, 1.0, 1.0]],\n"
    "  \"shading\": {\"ambient\": 0.45, \"diffuse\": 0.65, \"specular\": 0.3, \"specular_power\": 20.0},\n"
    "  \"background\": [0.0, 0.0, 0.0]\n"
    "}\n"
    ;
static const char tf_ml_json[] =
    "{\n"
    "  \"name\": \"ml\",\n"
    "  \"description\": \"Marschner-Lobb preset: semi-transparent tent around rho = 0.5 (uint8 128), "
    "blue below, orange above.\",\n"
    "  \"scalar_range\": [0, 255],\n"
    "  \"opacity_unit_distance_voxels\": 1.0,\n"
    "  \"interpolation\": \"linear\",\n"
    "  \"opacity\": [[0, 0.0], [104, 0.0], [128, 0.12], [152, 0.0], [255, 0.0]],\n"
    "  \"color\": [[0, 0.2, 0.3, 0.9], [110, 0.2, 0.5, 1.0], [128, 0.95, 0.95, 0.95], [146, 1.0, 0.55, "
    "0.15], [255, 1.0, 0.3, 0.1]],\n"
    "  \"shading\": {\"ambient\": 0.4, \"diffuse\": 0.6, \"specular\": 0.3, \"specular_power\": 20.0},\n"
    "  \"background\": [0.0, 0.0, 0.0]\n"
    "}\n"
    ;

static const struct {
    const char *name, *label, *text;
} builtin_tfs[] = {
    {"default", "built-in tf_default.json", tf_default_json},
    {"ml", "built-in tf_ml.json", tf_ml_json},
};

/* The whole file as a NUL-terminated string (malloc'd), or NULL after c5_fail. */
static char *read_text(const char *path, c5_err *err)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        c5_fail(err, "%s: cannot open: %s", path, strerror(errno));
        return NULL;
    }
    char *buf = malloc(MAX_TF_FILE_BYTES + 1);
    size_t len = buf ? fread(buf, 1, MAX_TF_FILE_BYTES + 1, f) : 0;
    int bad = !buf || ferror(f) || len > MAX_TF_FILE_BYTES || memchr(buf, 0, len);
    if (!buf)
        c5_fail(err, "%s: out of memory", path);
    else if (ferror(f))
        c5_fail(err, "%s: cannot read: %s", path, strerror(errno));
    else if (len > MAX_TF_FILE_BYTES)
        c5_fail(err, "%s: larger than 1 MiB, too big for a transfer-function file", path);
    else if (memchr(buf, 0, len))
        c5_fail(err, "%s: contains a NUL byte, not a JSON text file", path);
    fclose(f);
    if (bad) {
        free(buf);
        return NULL;
    }
    buf[len] = 0;
    return buf;
}

int c5_peer_tf_load(const char *name_or_path, double min_spacing, c5_tf_desc *out, c5_err *err)
{
    if (!name_or_path)
        return c5_fail(err, "transfer function: no name or path");
    for (size_t i = 0; i < sizeof builtin_tfs / sizeof builtin_tfs[0]; i++)
        if (!strcmp(name_or_path, builtin_tfs[i].name))
            return c5_peer_tf_parse(builtin_tfs[i].text, builtin_tfs[i].label, min_spacing, out, err);
    char *text = read_text(name_or_path, err);
    if (!text)
        return -1;
    int rc = c5_peer_tf_parse(text, name_or_path, min_spacing, out, err);
    free(text);
    return rc;
}

/* ---- phantoms ------------------------------------------------------------------------ */

#define PHANTOM_MAX_N 2048 /* 8 GiB of voxels; far beyond any benchmark volume */

/* np.linspace(-1, 1, n, dtype=np.float32): i * step + start in double, the last point set
 * to the end exactly, then each rounded to float. */
static void np_linspace(float *t, size_t n)
{
    double step = 2.0 / (double)(n - 1);
    for (size_t i = 0; i < n; i++)
        t[i] = (float)((double)i * step + -1.0);
    t[n - 1] = 1.0f;
}

/* np.clip(np.rint(v), 0, 255).astype(np.uint8); rintf rounds half to even like np.rint. */
static uint8_t to_u8(float v)
{
    v = rintf(v);
    return (uint8_t)(v > 255.0f ? 255.0f : v > 0.0f ? v : 0.0f);
}

/* In numpy's arithmetic a Python float meets a float32 array as a float32: every constant
 * below is the Python literal rounded to float, and every operation is a float operation in
 * the Python's order. */

/* Marschner-Lobb, fM = 6, alpha = 0.25. The radial term depends on (x, y) only and the
 * vertical one on z only, so each is computed once. */
static void phantom_ml(uint8_t *vox, const float *t, size_t n, float *radial, float *vertical)
{
    const float pi = (float)M_PI, two_pi_fm = (float)(2.0 * M_PI * 6.0);
    for (size_t j = 0; j < n; j++)
        for (size_t i = 0; i < n; i++) {
            float r = sqrtf(t[i] * t[i] + t[j] * t[j]);
            radial[j * n + i] = cosf(two_pi_fm * cosf(pi * r / 2.0f));
        }
    for (size_t k = 0; k < n; k++)
        vertical[k] = 1.0f - sinf(pi * t[k] / 2.0f);
    for (size_t k = 0; k < n; k++)
        for (size_t ji = 0; ji < n * n; ji++) {
            float rho = (vertical[k] + 0.25f * (1.0f + radial[ji])) / 2.5f;
            vox[k * n * n + ji] = to_u8(255.0f * rho);
        }
}

/* clip((R - r) / w + 0.5, 0, 1), w = 0.03: 1 inside radius R, 0 outside, a linear edge. */
static float inside(float r, float radius)
{
    float v = (radius - r) / 0.03f + 0.5f;
    return v < 0.0f ? 0.0f : v > 1.0f ? 1.0f : v;
}

/* Squares of the grid coordinates and of their offsets by 0.5 (the blob centres). */
static void shell_squares(const float *t, size_t n, float *sq, float *sq_half)
{
    for (size_t i = 0; i < n; i++) {
        float d = t[i] - 0.5f;
        sq[i] = t[i] * t[i];
        sq_half[i] = d * d;
    }
}

static float shell_value(const float *sq, const float *sqh, size_t i, size_t j, size_t k)
{
    float r = sqrtf(sq[i] + sq[j] + sq[k]);
    float val = 130.0f * (inside(r, 0.80f) - inside(r, 0.70f));
    val = fmaxf(val, 240.0f * inside(r, 0.35f));
    /* blobs at +x, +y, +z, in that order */
    val = fmaxf(val, 180.0f * inside(sqrtf(sqh[i] + sq[j] + sq[k]), 0.12f));
    val = fmaxf(val, 180.0f * inside(sqrtf(sq[i] + sqh[j] + sq[k]), 0.12f));
    val = fmaxf(val, 180.0f * inside(sqrtf(sq[i] + sq[j] + sqh[k]), 0.12f));
    return val;
}

static void phantom_shell(uint8_t *vox, const float *t, size_t n, float *sq, float *sq_half)
{
    shell_squares(t, n, sq, sq_half);
    for (size_t k = 0; k < n; k++)
        for (size_t j = 0; j < n; j++)
            for (size_t i = 0; i < n; i++)
                vox[(k * n + j) * n + i] = to_u8(shell_value(sq, sq_half, i, j, k));
}

uint8_t *c5_phantom_make(c5_phantom kind, size_t n)
{
    if (n < 2 || n > PHANTOM_MAX_N || (kind != C5_PHANTOM_ML && kind != C5_PHANTOM_SHELL))
        return NULL;
    uint8_t *vox = malloc(n * n * n);
    float *t = malloc(n * sizeof *t);
    /* scratch: ml's radial table (n^2) and vertical row (n); shell's two rows of squares */
    float *a = malloc(n * n * sizeof *a), *b = malloc(n * sizeof *b);
    if (vox && t && a && b) {
        np_linspace(t, n);
        if (kind == C5_PHANTOM_ML)
            phantom_ml(vox, t, n, a, b);
        else
            phantom_shell(vox, t, n, a, b);
    } else {
        free(vox);
        vox = NULL;
    }
    free(t);
    free(a);
    free(b);
    return vox;
}

int c5_phantom_parse(const char *s, c5_phantom *out)
{
    if (s && !strcmp(s, "ml"))
        *out = C5_PHANTOM_ML;
    else if (s && !strcmp(s, "shell"))
        *out = C5_PHANTOM_SHELL;
    else
        return -1;
    return 0;
}
