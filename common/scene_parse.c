/* The scene parser: JSON (docs/scene-format.md) to a validated c5_scene, with jansson.
 *
 * Every check goes through a few table-driven helpers (check_keys, get_num, get_int,
 * get_vec, ...) so that each message has the one form "WHAT: json.path: problem" and
 * names the offending value. The scene is built in a scratch copy: *out changes only on
 * success. */
#include "scene.h"

#include "camera.h"

#include <errno.h>
#include <jansson.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_FILE_BYTES ((size_t)16 << 20)
#define BUILTIN_PREFIX "built-in scene "

typedef struct {
    const char *what;     /* names the source in messages */
    const char *base_dir; /* relative volume paths are resolved against it; NULL: cwd */
    c5_err *err;
} ctx;

/* A closed, open or half-open interval of accepted numbers; infinite ends are unbounded. */
typedef struct {
    double lo, hi;
    int lo_open, hi_open;
} range;

#define UNIT ((range){0, 1, 0, 0})          /* [0, 1] */
#define BYTE ((range){0, 255, 0, 0})        /* [0, 255] */
/* The ranges of docs/scene-format.md ("Valid ranges"). World positions stay within 1e6 and
 * lengths at or above 1e-6, so a position keeps about 13 of double's 53 bits below the
 * smallest length; light factors stay within 1e3, so no pixel sum comes near float's
 * largest value (about 3.4e38) whatever the bounce and light counts. */
#define C5_MAX_COORD 1e6
#define C5_MIN_LENGTH 1e-6
#define COORD ((range){-C5_MAX_COORD, C5_MAX_COORD, 0, 0})
#define LENGTH ((range){C5_MIN_LENGTH, C5_MAX_COORD, 0, 0})
#define FACTOR ((range){0, 1e3, 0, 0})      /* intensities, shading factors, background */
#define IOR ((range){1e-3, 1e3, 0, 0})      /* eta^2 stays finite in refraction */
#define GEN_PARAM ((range){0, 1e3, 1, 0})   /* f_m: (0, 1e3] */

enum { OPT = 0, REQ = 1 };

#define VFMT "[%.15g, %.15g, %.15g]"
#define VARGS(v) (v).x, (v).y, (v).z

/* ---- messages ------------------------------------------------------------------------ */

/* "WHAT: path.key: problem"; path may be "" (top level) and key NULL (the object itself). */
__attribute__((format(printf, 4, 5))) static int fail(ctx *c, const char *path, const char *key,
                                                      const char *fmt, ...)
{
    char problem[768];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(problem, sizeof problem, fmt, ap);
    va_end(ap);
    if (key && *path)
        return c5_fail(c->err, "%s: %s.%s: %s", c->what, path, key, problem);
    return c5_fail(c->err, "%s: %s: %s", c->what, key ? key : path, problem);
}

static int missing(ctx *c, const char *path, const char *key)
{
    return fail(c, path, key, "missing required key");
}

static const char *kind_of(const json_t *v)
{
    switch (json_typeof(v)) {
    case JSON_OBJECT: return "an object";
    case JSON_ARRAY: return "an array";
    case JSON_STRING: return "a string";
    case JSON_INTEGER:
    case JSON_REAL: return "a number";
    case JSON_TRUE: return "true";
    case JSON_FALSE: return "false";
    default: return "null";
    }
}

/* ---- keys ---------------------------------------------------------------------------- */

static int in_list(const char *k, const char *const *list)
{
    for (; *list; list++)
        if (!strcmp(k, *list))
            return 1;
    return 0;
}

/* Every key of obj must be in `known` ("unknown key"), and in `allowed` when that is given
 * (a key of another variant: "not allowed for KIND"). */
static int check_keys(ctx *c, json_t *obj, const char *path, const char *const *known,
                      const char *const *allowed, const char *kind)
{
    for (void *it = json_object_iter(obj); it; it = json_object_iter_next(obj, it)) {
        const char *k = json_object_iter_key(it);
        if (!in_list(k, known))
            return fail(c, path, k, "unknown key");
        if (allowed && !in_list(k, allowed))
            return fail(c, path, k, "not allowed for %s", kind);
    }
    return 0;
}

/* ---- values -------------------------------------------------------------------------- */

static int in_range(double x, range r)
{
    return (r.lo_open ? x > r.lo : x >= r.lo) && (r.hi_open ? x < r.hi : x <= r.hi);
}

static int check_num(ctx *c, const char *path, const char *key, const json_t *v, range r, double *out)
{
    if (!json_is_number(v))
        return fail(c, path, key, "expected a number, got %s", kind_of(v));
    double x = json_number_value(v);
    if (!isfinite(x))
        return fail(c, path, key, "must be finite");
    if (!in_range(x, r)) {
        if (isinf(r.hi))
            return fail(c, path, key, "must be %s %.15g, got %.15g", r.lo_open ? ">" : ">=", r.lo, x);
        if (isinf(r.lo))
            return fail(c, path, key, "must be %s %.15g, got %.15g", r.hi_open ? "<" : "<=", r.hi, x);
        return fail(c, path, key, "must be in %c%.15g, %.15g%c, got %.15g", r.lo_open ? '(' : '[', r.lo,
                    r.hi, r.hi_open ? ')' : ']', x);
    }
    *out = x;
    return 0;
}

static int check_int(ctx *c, const char *path, const char *key, const json_t *v, long long lo,
                     long long hi, long long *out)
{
    if (json_is_real(v))
        return fail(c, path, key, "expected an integer, got %.15g", json_real_value(v));
    if (!json_is_integer(v))
        return fail(c, path, key, "expected an integer, got %s", kind_of(v));
    long long x = (long long)json_integer_value(v);
    if (x < lo || x > hi) {
        if (hi == LLONG_MAX)
            return fail(c, path, key, "must be >= %lld, got %lld", lo, x);
        return fail(c, path, key, "must be in [%lld, %lld], got %lld", lo, hi, x);
    }
    *out = x;
    return 0;
}

/* An array of exactly n elements, or an error naming what it is instead. */
static int check_array(ctx *c, const char *path, const char *key, const json_t *v, size_t n,
                       const char *of)
{
    if (!json_is_array(v))
        return fail(c, path, key, "expected an array of %zu %s, got %s", n, of, kind_of(v));
    if (json_array_size(v) != n)
        return fail(c, path, key, "expected an array of %zu %s, got %zu element%s", n, of,
                    json_array_size(v), json_array_size(v) == 1 ? "" : "s");
    return 0;
}

/* Numbers in an array of n: each one checked against r, its path "key[i]". */
static int check_nums(ctx *c, const char *path, const char *key, const json_t *v, size_t n, range r,
                      double *out)
{
    if (check_array(c, path, key, v, n, "numbers"))
        return -1;
    for (size_t i = 0; i < n; i++) {
        char k[96];
        snprintf(k, sizeof k, "%s[%zu]", key, i);
        if (check_num(c, path, k, json_array_get(v, i), r, &out[i]))
            return -1;
    }
    return 0;
}

static int get_num(ctx *c, json_t *obj, const char *path, const char *key, range r, int req, double def,
                   double *out)
{
    json_t *v = json_object_get(obj, key);
    if (!v) {
        *out = def;
        return req ? missing(c, path, key) : 0;
    }
    return check_num(c, path, key, v, r, out);
}

static int get_int(ctx *c, json_t *obj, const char *path, const char *key, long long lo, long long hi,
                   int req, long long def, long long *out)
{
    json_t *v = json_object_get(obj, key);
    if (!v) {
        *out = def;
        return req ? missing(c, path, key) : 0;
    }
    return check_int(c, path, key, v, lo, hi, out);
}

static int get_vec(ctx *c, json_t *obj, const char *path, const char *key, range r, int req,
                   c5_vec3 def, c5_vec3 *out)
{
    json_t *v = json_object_get(obj, key);
    double x[3];
    if (!v) {
        *out = def;
        return req ? missing(c, path, key) : 0;
    }
    if (check_nums(c, path, key, v, 3, r, x))
        return -1;
    *out = v3(x[0], x[1], x[2]);
    return 0;
}

/* Three integers in [lo, hi]; absent: all three `def`. Returns 1 when present. */
static int get_int3(ctx *c, json_t *obj, const char *path, const char *key, long long lo, long long hi,
                    int req, long long def, long long out[3])
{
    json_t *v = json_object_get(obj, key);
    out[0] = out[1] = out[2] = def;
    if (!v)
        return req ? missing(c, path, key) : 0;
    if (check_array(c, path, key, v, 3, "integers"))
        return -1;
    for (size_t i = 0; i < 3; i++) {
        char k[96];
        snprintf(k, sizeof k, "%s[%zu]", key, i);
        if (check_int(c, path, k, json_array_get(v, i), lo, hi, &out[i]))
            return -1;
    }
    return 0;
}

static int get_bool(ctx *c, json_t *obj, const char *path, const char *key, int def, int *out)
{
    json_t *v = json_object_get(obj, key);
    *out = def;
    if (!v)
        return 0;
    if (!json_is_boolean(v))
        return fail(c, path, key, "expected true or false, got %s", kind_of(v));
    *out = json_is_true(v);
    return 0;
}

static int get_str(ctx *c, json_t *obj, const char *path, const char *key, int req, const char **out)
{
    json_t *v = json_object_get(obj, key);
    *out = NULL;
    if (!v)
        return req ? missing(c, path, key) : 0;
    if (!json_is_string(v))
        return fail(c, path, key, "expected a string, got %s", kind_of(v));
    if (!*json_string_value(v))
        return fail(c, path, key, "must not be empty");
    *out = json_string_value(v);
    return 0;
}

/* One of `names` (NULL-terminated); *out is its index. */
static int get_enum(ctx *c, json_t *obj, const char *path, const char *key, const char *const *names,
                    int req, int def, int *out)
{
    const char *s;
    *out = def;
    if (get_str(c, obj, path, key, req, &s))
        return -1;
    if (!s)
        return 0;
    char list[256] = "";
    for (int i = 0; names[i]; i++) {
        if (!strcmp(s, names[i])) {
            *out = i;
            return 0;
        }
        size_t n = strlen(list);
        snprintf(list + n, sizeof list - n, "%s\"%s\"", i ? ", " : "", names[i]);
    }
    return fail(c, path, key, "must be one of %s, got \"%s\"", list, s);
}

static int get_obj(ctx *c, json_t *obj, const char *path, const char *key, int req, json_t **out)
{
    json_t *v = json_object_get(obj, key);
    *out = NULL;
    if (!v)
        return req ? missing(c, path, key) : 0;
    if (!json_is_object(v))
        return fail(c, path, key, "expected an object, got %s", kind_of(v));
    *out = v;
    return 0;
}

/* An array of min..max entries; absent: NULL (an error when required). */
static int get_arr(ctx *c, json_t *obj, const char *path, const char *key, int req, size_t min,
                   size_t max, json_t **out)
{
    json_t *v = json_object_get(obj, key);
    *out = NULL;
    if (!v)
        return req ? missing(c, path, key) : 0;
    if (!json_is_array(v))
        return fail(c, path, key, "expected an array, got %s", kind_of(v));
    size_t n = json_array_size(v);
    if (n < min)
        return fail(c, path, key, "needs at least %zu entr%s, got %zu", min, min == 1 ? "y" : "ies", n);
    if (n > max)
        return fail(c, path, key, "at most %zu entries, got %zu", max, n);
    *out = v;
    return 0;
}

/* The i-th element of an array, which must be an object; its path in p. */
static int elem_obj(ctx *c, json_t *arr, const char *path, const char *key, size_t i, char *p,
                    size_t np, json_t **out)
{
    snprintf(p, np, "%s%s%s[%zu]", path, *path ? "." : "", key, i);
    *out = json_array_get(arr, i);
    if (!json_is_object(*out))
        return fail(c, p, NULL, "expected an object, got %s", kind_of(*out));
    return 0;
}

/* The length of v without underflow or overflow: scaled by its largest component first
 * (v3_len squares, so [1e-300, 0, 0] would read as length 0). */
static double robust_len(c5_vec3 v)
{
    double m = fmax(fabs(v.x), fmax(fabs(v.y), fabs(v.z)));
    return m > 0 ? m * v3_len(v3_scale(v, 1 / m)) : 0;
}

/* A direction: "non-zero" means a length of at least C5_MIN_LENGTH, the smallest length
 * the format accepts anywhere (docs/scene-format.md, "Directions"). */
static int check_dir_len(ctx *c, const char *path, const char *key, c5_vec3 v)
{
    double l = robust_len(v);
    if (!(l >= C5_MIN_LENGTH))
        return fail(c, path, key, "must have a length of at least %g (shorter counts as zero), got " VFMT
                    " of length %g", C5_MIN_LENGTH, VARGS(v), l);
    return 0;
}

/* A direction vector, normalised. */
static int get_dir(ctx *c, json_t *obj, const char *path, const char *key, c5_vec3 *out)
{
    if (get_vec(c, obj, path, key, COORD, REQ, v3(0, 0, 0), out) || check_dir_len(c, path, key, *out))
        return -1;
    *out = v3_norm(*out);
    return 0;
}

/* ---- sections ------------------------------------------------------------------------ */

static int parse_grid(ctx *c, json_t *root, c5_grid_desc *g)
{
    static const char *const keys[] = {"origin", "center", "spacing", "size", "dims", "fill", NULL};
    const char *p = "grid";
    json_t *o;
    long long dims[3], fill;
    g->spacing = v3(1, 1, 1);
    if (get_obj(c, root, "", "grid", OPT, &o))
        return -1;
    if (!o)
        return 0;
    if (check_keys(c, o, p, keys, NULL, NULL))
        return -1;
    if (json_object_get(o, "origin") && json_object_get(o, "center"))
        return fail(c, p, "center", "not allowed together with grid.origin (give one of them)");
    g->has_center = json_object_get(o, "center") != NULL;
    g->has_spacing = json_object_get(o, "spacing") != NULL;
    if (get_vec(c, o, p, "origin", COORD, OPT, v3(0, 0, 0), &g->origin) ||
        get_vec(c, o, p, "center", COORD, OPT, v3(0, 0, 0), &g->center) ||
        get_vec(c, o, p, "spacing", LENGTH, OPT, v3(1, 1, 1), &g->spacing) ||
        get_num(c, o, p, "size", LENGTH, OPT, 0, &g->size) ||
        get_int3(c, o, p, "dims", 1, C5_VOLUME_MAX_DIM, OPT, 0, dims) ||
        get_int(c, o, p, "fill", 0, 255, OPT, 0, &fill))
        return -1;
    for (int i = 0; i < 3; i++)
        g->dims[i] = (size_t)dims[i];
    g->fill = (unsigned)fill;
    return 0;
}

static const char *const VOLUME_KEYS[] = {"file", "dims", "type", "endian", "window", "offset",
                                          "generator", "f_m", "alpha", "count", "seed", "radius",
                                          "value", "axis", NULL};
static const char *const FILE_KEYS[] = {"file", "dims", "type", "endian", "window", "offset", NULL};
static const char *const GENERATORS[] = {"marschner_lobb", "blobs", "cloud", "sphere", "constant",
                                         "ramp", NULL};
static const char *const GENERATOR_KEYS[][6] = {
    [C5_GEN_MARSCHNER_LOBB] = {"generator", "dims", "offset", "f_m", "alpha", NULL},
    [C5_GEN_BLOBS] = {"generator", "dims", "offset", "count", "seed", NULL},
    [C5_GEN_CLOUD] = {"generator", "dims", "offset", "seed", NULL},
    [C5_GEN_SPHERE] = {"generator", "dims", "offset", "radius", "value", NULL},
    [C5_GEN_CONSTANT] = {"generator", "dims", "offset", "value", NULL},
    [C5_GEN_RAMP] = {"generator", "dims", "offset", "axis", NULL},
};

static int get_seed(ctx *c, json_t *o, const char *p, uint64_t *seed)
{
    long long n;
    if (get_int(c, o, p, "seed", 0, LLONG_MAX, OPT, 1, &n))
        return -1;
    *seed = (uint64_t)n;
    return 0;
}

static int parse_generator(ctx *c, json_t *o, const char *p, c5_volume_desc *v)
{
    int g;
    long long dims[3], n;
    char kind[64];
    if (get_enum(c, o, p, "generator", GENERATORS, REQ, 0, &g))
        return -1;
    snprintf(kind, sizeof kind, "generator \"%s\"", GENERATORS[g]);
    if (check_keys(c, o, p, VOLUME_KEYS, GENERATOR_KEYS[g], kind) ||
        get_int3(c, o, p, "dims", 1, C5_VOLUME_MAX_DIM, REQ, 0, dims))
        return -1;
    v->kind = C5_SRC_GENERATOR;
    v->generator = (c5_generator)g;
    for (int i = 0; i < 3; i++)
        v->gen_dims[i] = (size_t)dims[i];
    switch (v->generator) {
    case C5_GEN_MARSCHNER_LOBB:
        return get_num(c, o, p, "f_m", GEN_PARAM, OPT, 6, &v->f_m) ||
               get_num(c, o, p, "alpha", FACTOR, OPT, 0.25, &v->alpha);
    case C5_GEN_BLOBS:
        if (get_int(c, o, p, "count", 1, 256, OPT, 12, &n))
            return -1;
        v->count = (int)n;
        return get_seed(c, o, p, &v->seed);
    case C5_GEN_CLOUD:
        return get_seed(c, o, p, &v->seed);
    case C5_GEN_SPHERE:
        return get_num(c, o, p, "radius", (range){0, 1, 1, 0}, OPT, 0.4, &v->radius) ||
               get_num(c, o, p, "value", BYTE, OPT, 200, &v->value);
    case C5_GEN_CONSTANT:
        return get_num(c, o, p, "value", BYTE, OPT, 0, &v->value);
    case C5_GEN_RAMP:
        if (get_int(c, o, p, "axis", 0, 2, OPT, 0, &n))
            return -1;
        v->axis = (int)n;
        return 0;
    }
    return 0;
}

static int parse_file_volume(ctx *c, json_t *o, const char *p, c5_volume_desc *v)
{
    static const char *const types[] = {"uint8", "uint16", NULL};
    static const char *const endians[] = {"little", "big", NULL};
    const char *file;
    long long dims[3];
    int type, big;
    if (check_keys(c, o, p, VOLUME_KEYS, FILE_KEYS, "file volumes") ||
        get_str(c, o, p, "file", REQ, &file) ||
        get_int3(c, o, p, "dims", 1, C5_VOLUME_MAX_DIM, OPT, 0, dims) ||
        get_enum(c, o, p, "type", types, OPT, -1, &type) ||
        get_enum(c, o, p, "endian", endians, OPT, 0, &big))
        return -1;
    if (json_object_get(o, "dims") && type < 0)
        return fail(c, p, "type", "missing required key (dims is given; give both or neither)");
    if (!json_object_get(o, "dims") && type >= 0)
        return fail(c, p, "dims", "missing required key (type is given; give both or neither)");
    v->kind = C5_SRC_FILE;
    for (int i = 0; i < 3; i++)
        v->raw.dims[i] = (size_t)dims[i];
    v->raw.type = type == 0 ? C5_VOX_U8 : type == 1 ? C5_VOX_U16 : C5_VOX_NONE;
    v->raw.big_endian = big;

    json_t *w = json_object_get(o, "window");
    if (w) {
        if (type == 0)
            return fail(c, p, "window", "only for uint16 volumes, but type is \"uint8\"");
        if (check_nums(c, p, "window", w, 2, COORD, v->window))
            return -1;
        if (!(v->window[0] < v->window[1]))
            return fail(c, p, "window", "must have lo < hi, got [%.15g, %.15g]", v->window[0], v->window[1]);
        v->has_window = 1;
    }

    int n;
    if (file[0] == '/' || !c->base_dir || !*c->base_dir)
        n = snprintf(v->path, sizeof v->path, "%s", file);
    else
        n = snprintf(v->path, sizeof v->path, "%s%s%s", c->base_dir,
                     c->base_dir[strlen(c->base_dir) - 1] == '/' ? "" : "/", file);
    if (n < 0 || (size_t)n >= sizeof v->path)
        return fail(c, p, "file", "path too long (at most %zu bytes once resolved)", sizeof v->path - 1);
    return 0;
}

static int parse_volumes(ctx *c, json_t *root, c5_scene *s)
{
    json_t *arr, *o;
    char p[64];
    if (get_arr(c, root, "", "volumes", OPT, 0, C5_MAX_VOLUMES, &arr))
        return -1;
    for (size_t i = 0; arr && i < json_array_size(arr); i++) {
        c5_volume_desc *v = &s->volumes[i];
        long long off[3];
        if (elem_obj(c, arr, "", "volumes", i, p, sizeof p, &o) ||
            check_keys(c, o, p, VOLUME_KEYS, NULL, NULL))
            return -1;
        int has_file = json_object_get(o, "file") != NULL;
        int has_gen = json_object_get(o, "generator") != NULL;
        if (has_file == has_gen)
            return fail(c, p, NULL, has_file ? "has both \"file\" and \"generator\"; give exactly one"
                                             : "needs either \"file\" or \"generator\"");
        if ((has_file ? parse_file_volume(c, o, p, v) : parse_generator(c, o, p, v)) ||
            get_int3(c, o, p, "offset", 0, C5_VOLUME_MAX_DIM, OPT, 0, off))
            return -1;
        for (int k = 0; k < 3; k++)
            v->offset[k] = (long)off[k];
        s->n_volumes = (int)i + 1;
    }
    return 0;
}

/* TF control points: an array of 1..C5_MAX_TF_POINTS arrays of `cols` numbers, x first. */
static int parse_points(ctx *c, json_t *tf, const char *key, int cols, double pts[][4], int *n)
{
    json_t *arr;
    const char *p = "transfer_function";
    if (get_arr(c, tf, p, key, REQ, 1, C5_MAX_TF_POINTS, &arr))
        return -1;
    for (size_t i = 0; i < json_array_size(arr); i++) {
        char k[64];
        snprintf(k, sizeof k, "%s[%zu]", key, i);
        json_t *e = json_array_get(arr, i);
        if (check_array(c, p, k, e, (size_t)cols, "numbers"))
            return -1;
        for (int j = 0; j < cols; j++) {
            char kj[80];
            snprintf(kj, sizeof kj, "%s[%d]", k, j);
            if (check_num(c, p, kj, json_array_get(e, (size_t)j), j ? UNIT : BYTE, &pts[i][j]))
                return -1;
        }
        if (i > 0 && !(pts[i][0] > pts[i - 1][0]))
            return fail(c, p, k, "x must rise strictly, got %.15g after %.15g", pts[i][0], pts[i - 1][0]);
    }
    *n = (int)json_array_size(arr);
    return 0;
}

static int parse_tf(ctx *c, json_t *root, c5_scene *s)
{
    static const char *const keys[] = {"opacity", "color", "unit_distance", "shading", NULL};
    static const char *const shading_keys[] = {"ambient", "diffuse", "specular", "specular_power", NULL};
    const char *p = "transfer_function", *sp = "transfer_function.shading";
    c5_tf_desc *tf = &s->tf;
    json_t *o, *sh;
    double pts[C5_MAX_TF_POINTS][4];
    tf->ambient = 0.3, tf->diffuse = 0.7, tf->specular = 0.2, tf->specular_power = 20;
    if (get_obj(c, root, "", p, OPT, &o))
        return -1;
    if (!o)
        return s->n_volumes > 0 ? fail(c, p, NULL, "missing required key (the scene has volumes)") : 0;
    if (check_keys(c, o, p, keys, NULL, NULL) || parse_points(c, o, "opacity", 2, pts, &tf->n_opacity))
        return -1;
    for (int i = 0; i < tf->n_opacity; i++)
        memcpy(tf->opacity[i], pts[i], sizeof tf->opacity[i]);
    if (parse_points(c, o, "color", 4, pts, &tf->n_color))
        return -1;
    memcpy(tf->color, pts, (size_t)tf->n_color * sizeof tf->color[0]);
    if (get_num(c, o, p, "unit_distance", LENGTH, OPT, 0, &tf->unit_distance) ||
        get_obj(c, o, p, "shading", OPT, &sh))
        return -1;
    if (sh && (check_keys(c, sh, sp, shading_keys, NULL, NULL) ||
               get_num(c, sh, sp, "ambient", FACTOR, OPT, 0.3, &tf->ambient) ||
               get_num(c, sh, sp, "diffuse", FACTOR, OPT, 0.7, &tf->diffuse) ||
               get_num(c, sh, sp, "specular", FACTOR, OPT, 0.2, &tf->specular) ||
               get_num(c, sh, sp, "specular_power", (range){1, 1e4, 0, 0}, OPT, 20,
                       &tf->specular_power)))
        return -1;
    return 0;
}

static int parse_lights(ctx *c, json_t *root, c5_scene *s)
{
    static const char *const types[] = {"point", "directional", NULL};
    static const char *const keys[] = {"type", "position", "direction", "intensity", "shadows", NULL};
    static const char *const allowed[][5] = {{"type", "position", "intensity", "shadows", NULL},
                                             {"type", "direction", "intensity", "shadows", NULL}};
    json_t *arr, *o;
    char p[64];
    if (get_arr(c, root, "", "lights", OPT, 0, C5_MAX_LIGHTS, &arr))
        return -1;
    for (size_t i = 0; arr && i < json_array_size(arr); i++) {
        c5_light *l = &s->lights[i];
        int t;
        if (elem_obj(c, arr, "", "lights", i, p, sizeof p, &o) || check_keys(c, o, p, keys, NULL, NULL) ||
            get_enum(c, o, p, "type", types, REQ, 0, &t) ||
            check_keys(c, o, p, keys, allowed[t], t ? "directional lights" : "point lights") ||
            (t == 0 ? get_vec(c, o, p, "position", COORD, REQ, v3(0, 0, 0), &l->position)
                    : get_dir(c, o, p, "direction", &l->direction)) ||
            get_num(c, o, p, "intensity", FACTOR, OPT, 1, &l->intensity) ||
            get_bool(c, o, p, "shadows", 0, &l->shadows))
            return -1;
        l->kind = t ? C5_LIGHT_DIRECTIONAL : C5_LIGHT_POINT;
        s->n_lights = (int)i + 1;
    }
    return 0;
}

static int parse_material(ctx *c, json_t *surf, const char *sp, c5_material *m)
{
    static const char *const keys[] = {"color", "ambient", "diffuse", "reflectivity", "transparency",
                                       "ior", NULL};
    json_t *o;
    char p[96];
    snprintf(p, sizeof p, "%s.material", sp);
    *m = (c5_material){v3(0.8, 0.8, 0.8), 0.1, 0.9, 0, 0, 1.5};
    if (get_obj(c, surf, sp, "material", OPT, &o))
        return -1;
    if (!o)
        return 0;
    if (check_keys(c, o, p, keys, NULL, NULL) ||
        get_vec(c, o, p, "color", UNIT, OPT, m->color, &m->color) ||
        get_num(c, o, p, "ambient", FACTOR, OPT, m->ambient, &m->ambient) ||
        get_num(c, o, p, "diffuse", FACTOR, OPT, m->diffuse, &m->diffuse) ||
        get_num(c, o, p, "reflectivity", UNIT, OPT, 0, &m->reflectivity) ||
        get_num(c, o, p, "transparency", UNIT, OPT, 0, &m->transparency) ||
        get_num(c, o, p, "ior", IOR, OPT, 1.5, &m->ior))
        return -1;
    if (m->reflectivity + m->transparency > 1)
        return fail(c, p, "transparency", "reflectivity + transparency must be <= 1, got %.15g + %.15g",
                    m->reflectivity, m->transparency);
    return 0;
}

static int parse_surfaces(ctx *c, json_t *root, c5_scene *s)
{
    static const char *const types[] = {"plane", "rect", "sphere", NULL};
    static const char *const keys[] = {"type", "point", "normal", "corner", "u", "v", "center", "radius",
                                       "material", NULL};
    static const char *const allowed[][6] = {{"type", "point", "normal", "material", NULL},
                                             {"type", "corner", "u", "v", "material", NULL},
                                             {"type", "center", "radius", "material", NULL}};
    static const char *const kinds[] = {"plane surfaces", "rect surfaces", "sphere surfaces"};
    json_t *arr, *o;
    char p[64];
    if (get_arr(c, root, "", "surfaces", OPT, 0, C5_MAX_SURFACES, &arr))
        return -1;
    for (size_t i = 0; arr && i < json_array_size(arr); i++) {
        c5_surface *f = &s->surfaces[i];
        int t;
        if (elem_obj(c, arr, "", "surfaces", i, p, sizeof p, &o) || check_keys(c, o, p, keys, NULL, NULL) ||
            get_enum(c, o, p, "type", types, REQ, 0, &t) || check_keys(c, o, p, keys, allowed[t], kinds[t]))
            return -1;
        f->kind = (c5_surface_kind)t;
        if (f->kind == C5_SURF_PLANE) {
            if (get_vec(c, o, p, "point", COORD, REQ, v3(0, 0, 0), &f->point) ||
                get_dir(c, o, p, "normal", &f->normal))
                return -1;
        } else if (f->kind == C5_SURF_RECT) {
            if (get_vec(c, o, p, "corner", COORD, REQ, v3(0, 0, 0), &f->point) ||
                get_vec(c, o, p, "u", COORD, REQ, v3(0, 0, 0), &f->u) ||
                get_vec(c, o, p, "v", COORD, REQ, v3(0, 0, 0), &f->v))
                return -1;
            if (check_dir_len(c, p, "u", f->u) || check_dir_len(c, p, "v", f->v))
                return -1;
            double lu = v3_len(f->u), lv = v3_len(f->v);
            if (fabs(v3_dot(f->u, f->v)) > 1e-9 * lu * lv)
                return fail(c, p, "v", "must be perpendicular to u, got u = " VFMT ", v = " VFMT,
                            VARGS(f->u), VARGS(f->v));
            f->normal = v3_norm(v3_cross(f->u, f->v));
        } else {
            if (get_vec(c, o, p, "center", COORD, REQ, v3(0, 0, 0), &f->point) ||
                get_num(c, o, p, "radius", LENGTH, REQ, 0, &f->radius))
                return -1;
        }
        if (parse_material(c, o, p, &f->mat))
            return -1;
        s->n_surfaces = (int)i + 1;
    }
    return 0;
}

/* eye, target, up, fov of the camera or of a path key; missing up/fov from `def`. */
static int parse_view(ctx *c, json_t *o, const char *p, const c5_camera *def, c5_camera *cam)
{
    if (get_vec(c, o, p, "eye", COORD, REQ, v3(0, 0, 0), &cam->eye) ||
        get_vec(c, o, p, "target", COORD, REQ, v3(0, 0, 0), &cam->target) ||
        get_vec(c, o, p, "up", COORD, OPT, def->up, &cam->up) ||
        get_num(c, o, p, "fov", (range){0, 180, 1, 1}, OPT, def->fov_deg, &cam->fov_deg))
        return -1;
    c5_vec3 d = v3_sub(cam->target, cam->eye);
    if (!(robust_len(d) >= C5_MIN_LENGTH))
        return fail(c, p, "target", "must be at least %g from eye, got " VFMT " and eye " VFMT, C5_MIN_LENGTH,
                    VARGS(cam->target), VARGS(cam->eye));
    if (check_dir_len(c, p, "up", cam->up))
        return -1;
    if (c5_camera_problem(cam))
        return fail(c, p, "up", "must not be parallel to target - eye " VFMT ", got " VFMT, VARGS(d),
                    VARGS(cam->up));
    return 0;
}

static int parse_camera(ctx *c, json_t *root, c5_scene *s)
{
    static const char *const keys[] = {"eye", "target", "up", "fov", "width", "height", NULL};
    static const char *const path_keys[] = {"frames", "keys", NULL};
    static const char *const key_keys[] = {"eye", "target", "up", "fov", NULL};
    const c5_camera def = {v3(0, 0, 0), v3(0, 0, 0), v3(0, 0, 1), 30};
    json_t *o, *arr, *k;
    long long w, h, frames;
    char p[64];
    if (get_obj(c, root, "", "camera", REQ, &o) || check_keys(c, o, "camera", keys, NULL, NULL) ||
        parse_view(c, o, "camera", &def, &s->camera) ||
        get_int(c, o, "camera", "width", 1, C5_MAX_IMAGE_DIM, OPT, 256, &w) ||
        get_int(c, o, "camera", "height", 1, C5_MAX_IMAGE_DIM, OPT, 256, &h))
        return -1;
    s->render.width = (int)w, s->render.height = (int)h;
    s->path.frames = 1;
    if (get_obj(c, root, "", "camera_path", OPT, &o))
        return -1;
    if (!o)
        return 0;
    if (check_keys(c, o, "camera_path", path_keys, NULL, NULL) ||
        get_int(c, o, "camera_path", "frames", 1, C5_MAX_FRAMES, REQ, 1, &frames) ||
        get_arr(c, o, "camera_path", "keys", REQ, 2, C5_MAX_CAMERA_KEYS, &arr))
        return -1;
    for (size_t i = 0; i < json_array_size(arr); i++)
        if (elem_obj(c, arr, "camera_path", "keys", i, p, sizeof p, &k) ||
            check_keys(c, k, p, key_keys, NULL, NULL) || parse_view(c, k, p, &s->camera, &s->path.keys[i]))
            return -1;
    s->path.frames = (int)frames;
    s->path.n_keys = (int)json_array_size(arr);
    return c5_scene_check_path(s, c->what, c->err);
}

static int parse_render(ctx *c, json_t *root, c5_render_settings *r)
{
    static const char *const keys[] = {"step", "max_opacity", "max_bounces", "min_weight", "background",
                                       "shading", NULL};
    const char *p = "render";
    json_t *o;
    long long bounces;
    /* An absent section reads as an empty one: json_object_get(NULL, key) is NULL. */
    if (get_obj(c, root, "", p, OPT, &o) || (o && check_keys(c, o, p, keys, NULL, NULL)) ||
        get_num(c, o, p, "step", LENGTH, OPT, 0, &r->step) ||
        get_num(c, o, p, "max_opacity", (range){0, 1, 1, 0}, OPT, 0.99, &r->max_opacity) ||
        get_int(c, o, p, "max_bounces", 0, C5_MAX_BOUNCES, OPT, 3, &bounces) ||
        get_num(c, o, p, "min_weight", (range){0, 1, 0, 1}, OPT, 1.0 / 256, &r->min_weight) ||
        get_vec(c, o, p, "background", FACTOR, OPT, v3(0, 0, 0), &r->background) ||
        get_bool(c, o, p, "shading", 1, &r->shading))
        return -1;
    r->max_bounces = (int)bounces;
    return 0;
}

/* The name when the scene gives none: the built-in name, or the file's base name without
 * its extension. */
static void default_name(const char *what, char *name, size_t n)
{
    const char *b = what;
    size_t len;
    if (!strncmp(what, BUILTIN_PREFIX, strlen(BUILTIN_PREFIX))) {
        b += strlen(BUILTIN_PREFIX);
        len = strlen(b);
    } else {
        const char *slash = strrchr(what, '/');
        b = slash ? slash + 1 : what;
        const char *dot = strrchr(b, '.');
        len = dot && dot != b ? (size_t)(dot - b) : strlen(b);
    }
    if (len == 0)
        b = "scene", len = 5;
    if (len >= n)
        len = n - 1;
    memcpy(name, b, len);
    name[len] = 0;
}

static int parse_scene(ctx *c, json_t *root, c5_scene *s)
{
    static const char *const keys[] = {"name", "grid", "volumes", "transfer_function", "lights",
                                       "surfaces", "camera", "camera_path", "render", NULL};
    const char *name;
    if (!json_is_object(root))
        return c5_fail(c->err, "%s: expected a JSON object at the top level, got %s", c->what, kind_of(root));
    if (check_keys(c, root, "", keys, NULL, NULL) || get_str(c, root, "", "name", OPT, &name))
        return -1;
    if (name && strlen(name) >= sizeof s->name)
        return fail(c, "", "name", "too long (at most %zu bytes), got \"%.40s...\"", sizeof s->name - 1,
                    name);
    snprintf(s->source, sizeof s->source, "%s", c->what);
    if (name)
        snprintf(s->name, sizeof s->name, "%s", name);
    else
        default_name(c->what, s->name, sizeof s->name);
    return parse_grid(c, root, &s->grid) || parse_volumes(c, root, s) || parse_tf(c, root, s) ||
                   parse_lights(c, root, s) || parse_surfaces(c, root, s) || parse_camera(c, root, s) ||
                   parse_render(c, root, &s->render)
               ? -1
               : 0;
}

/* ---- API ----------------------------------------------------------------------------- */

int c5_scene_parse(const char *json_text, const char *base_dir, const char *what, c5_scene *out,
                   c5_err *err)
{
    c5_err local;
    ctx c = {what ? what : "scene", base_dir, err ? err : &local};
    json_error_t je;
    if (!json_text)
        return c5_fail(c.err, "%s: no scene text", c.what);
    json_t *root = json_loads(json_text, JSON_REJECT_DUPLICATES, &je);
    if (!root)
        return c5_fail(c.err, "%s: line %d, column %d: %s", c.what, je.line, je.column, je.text);
    c5_scene *s = calloc(1, sizeof *s);
    int rc = s ? parse_scene(&c, root, s) : c5_fail(c.err, "%s: out of memory", c.what);
    if (rc == 0)
        *out = *s;
    free(s);
    json_decref(root);
    return rc;
}

int c5_scene_load_file(const char *path, c5_scene *out, c5_err *err)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return c5_fail(err, "%s: cannot open: %s", path, strerror(errno));
    char *buf = NULL, *dir = NULL;
    size_t len = 0, cap = 0;
    int rc = -1;
    for (;;) {
        if (len == cap) {
            if (cap > MAX_FILE_BYTES) {
                c5_fail(err, "%s: larger than 16 MiB, too big for a scene file", path);
                goto done;
            }
            size_t ncap = cap ? 2 * cap : 65536;
            if (ncap > MAX_FILE_BYTES + 1)
                ncap = MAX_FILE_BYTES + 1;
            char *nb = realloc(buf, ncap + 1);
            if (!nb) {
                c5_fail(err, "%s: out of memory", path);
                goto done;
            }
            buf = nb, cap = ncap;
        }
        size_t n = fread(buf + len, 1, cap - len, f);
        len += n;
        if (n == 0) {
            if (ferror(f)) {
                c5_fail(err, "%s: cannot read: %s", path, strerror(errno));
                goto done;
            }
            break;
        }
    }
    buf[len] = 0;
    if (memchr(buf, 0, len)) {
        c5_fail(err, "%s: contains a NUL byte, not a JSON text file", path);
        goto done;
    }
    const char *slash = strrchr(path, '/');
    if (slash) {
        size_t dl = slash == path ? 1 : (size_t)(slash - path);
        if (!(dir = malloc(dl + 1))) {
            c5_fail(err, "%s: out of memory", path);
            goto done;
        }
        memcpy(dir, path, dl);
        dir[dl] = 0;
    }
    rc = c5_scene_parse(buf, dir, path, out, err);
done:
    fclose(f);
    free(buf);
    free(dir);
    return rc;
}

int c5_scene_frames(const c5_scene *s) { return s->path.n_keys > 0 ? s->path.frames : 1; }

int c5_scene_check_path(const c5_scene *s, const char *what, c5_err *err)
{
    int n = c5_scene_frames(s);
    for (int f = 0; f < n; f++) {
        c5_camera cam = c5_scene_camera_at(s, f);
        const char *problem = c5_camera_problem(&cam);
        if (problem)
            return c5_fail(err, "%s: camera_path: frame %d of %d: %s (eye " VFMT ", target " VFMT ", up " VFMT
                           "); every frame between the keys must frame a view", what, f, n, problem,
                           VARGS(cam.eye), VARGS(cam.target), VARGS(cam.up));
    }
    return 0;
}

/* a*(1-f) + b*f: exactly a at f = 0 and exactly b at f = 1. */
static double lerp(double a, double b, double f) { return a * (1 - f) + b * f; }
static c5_vec3 lerp3(c5_vec3 a, c5_vec3 b, double f)
{
    return v3(lerp(a.x, b.x, f), lerp(a.y, b.y, f), lerp(a.z, b.z, f));
}

c5_camera c5_scene_camera_at(const c5_scene *s, int frame)
{
    const c5_camera_path *p = &s->path;
    if (p->n_keys < 2)
        return p->n_keys == 1 ? p->keys[0] : s->camera;
    if (frame < 0)
        frame = 0;
    if (frame > p->frames - 1)
        frame = p->frames - 1;
    double t = p->frames > 1 ? (double)frame * (p->n_keys - 1) / (p->frames - 1) : 0;
    int i = (int)floor(t);
    if (i > p->n_keys - 2)
        i = p->n_keys - 2;
    double f = t - i;
    const c5_camera *a = &p->keys[i], *b = &p->keys[i + 1];
    c5_camera c;
    c.eye = lerp3(a->eye, b->eye, f);
    c.target = lerp3(a->target, b->target, f);
    c.up = lerp3(a->up, b->up, f);
    c.fov_deg = lerp(a->fov_deg, b->fov_deg, f);
    return c;
}
