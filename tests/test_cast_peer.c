/* The peer benchmark's conventions (cref/cast/cast_peer.h): the README's SplitMix64 and
 * camera test vectors, the transfer-function files and every validation rule, and the two
 * phantoms, checked at grid points where the formula gives exact values and, as a whole,
 * against checksums of render_vtk.py's own output. JSON in this file is written with ' for "
 * (see c5t_json()). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "cast_peer.h"
#include "harness.h"
#include "rng.h"

static const size_t engine_dims[3] = {256, 256, 128};
static const double unit_spacing[3] = {1, 1, 1};

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* ---- SplitMix64 and cameras ----------------------------------------------------------- */

TEST(peer_splitmix64_readme_vectors)
{
    uint64_t s = 1;
    CHECK(c5_splitmix64(&s) == 0x910a2dec89025cc1ull);
    CHECK(c5_splitmix64(&s) == 0xbeeb8da1658eec67ull);
    CHECK(c5_splitmix64(&s) == 0xf893a2eefb32555eull);
    s = 1;
    CHECK_NEAR(c5_uniform(&s), 0.5665615751722809, 1e-16);
    CHECK_NEAR(c5_uniform(&s), 0.7457817572627011, 1e-16);
}

/* README: view directions d = -f of seed 1 and the up vector of view 0. */
TEST(peer_cameras_readme_directions)
{
    static const struct {
        int view;
        double d[3];
    } want[] = {
        {0, {-0.026265, -0.990751, -0.133123}},
        {1, {-0.315297, 0.114950, -0.942006}},
        {2, {0.080425, -0.990508, 0.111471}},
        {23, {0.505778, 0.787968, 0.351134}},
    };
    c5_cast_camera cam[24];
    c5_peer_cameras(engine_dims, unit_spacing, 24, 1, C5_PEER_DISTANCE_HEAVY, C5_PEER_VIEW_ANGLE, cam);
    for (size_t i = 0; i < sizeof want / sizeof want[0]; i++)
        for (int a = 0; a < 3; a++)
            CHECK_NEAR(-cam[want[i].view].f[a], want[i].d[a], 1e-6);
    CHECK_NEAR(cam[0].up[0], -0.003528, 1e-6);
    CHECK_NEAR(cam[0].up[1], -0.133076, 1e-6);
    CHECK_NEAR(cam[0].up[2], 0.991100, 1e-6);
}

/* README: 256x256x128 has C = (127.5, 127.5, 63.5) and R_bs = 191.16681; eye = C + 2 R_bs d. */
TEST(peer_cameras_eye_focal_angle)
{
    c5_cast_camera cam[24];
    const double c[3] = {127.5, 127.5, 63.5}, r_bs = 191.16681;
    c5_peer_cameras(engine_dims, unit_spacing, 24, 1, C5_PEER_DISTANCE_HEAVY, C5_PEER_VIEW_ANGLE, cam);
    for (int a = 0; a < 3; a++) {
        CHECK_INT(cam[0].focal[a] == c[a], 1);
        CHECK_NEAR(cam[0].eye[a], c[a] - 2.0 * r_bs * cam[0].f[a], 1e-4);
    }
    double off[3] = {cam[5].eye[0] - c[0], cam[5].eye[1] - c[1], cam[5].eye[2] - c[2]};
    CHECK_NEAR(sqrt(dot3(off, off)), 2.0 * r_bs, 1e-4);
    CHECK_NEAR(cam[0].tan_half, tan(M_PI / 12.0), 1e-15);
    /* the fitting distance: 1/sin(15 deg) R_bs from the centre */
    c5_peer_cameras(engine_dims, unit_spacing, 1, 1, C5_PEER_DISTANCE_FIT, C5_PEER_VIEW_ANGLE, cam);
    CHECK_NEAR(cam[0].eye[1], c[1] - r_bs / sin(M_PI / 12.0) * cam[0].f[1], 1e-4);
}

/* right, up, f orthonormal and right-handed (right x up = -f is the view towards the eye),
 * also for the views near a pole that take (0,1,0) as up0: 2000 views include some. */
TEST(peer_cameras_orthonormal)
{
    enum { N = 2000 };
    c5_cast_camera *cam = malloc(N * sizeof *cam);
    CHECK(cam);
    c5_peer_cameras(engine_dims, unit_spacing, N, 1, C5_PEER_DISTANCE_HEAVY, C5_PEER_VIEW_ANGLE, cam);
    int polar = 0;
    for (int i = 0; i < N && !c5t_failed_now(); i++) {
        const c5_cast_camera *v = &cam[i];
        polar += fabs(v->f[2]) > 0.99;
        CHECK_NEAR(dot3(v->right, v->right), 1.0, 1e-12);
        CHECK_NEAR(dot3(v->up, v->up), 1.0, 1e-12);
        CHECK_NEAR(dot3(v->f, v->f), 1.0, 1e-12);
        CHECK_NEAR(dot3(v->right, v->up), 0.0, 1e-12);
        CHECK_NEAR(dot3(v->right, v->f), 0.0, 1e-12);
        CHECK_NEAR(dot3(v->up, v->f), 0.0, 1e-12);
        double ru[3] = {v->right[1] * v->up[2] - v->right[2] * v->up[1],
                        v->right[2] * v->up[0] - v->right[0] * v->up[2],
                        v->right[0] * v->up[1] - v->right[1] * v->up[0]};
        CHECK_NEAR(dot3(ru, v->f), -1.0, 1e-12);
    }
    free(cam);
    CHECK(polar > 0);
}

/* ---- transfer functions --------------------------------------------------------------- */


TEST(peer_tf_builtin_default)
{
    c5_tf_desc tf;
    c5_err e;
    CHECK_INT(c5_peer_tf_load("default", 1.0, &tf, &e), 0);
    CHECK_INT(tf.n_opacity, 9);
    CHECK_INT(tf.opacity[8][0] == 255 && tf.opacity[8][1] == 0.6, 1);
    CHECK_INT(tf.opacity[2][0] == 60 && tf.opacity[2][1] == 0.002, 1);
    CHECK_INT(tf.n_color, 6);
    CHECK_INT(tf.color[1][0] == 40 && tf.color[1][1] == 0.5 && tf.color[1][2] == 0.1 && tf.color[1][3] == 0.06, 1);
    CHECK_INT(tf.color[5][0] == 255 && tf.color[5][3] == 1.0, 1);
    CHECK_INT(tf.ambient == 0.45 && tf.diffuse == 0.65 && tf.specular == 0.3 && tf.specular_power == 20, 1);
    CHECK_INT(tf.unit_distance == 1.0, 1);
    /* the unit is in voxels: times the smallest spacing */
    CHECK_INT(c5_peer_tf_load("default", 0.5, &tf, &e), 0);
    CHECK_INT(tf.unit_distance == 0.5, 1);
}

TEST(peer_tf_builtin_ml)
{
    c5_tf_desc tf;
    c5_err e;
    CHECK_INT(c5_peer_tf_load("ml", 1.0, &tf, &e), 0);
    CHECK_INT(tf.n_opacity, 5);
    CHECK_INT(tf.opacity[2][0] == 128 && tf.opacity[2][1] == 0.12, 1);
    CHECK_INT(tf.opacity[3][0] == 152 && tf.opacity[3][1] == 0.0, 1);
    CHECK_INT(tf.n_color, 5);
    CHECK_INT(tf.color[2][0] == 128 && tf.color[2][1] == 0.95, 1);
    CHECK_INT(tf.ambient == 0.4 && tf.diffuse == 0.6 && tf.specular == 0.3 && tf.specular_power == 20, 1);
}

#define PTS "'opacity': [[0, 0], [255, 1]], 'color': [[0, 1, 1, 1]]"

/* Without "shading" or the unit, build_property()'s defaults (VTK's). */
TEST(peer_tf_defaults)
{
    c5_tf_desc tf;
    c5_err e;
    CHECK_INT(c5_peer_tf_parse(c5t_json("{" PTS "}"), "t.json", 2.0, &tf, &e), 0);
    CHECK_INT(tf.n_opacity, 2);
    CHECK_INT(tf.n_color, 1);
    CHECK_INT(tf.unit_distance == 2.0, 1);
    CHECK_INT(tf.ambient == 0.3 && tf.diffuse == 0.7 && tf.specular == 0.2 && tf.specular_power == 10, 1);
    CHECK_INT(c5_peer_tf_parse(c5t_json("{" PTS ", 'opacity_unit_distance_voxels': 2.5, 'shading': {'diffuse': 0.5},"
                                 " 'interpolation': 'linear', 'scalar_range': [0, 255], 'background': [0, 0, 0],"
                                 " 'name': 'n', 'description': 'd'}"),
                               "t.json", 2.0, &tf, &e),
              0);
    CHECK_INT(tf.unit_distance == 5.0, 1);
    CHECK_INT(tf.ambient == 0.3 && tf.diffuse == 0.5 && tf.specular == 0.2 && tf.specular_power == 10, 1);
}

/* Each refused file gives -1, leaves *out alone, and names the file and the key. */
TEST(peer_tf_validation)
{
    static const struct {
        const char *json, *where, *problem;
    } bad[] = {
        {"{'opacity': [[0, 0], [60, 0.1], [40, 0.2]], 'color': [[0, 1, 1, 1]]}", "opacity[2]",
         "x must rise strictly (40 after 60)"},
        {"{'opacity': [[0, 0], [0, 0.1]], 'color': [[0, 1, 1, 1]]}", "opacity[1]", "x must rise strictly"},
        {"{'opacity': [[0, 0], [255, 1.5]], 'color': [[0, 1, 1, 1]]}", "opacity[1]",
         "alpha must be in [0, 1], got 1.5"},
        {"{'opacity': [[-1, 0]], 'color': [[0, 1, 1, 1]]}", "opacity[0]", "x must be in [0, 255], got -1"},
        {"{'opacity': [[0, 0]], 'color': [[300, 1, 1, 1]]}", "color[0]", "x must be in [0, 255], got 300"},
        {"{'opacity': [[0, 0]], 'color': [[0, 1, -0.5, 1]]}", "color[0]", "g must be in [0, 1]"},
        {"{'opacity': [[0, 0]], 'color': [[0, 1, 1]]}", "color[0]", "must be an array of 4 numbers"},
        {"{'opacity': [[0, '0']], 'color': [[0, 1, 1, 1]]}", "opacity[0]", "alpha must be a number"},
        {"{'opacity': [], 'color': [[0, 1, 1, 1]]}", "opacity", "array of 1 to 64 points"},
        {"{'color': [[0, 1, 1, 1]]}", "opacity", "missing"},
        {"{'opacity': [[0, 0]]}", "color", "missing"},
        {"{" PTS ", 'opacty': 1}", "opacty", "unknown key"},
        {"{" PTS ", 'shading': {'gloss': 1}}", "shading", "unknown key \"gloss\""},
        {"{" PTS ", 'shading': {'ambient': -0.1}}", "shading.ambient", "must be >= 0"},
        {"{" PTS ", 'shading': [1]}", "shading", "must be an object"},
        {"{" PTS ", 'interpolation': 'nearest'}", "interpolation", "\"nearest\" is not supported"},
        {"{" PTS ", 'interpolation': 'cubic'}", "interpolation", "must be \"linear\""},
        {"{" PTS ", 'background': [1, 1, 1]}", "background", "must be [0, 0, 0]"},
        {"{" PTS ", 'scalar_range': [0, 4095]}", "scalar_range", "must be [0, 255]"},
        {"{" PTS ", 'opacity_unit_distance_voxels': 0}", "opacity_unit_distance_voxels", "must be > 0"},
        {"{" PTS ", 'opacity_unit_distance_voxels': -1}", "opacity_unit_distance_voxels", "must be >= 0"},
        {"{" PTS ", 'name': 5}", "name", "must be a string"},
        {"{" PTS ",\n 'color': [[0, 1, 1, 1]]}", "line 2", "duplicate"},
        {"{\n  'opacity': [[0, 0]],\n}", "line 3, column", ""},
        {"{" PTS ", 'opacity_unit_distance_voxels': 1e999}", "line 1, column", ""},
        {"[1, 2]", "top level", "object"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        c5_tf_desc tf;
        c5_err e = {{0}};
        memset(&tf, 0x5a, sizeof tf);
        int rc = c5_peer_tf_parse(c5t_json(bad[i].json), "t.json", 1.0, &tf, &e);
        CHECK_MSG(rc == -1, "case %zu accepted: %s", i, bad[i].json);
        CHECK_MSG(!strncmp(e.msg, "t.json: ", 8), "case %zu: \"%s\" does not name the file", i, e.msg);
        CHECK_HAS(e.msg, bad[i].where);
        CHECK_HAS(e.msg, bad[i].problem);
        CHECK_MSG(tf.n_opacity == 0x5a5a5a5a, "case %zu changed the output", i);
    }
    c5_tf_desc tf;
    c5_err e;
    CHECK_INT(c5_peer_tf_parse(c5t_json("{" PTS "}"), "t.json", 0.0, &tf, &e), -1);
    CHECK_HAS(e.msg, "spacing");
}

/* C5_MAX_TF_POINTS points are fine, one more is refused. */
TEST(peer_tf_point_limit)
{
    char json[4096];
    for (int extra = 0; extra < 2; extra++) {
        size_t len = (size_t)snprintf(json, sizeof json, "{\"color\": [[0, 1, 1, 1]], \"opacity\": [");
        for (int i = 0; i < C5_MAX_TF_POINTS + extra; i++)
            len += (size_t)snprintf(json + len, sizeof json - len, "%s[%d, 0.5]", i ? ", " : "", i);
        snprintf(json + len, sizeof json - len, "]}");
        c5_tf_desc tf;
        c5_err e;
        CHECK_INT(c5_peer_tf_parse(json, "t.json", 1.0, &tf, &e), extra ? -1 : 0);
        if (extra)
            CHECK_HAS(e.msg, "opacity: must be an array of 1 to 64 points");
        else
            CHECK_INT(tf.n_opacity, C5_MAX_TF_POINTS);
    }
}

TEST(peer_tf_load_file)
{
    const char *p = c5t_path(0, "tf_mine.json");
    FILE *f = fopen(p, "w");
    CHECK(f);
    fputs(c5t_json("{'opacity': [[10, 0], [20, 0.25]], 'color': [[0, 0.5, 0.5, 0.5]], 'shading': {'specular_power': 40}}"), f);
    fclose(f);
    c5_tf_desc tf;
    c5_err e;
    CHECK_INT(c5_peer_tf_load(p, 1.0, &tf, &e), 0);
    CHECK_INT(tf.n_opacity, 2);
    CHECK_INT(tf.opacity[1][1] == 0.25 && tf.specular_power == 40, 1);
    /* a file's messages carry its path */
    f = fopen(p, "w");
    CHECK(f);
    fputs(c5t_json("{'opacity': [[10, 0], [20, 2]], 'color': [[0, 0.5, 0.5, 0.5]]}"), f);
    fclose(f);
    CHECK_INT(c5_peer_tf_load(p, 1.0, &tf, &e), -1);
    CHECK_HAS(e.msg, p);
    CHECK_HAS(e.msg, "opacity[1]: alpha");
    /* not a built-in name and no such file */
    const char *missing = c5t_path(1, "nope.json");
    CHECK_INT(c5_peer_tf_load(missing, 1.0, &tf, &e), -1);
    CHECK_HAS(e.msg, missing);
    CHECK_HAS(e.msg, "No such file or directory");
    CHECK_INT(c5_peer_tf_load("tf_default", 1.0, &tf, &e), -1);
}

/* ---- phantoms ------------------------------------------------------------------------- */

static uint8_t at(const uint8_t *v, size_t n, size_t i, size_t j, size_t k) { return v[(k * n + j) * n + i]; }

TEST(peer_phantom_parse)
{
    c5_phantom p = C5_PHANTOM_SHELL;
    CHECK_INT(c5_phantom_parse("ml", &p), 0);
    CHECK_INT(p, C5_PHANTOM_ML);
    CHECK_INT(c5_phantom_parse("shell", &p), 0);
    CHECK_INT(p, C5_PHANTOM_SHELL);
    CHECK_INT(c5_phantom_parse("ML", &p), -1);
    CHECK_INT(c5_phantom_parse("", &p), -1);
    CHECK_INT(c5_phantom_parse(NULL, &p), -1);
}

TEST(peer_phantom_sizes_refused)
{
    CHECK(c5_phantom_make(C5_PHANTOM_ML, 0) == NULL);
    CHECK(c5_phantom_make(C5_PHANTOM_SHELL, 1) == NULL);
    CHECK(c5_phantom_make(C5_PHANTOM_ML, (size_t)1 << 22) == NULL); /* n^3 would overflow */
    CHECK(c5_phantom_make((c5_phantom)7, 8) == NULL);
    uint8_t *v = c5_phantom_make(C5_PHANTOM_SHELL, 2); /* the 8 corners, all outside: 0 */
    CHECK(v);
    for (int i = 0; i < 8; i++)
        CHECK_INT(v[i], 0);
    free(v);
}

/* n = 65 puts grid points at exactly 0, +-0.5 and 0.75 (t_i = -1 + i/32). */
TEST(peer_phantom_shell_exact_points)
{
    const size_t n = 65;
    uint8_t *v = c5_phantom_make(C5_PHANTOM_SHELL, n);
    CHECK(v);
    CHECK_INT(at(v, n, 32, 32, 32), 240); /* r = 0: the core */
    CHECK_INT(at(v, n, 48, 32, 32), 180); /* the +x blob's centre; r = 0.5: no core, no shell */
    CHECK_INT(at(v, n, 32, 48, 32), 180); /* +y */
    CHECK_INT(at(v, n, 32, 32, 48), 180); /* +z */
    CHECK_INT(at(v, n, 16, 32, 32), 0);   /* -x: no blob there */
    CHECK_INT(at(v, n, 56, 32, 32), 130); /* r = 0.75: mid-shell, 0.25 from the blob */
    CHECK_INT(at(v, n, 32, 8, 32), 130);  /* r = 0.75 along -y */
    CHECK_INT(at(v, n, 0, 0, 0), 0);      /* a corner, r = sqrt 3 */
    free(v);
}

/* n = 256 has no grid point at 0: the 2x2x2 centre voxels are at r = 0.0068, deep in the core. */
TEST(peer_phantom_shell_256_core)
{
    const size_t n = 256;
    uint8_t *v = c5_phantom_make(C5_PHANTOM_SHELL, n);
    CHECK(v);
    for (size_t k = 120; k < 136; k++)
        for (size_t j = 120; j < 136; j++)
            for (size_t i = 120; i < 136; i++)
                CHECK_INT(at(v, n, i, j, k), 240);
    free(v);
}

/* rho = (1 - sin(pi z/2) + 0.25 (1 + cos(12 pi cos(pi r/2)))) / 2.5: on the top slice (z = 1)
 * the first two terms cancel, so rho = 0.1 (1 + cos ...) is in [0, 0.2]: voxels 0..51; on the
 * bottom (z = -1) rho is in [0.8, 1]: 204..255. At r = 0 the cosine is cos(12 pi) = 1. */
TEST(peer_phantom_ml_exact_points)
{
    const size_t n = 65;
    uint8_t *v = c5_phantom_make(C5_PHANTOM_ML, n);
    CHECK(v);
    CHECK_INT(at(v, n, 32, 32, 32), 153); /* z = 0: rho = (1 + 0.5) / 2.5 = 0.6 */
    CHECK_INT(at(v, n, 32, 32, n - 1), 51);
    CHECK_INT(at(v, n, 32, 32, 0), 255);
    int lo = 255, hi = 0;
    for (size_t ji = 0; ji < n * n; ji++) {
        uint8_t top = v[(n - 1) * n * n + ji], bottom = v[ji];
        CHECK(top <= 51 && bottom >= 204);
        lo = top < lo ? top : lo, hi = bottom > hi ? bottom : hi;
    }
    CHECK_INT(lo, 0); /* the ring where the cosine is -1 is on the grid's slices too */
    CHECK_INT(hi, 255);
    free(v);
}

TEST(peer_phantom_deterministic)
{
    const size_t n = 48;
    for (int kind = 0; kind < 2; kind++) {
        uint8_t *a = c5_phantom_make((c5_phantom)kind, n), *b = c5_phantom_make((c5_phantom)kind, n);
        CHECK(a && b);
        int same = !memcmp(a, b, n * n * n);
        free(a);
        free(b);
        CHECK(same);
    }
}

/* The whole volume against render_vtk.py's own: CRC-32 of synthetic_volume(n, kind).tobytes()
 * as computed by numpy 1.24.2 with Debian's /usr/bin/python3:
 *   import importlib.util, zlib
 *   s = importlib.util.spec_from_file_location("rv", "../shared/bench/peer-vtk/render_vtk.py")
 *   rv = importlib.util.module_from_spec(s); s.loader.exec_module(rv)
 *   print("%08x" % zlib.crc32(rv.synthetic_volume(n, kind).tobytes()))
 * These are external reference figures: a change of one voxel changes them. ml at n = 256
 * (numpy's 159d6a4c) is left out: libm's cosf differs from numpy's float32 cosine by an ulp
 * for some arguments, which moves 64 of its voxels by one (cast_peer.c). */
TEST(peer_phantom_matches_numpy)
{
    static const struct {
        c5_phantom kind;
        size_t n;
        unsigned long crc;
    } ref[] = {
        {C5_PHANTOM_ML, 64, 0x23eb6957ul},
        {C5_PHANTOM_SHELL, 64, 0x15fb2052ul},
        {C5_PHANTOM_SHELL, 256, 0x87bbcec9ul},
    };
    for (size_t i = 0; i < sizeof ref / sizeof ref[0]; i++) {
        size_t n = ref[i].n;
        uint8_t *v = c5_phantom_make(ref[i].kind, n);
        CHECK(v);
        unsigned long crc = crc32(crc32(0L, Z_NULL, 0), v, (uInt)(n * n * n));
        free(v);
        CHECK_MSG(crc == ref[i].crc, "%s n=%zu: crc32 %08lx, numpy's %08lx",
                  ref[i].kind == C5_PHANTOM_ML ? "ml" : "shell",
                  n, crc, ref[i].crc);
    }
}
