/* cref against hand-computed values, analytic truth and its own invariants. */
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "builtin_scenes.h"
#include "cref.h"
#include "generators.h"
#include "geometry.h"
#include "harness.h"
#include "tf.h"

/* Parses a scene, builds its super volume and renders frame 0. */
static int render_json(const char *json, int threads, const c5_field *field, c5_image *img, c5_cref_stats *st)
{
    static c5_scene s;
    c5_err err;
    c5_supervol sv;
    if (c5_scene_parse(json, NULL, "test", &s, &err) != 0 || c5_supervol_build(&s, &sv, &err) != 0) {
        printf("    %s\n", err.msg);
        return -1;
    }
    c5_cref_opts o = {.threads = threads, .field = field};
    int rc = c5_cref_render(&s, &sv, 0, &o, img, st, &err);
    if (rc)
        printf("    %s\n", err.msg);
    c5_supervol_free(&sv);
    return rc;
}

static c5_supervol grid_of(size_t nx, size_t ny, size_t nz, const uint8_t *vals)
{
    c5_supervol sv = {.dims = {nx, ny, nz}, .origin = v3(0, 0, 0), .spacing = v3(1, 1, 1), .v = (uint8_t *)vals};
    return sv;
}

TEST(cref_trilinear_hand_values)
{
    /* v(i,j,k) = 10 i + 20 j + 40 k on a 2x2x2 grid: trilinear reproduces it exactly. */
    uint8_t v[8];
    for (int k = 0; k < 2; k++)
        for (int j = 0; j < 2; j++)
            for (int i = 0; i < 2; i++)
                v[(k * 2 + j) * 2 + i] = (uint8_t)(10 * i + 20 * j + 40 * k);
    c5_supervol sv = grid_of(2, 2, 2, v);
    double val;
    c5_supervol_sample(&sv, v3(0.5, 0.5, 0.5), &val, NULL); /* voxel (0,0,0)'s centre */
    CHECK_NEAR(val, 0, 1e-12);
    c5_supervol_sample(&sv, v3(1, 1, 1), &val, NULL); /* between all eight centres */
    CHECK_NEAR(val, (10 + 20 + 40) / 2.0, 1e-12);
    c5_supervol_sample(&sv, v3(1.25, 0.5, 1.5), &val, NULL); /* x: 3/4 of the way, k = 1 */
    CHECK_NEAR(val, 0.75 * 10 + 40, 1e-12);
    c5_supervol_sample(&sv, v3(0.1, 0.5, 0.5), &val, NULL); /* outer half voxel: clamped */
    CHECK_NEAR(val, 0, 1e-12);
    c5_supervol_sample(&sv, v3(1.9, 1.9, 1.9), &val, NULL);
    CHECK_NEAR(val, 70, 1e-12);
}

TEST(cref_gradient_central_differences)
{
    /* A ramp of 10 per voxel along x, spacing 2: interior gradient 10/2 = 5 per world unit;
     * at the edge voxel the clamped central difference gives half of it. */
    uint8_t v[4] = {0, 10, 20, 30};
    c5_supervol sv = grid_of(4, 1, 1, v);
    sv.spacing = v3(2, 1, 1);
    double val;
    c5_vec3 g;
    c5_supervol_sample(&sv, v3(3, 0.5, 0.5), &val, &g); /* voxel 1's centre */
    CHECK_NEAR(val, 10, 1e-12);
    CHECK_NEAR(g.x, 5, 1e-12);
    CHECK_NEAR(g.y, 0, 1e-12);
    c5_supervol_sample(&sv, v3(1, 0.5, 0.5), &val, &g); /* voxel 0: (10 - 0) / (2 * 2) */
    CHECK_NEAR(g.x, 2.5, 1e-12);
    c5_supervol_sample(&sv, v3(4, 0.5, 0.5), &val, &g); /* halfway between voxels 1 and 2 */
    CHECK_NEAR(g.x, 5, 1e-12);
    CHECK_NEAR(val, 15, 1e-12);
}

TEST(cref_tf_table_and_opacity_correction)
{
    c5_tf_desc tf = {0};
    tf.n_opacity = 2;
    tf.opacity[0][0] = 0, tf.opacity[0][1] = 0;
    tf.opacity[1][0] = 255, tf.opacity[1][1] = 1;
    tf.n_color = 2;
    tf.color[0][0] = 0, tf.color[0][1] = 1;
    tf.color[1][0] = 255, tf.color[1][3] = 1;
    c5_tf_table t;
    c5_tf_build(&tf, 0.5, 1.0, &t);
    CHECK_NEAR(t.rgba[51][3], 1 - sqrt(1 - 51 / 255.0), 1e-15);
    CHECK_NEAR(t.rgba[255][3], 1, 0);
    CHECK_NEAR(t.rgba[0][3], 0, 0);
    CHECK_NEAR(t.rgba[102][0], 1 - 102 / 255.0, 1e-15);
    double rgba[4];
    c5_tf_lookup(&t, 51.25, rgba); /* linear between entries 51 and 52 */
    CHECK_NEAR(rgba[3], 0.75 * t.rgba[51][3] + 0.25 * t.rgba[52][3], 1e-15);
    c5_tf_lookup(&t, 255, rgba);
    CHECK_NEAR(rgba[3], 1, 1e-15);
    /* Clamped beyond the control points. */
    double pts[2][2] = {{100, 0.2}, {200, 0.6}};
    CHECK_NEAR(c5_tf_eval(&pts[0][0], 2, 2, 1, 50), 0.2, 0);
    CHECK_NEAR(c5_tf_eval(&pts[0][0], 2, 2, 1, 250), 0.6, 0);
    CHECK_NEAR(c5_tf_eval(&pts[0][0], 2, 2, 1, 125), 0.3, 1e-15);
}

/* One ray along +x through a 10x1x1 slab of constant value: samples at x = 0..9. */
static const char *slab_scene =
    "{\"volumes\": [{\"generator\": \"constant\", \"dims\": [10, 1, 1], \"value\": 255}],"
    " \"transfer_function\": {\"opacity\": [[0, %g], [255, %g]], \"color\": [[0, 0.5, 0.25, 1], [255, 0.5, 0.25, 1]]},"
    " \"camera\": {\"eye\": [-5, 0.5, 0.5], \"target\": [0, 0.5, 0.5], \"fov\": 1, \"width\": 1, \"height\": 1},"
    " \"render\": {\"step\": 1, \"max_opacity\": %g, \"background\": [0.2, 0.2, 0.2]}}";

TEST(cref_compositing_hand_values)
{
    char json[1024];
    double a = 0.1;
    snprintf(json, sizeof json, slab_scene, a, a, 1.0);
    c5_image img;
    c5_cref_stats st;
    CHECK(render_json(json, 1, NULL, &img, &st) == 0);
    double T10 = pow(1 - a, 10);
    /* sum_{n<10} c a (1-a)^n = c (1 - (1-a)^10), then the background through T10. */
    CHECK_NEAR(img.rgb[0], 0.5 * (1 - T10) + 0.2 * T10, 1e-6);
    CHECK_NEAR(img.rgb[1], 0.25 * (1 - T10) + 0.2 * T10, 1e-6);
    CHECK_NEAR(img.rgb[2], 1.0 * (1 - T10) + 0.2 * T10, 1e-6);
    CHECK_INT(st.samples, 10);
    CHECK_INT(st.ends[C5_END_LEFT], 1);
    c5_image_free(&img);
}

TEST(cref_early_termination_hand_values)
{
    char json[1024];
    double a = 0.3;
    snprintf(json, sizeof json, slab_scene, a, a, 0.8);
    c5_image img;
    c5_cref_stats st;
    CHECK(render_json(json, 1, NULL, &img, &st) == 0);
    /* 1 - 0.7^n >= 0.8 first at n = 5 (0.7^5 = 0.168): five samples, no background. */
    CHECK_INT(st.samples, 5);
    CHECK_INT(st.ends[C5_END_OPACITY], 1);
    CHECK_NEAR(img.rgb[0], 0.5 * (1 - pow(0.7, 5)), 1e-6);
    c5_image_free(&img);
}

TEST(cref_ray_surface_intersections)
{
    c5_surface pl = {.kind = C5_SURF_PLANE, .point = v3(0, 0, 2), .normal = v3(0, 0, 1)};
    double t;
    CHECK(c5_ray_surface(&pl, v3(0, 0, 0), v3_norm(v3(1, 0, 1)), 1e-9, INFINITY, &t));
    CHECK_NEAR(t, 2 * sqrt(2), 1e-12);
    CHECK(!c5_ray_surface(&pl, v3(0, 0, 0), v3(1, 0, 0), 1e-9, INFINITY, &t)); /* parallel */
    CHECK(!c5_ray_surface(&pl, v3(0, 0, 0), v3(0, 0, -1), 1e-9, INFINITY, &t)); /* behind */
    CHECK(!c5_ray_surface(&pl, v3(0, 0, 0), v3(0, 0, 1), 1e-9, 1.5, &t));      /* beyond tmax */

    c5_surface re = {.kind = C5_SURF_RECT, .point = v3(0, 0, 2), .u = v3(1, 0, 0), .v = v3(0, 2, 0),
                     .normal = v3(0, 0, 1)};
    CHECK(c5_ray_surface(&re, v3(0.5, 1.5, 0), v3(0, 0, 1), 1e-9, INFINITY, &t));
    CHECK_NEAR(t, 2, 1e-12);
    CHECK(!c5_ray_surface(&re, v3(1.5, 1.5, 0), v3(0, 0, 1), 1e-9, INFINITY, &t));
    CHECK(!c5_ray_surface(&re, v3(0.5, 2.5, 0), v3(0, 0, 1), 1e-9, INFINITY, &t));

    c5_surface sp = {.kind = C5_SURF_SPHERE, .point = v3(5, 0, 0), .radius = 1};
    CHECK(c5_ray_surface(&sp, v3(0, 0, 0), v3(1, 0, 0), 1e-9, INFINITY, &t));
    CHECK_NEAR(t, 4, 1e-12);
    CHECK(c5_ray_surface(&sp, v3(5, 0, 0), v3(1, 0, 0), 1e-9, INFINITY, &t)); /* from inside */
    CHECK_NEAR(t, 1, 1e-12);
    CHECK(!c5_ray_surface(&sp, v3(0, 1.5, 0), v3(1, 0, 0), 1e-9, INFINITY, &t));
    CHECK(c5_ray_surface(&sp, v3(0, 1, 0), v3(1, 0, 0), 1e-9, INFINITY, &t)); /* tangent */
    CHECK_NEAR(t, 5, 1e-12);

    double t0, t1;
    CHECK(c5_ray_box(v3(-1, 0.5, 0.5), v3(1, 0, 0), v3(0, 0, 0), v3(2, 1, 1), &t0, &t1));
    CHECK_NEAR(t0, 1, 0);
    CHECK_NEAR(t1, 3, 0);
    CHECK(!c5_ray_box(v3(-1, 1.5, 0.5), v3(1, 0, 0), v3(0, 0, 0), v3(2, 1, 1), &t0, &t1));
}

TEST(cref_reflect_refract_directions)
{
    c5_vec3 n = v3(0, 0, 1), d = v3_norm(v3(1, 0, -1));
    c5_vec3 r = c5_reflect(d, n);
    CHECK_NEAR(r.x, d.x, 1e-15);
    CHECK_NEAR(r.z, -d.z, 1e-15);
    /* Snell: sin(theta_t) = sin(theta_i) / 1.5 entering glass at 45 degrees. */
    c5_vec3 t;
    CHECK(c5_refract(d, n, 1 / 1.5, &t));
    CHECK_NEAR(v3_len(t), 1, 1e-12);
    CHECK_NEAR(t.x, sin(M_PI / 4) / 1.5, 1e-12);
    CHECK(t.z < 0);
    /* Normal incidence passes straight. */
    CHECK(c5_refract(v3(0, 0, -1), n, 1 / 1.5, &t));
    CHECK_NEAR(t.z, -1, 1e-12);
    /* Leaving glass at 45 degrees: past the critical angle asin(1/1.5) = 41.8 degrees. */
    CHECK(!c5_refract(d, n, 1.5, &t));
    /* Just below the critical angle it still refracts, grazing. */
    double th = asin(1 / 1.5) - 1e-6;
    CHECK(c5_refract(v3(sin(th), 0, -cos(th)), n, 1.5, &t));
    CHECK(fabs(t.z) < 1e-2);
}

/* Whatever eta is, refraction gives a finite unit direction or total internal reflection
 * (0): an eta whose square overflows once made a NaN direction that cref then marched
 * forever. */
TEST(cref_refract_never_returns_nan)
{
    const double etas[] = {1e16, 1e300, 1e-300, INFINITY, 1.5};
    const c5_vec3 n = v3(0, 0, 1), ds[] = {v3(0, 0, -1), v3_norm(v3(1, 0, -1)), v3_norm(v3(1e-9, 0, -1))};
    for (size_t e = 0; e < sizeof etas / sizeof etas[0]; e++)
        for (size_t i = 0; i < sizeof ds / sizeof ds[0]; i++) {
            c5_vec3 t = v3(0, 0, 0);
            if (!c5_refract(ds[i], n, etas[e], &t))
                continue;
            CHECK_MSG(isfinite(t.x) && isfinite(t.y) && isfinite(t.z) && fabs(v3_len(t) - 1) < 1e-12,
                      "eta %g, d %zu: direction [%g, %g, %g]", etas[e], i, t.x, t.y, t.z);
        }
}

/* Runs fn(arg) in a child process and reports whether it ended within `seconds`: a test
 * of "never hangs" fails instead of hanging the suite. */
static int ends_within(int (*fn)(void *), void *arg, unsigned seconds)
{
    fflush(stdout);
    pid_t pid = fork();
    if (pid < 0)
        return 0;
    if (pid == 0) {
        alarm(seconds);
        _exit(fn(arg) == 0 ? 0 : 1);
    }
    int status;
    if (waitpid(pid, &status, 0) != pid)
        return 0;
    return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

/* One pixel of the scene with its first spacing set to 1e-30 behind the parser's back: a
 * double sample counter k starting near 3e31 never grew (k + 1 == k), and march never ended. */
static int render_tiny_spacing(void *unused)
{
    (void)unused;
    static c5_scene s;
    c5_err err;
    c5_supervol sv;
    const char *json = "{\"volumes\": [{\"generator\": \"constant\", \"dims\": [8, 8, 8], \"value\": 0}],"
                       " \"transfer_function\": {\"opacity\": [[0, 0]], \"color\": [[0, 1, 1, 1]]},"
                       " \"camera\": {\"eye\": [0, 4, 40], \"target\": [0, 4, 4], \"up\": [0, 1, 0],"
                       " \"width\": 1, \"height\": 1}}";
    if (c5_scene_parse(json, NULL, "t", &s, &err) != 0 || c5_supervol_build(&s, &sv, &err) != 0)
        return -1;
    sv.spacing.x = 1e-30;
    c5_image img;
    c5_cref_stats st;
    c5_cref_opts o = {.threads = 1, .field = NULL};
    int rc = c5_cref_render(&s, &sv, 0, &o, &img, &st, &err);
    int finite = rc == 0 && isfinite(img.rgb[0]) && isfinite(img.rgb[1]) && isfinite(img.rgb[2]);
    c5_image_free(&img);
    c5_supervol_free(&sv);
    return finite ? 0 : -1;
}

TEST(cref_march_ends_on_a_tiny_spacing)
{
    CHECK_MSG(ends_within(render_tiny_spacing, NULL, 60), "the render did not end within 60 s (or failed)");
}

/* c5_supervol_build refuses a grid whose diagonal is more than C5_MAX_RAY_SAMPLES steps,
 * naming the key that sets the step. */
TEST(supervol_refuses_unbounded_samples_per_ray)
{
    static c5_scene s;
    c5_err err;
    c5_supervol sv;
    const char *base = "{\"volumes\": [{\"generator\": \"constant\", \"dims\": [8, 8, 8]}],"
                       " \"transfer_function\": {\"opacity\": [[0, 0]], \"color\": [[0, 1, 1, 1]]},"
                       " \"camera\": {\"eye\": [4, 4, 40], \"target\": [4, 4, 4], \"up\": [0, 1, 0]}%s}";
    const struct {
        const char *extra, *key;
    } cases[] = {{", \"render\": {\"step\": 1e-6}", "t: render.step: a ray across the grid"},
                 {", \"grid\": {\"spacing\": [1e-6, 1, 1]}", "t: grid.spacing: a ray across the grid"}};
    char json[1024];
    for (size_t i = 0; i < 2; i++) {
        snprintf(json, sizeof json, base, cases[i].extra);
        CHECK_MSG(c5_scene_parse(json, NULL, "t", &s, &err) == 0, "%s", err.msg);
        CHECK_INT(c5_supervol_build(&s, &sv, &err), -1);
        CHECK_HAS(err.msg, cases[i].key);
        CHECK_HAS(err.msg, "at most 1048576");
    }
    /* At the limit's side that is allowed: step 1e-4 across a diagonal of 13.9 is 1.4e5. */
    snprintf(json, sizeof json, base, ", \"render\": {\"step\": 1e-4}");
    CHECK_MSG(c5_scene_parse(json, NULL, "t", &s, &err) == 0, "%s", err.msg);
    CHECK_MSG(c5_supervol_build(&s, &sv, &err) == 0, "%s", err.msg);
    c5_supervol_free(&sv);
}

/* Every factor at the top of its range (docs/scene-format.md, "Valid ranges"), 8 shadowing
 * lights, refraction at both ends of the ior range, two facing mirrors and 16 bounces: every
 * pixel is finite. The ranges exist for this; a light of 1e300 once wrote +Inf. */
TEST(cref_range_ends_give_finite_pixels)
{
    char lights[2048] = "", json[8192];
    for (int i = 0; i < 8; i++) {
        size_t n = strlen(lights);
        snprintf(lights + n, sizeof lights - n, "%s{\"type\": \"point\", \"position\": [%d, 9, 30],"
                 " \"intensity\": 1000, \"shadows\": true}", i ? ", " : "", 2 * i - 7);
    }
    snprintf(json, sizeof json,
             "{\"volumes\": [{\"generator\": \"ramp\", \"dims\": [8, 8, 8]}],"
             " \"transfer_function\": {\"opacity\": [[0, 0], [255, 0.2]], \"color\": [[0, 1, 1, 1]],"
             "  \"shading\": {\"ambient\": 1000, \"diffuse\": 1000, \"specular\": 1000, \"specular_power\": 1}},"
             " \"lights\": [%s],"
             " \"surfaces\": ["
             "  {\"type\": \"sphere\", \"center\": [2, 4, 12], \"radius\": 2, \"material\": {\"transparency\": 1,"
             "   \"ior\": 1000}},"
             "  {\"type\": \"sphere\", \"center\": [6, 4, 12], \"radius\": 2, \"material\": {\"transparency\": 0.5,"
             "   \"reflectivity\": 0.5, \"ior\": 0.001}},"
             "  {\"type\": \"plane\", \"point\": [-20, 0, 0], \"normal\": [1, 0, 0], \"material\": {\"reflectivity\": 1}},"
             "  {\"type\": \"plane\", \"point\": [28, 0, 0], \"normal\": [-1, 0, 0], \"material\": {\"reflectivity\": 1}},"
             "  {\"type\": \"plane\", \"point\": [0, 0, -5], \"normal\": [0, 0, 1], \"material\": {\"ambient\": 1000,"
             "   \"diffuse\": 1000}}],"
             " \"camera\": {\"eye\": [4, -30, 20], \"target\": [4, 4, 4], \"width\": 24, \"height\": 24, \"fov\": 60},"
             " \"render\": {\"max_bounces\": 16, \"min_weight\": 0, \"background\": [1000, 1000, 1000]}}",
             lights);
    c5_image img;
    c5_cref_stats st;
    CHECK_INT(render_json(json, 2, NULL, &img, &st), 0);
    double peak = 0;
    for (int i = 0; i < img.w * img.h * 3; i++) {
        CHECK_MSG(isfinite(img.rgb[i]), "value %d is %g", i, (double)img.rgb[i]);
        peak = fmax(peak, img.rgb[i]);
    }
    printf("    largest channel %g; %llu refracted rays\n", peak, (unsigned long long)st.rays[C5_RAY_REFRACT]);
    CHECK(st.rays[C5_RAY_REFRACT] > 0);
    c5_image_free(&img);
}

/* A white plane z = 0 under a light straight above, seen from the side, with a sphere
 * between the plane's centre and the light. */
static const char *shadow_scene =
    "{\"lights\": [{\"type\": \"directional\", \"direction\": [0, 0, -1], \"shadows\": %s}],"
    " \"surfaces\": [{\"type\": \"plane\", \"point\": [0, 0, 0], \"normal\": [0, 0, 1],"
    "   \"material\": {\"color\": [1, 1, 1], \"ambient\": 0.2, \"diffuse\": 0.8}},"
    "  {\"type\": \"sphere\", \"center\": [0, 0, 5], \"radius\": 1, \"material\": {\"transparency\": %g}}],"
    " \"camera\": {\"eye\": [10, 0, 10], \"target\": [0, 0, 0], \"fov\": 1, \"width\": 1, \"height\": 1}}";

TEST(cref_shadow_rays_hand_values)
{
    char json[1024];
    c5_image img;
    c5_cref_stats st;
    snprintf(json, sizeof json, shadow_scene, "false", 0.0); /* light ignores the sphere */
    CHECK(render_json(json, 1, NULL, &img, &st) == 0);
    CHECK_NEAR(img.rgb[0], 0.2 + 0.8, 1e-7) /* float image */;
    CHECK_INT(st.rays[C5_RAY_SHADOW], 0);
    c5_image_free(&img);

    snprintf(json, sizeof json, shadow_scene, "true", 0.0); /* opaque sphere: ambient only */
    CHECK(render_json(json, 1, NULL, &img, &st) == 0);
    CHECK_NEAR(img.rgb[1], 0.2, 1e-7) /* float image */;
    CHECK_INT(st.rays[C5_RAY_SHADOW], 1);
    CHECK_INT(st.ends[C5_END_BLOCKED], 1);
    c5_image_free(&img);

    snprintf(json, sizeof json, shadow_scene, "true", 0.5); /* two crossings at 0.5 each */
    CHECK(render_json(json, 1, NULL, &img, &st) == 0);
    CHECK_NEAR(img.rgb[2], 0.2 + 0.8 * 0.25, 1e-7) /* float image */;
    CHECK_INT(st.ends[C5_END_LIGHT], 1);
    c5_image_free(&img);
}

static const char *mirror_scene =
    "{\"surfaces\": [{\"type\": \"plane\", \"point\": [0, 0, 0], \"normal\": [0, 0, 1],"
    "   \"material\": {\"color\": [1, 0, 0], \"ambient\": 0.2, \"diffuse\": 0, \"reflectivity\": 0.5}}],"
    " \"camera\": {\"eye\": [10, 0, 10], \"target\": [0, 0, 0], \"fov\": 1, \"width\": 1, \"height\": 1},"
    " \"render\": {\"max_bounces\": %d, \"background\": [0, 0.6, 0]}}";

TEST(cref_mirror_and_bounce_limit_hand_values)
{
    char json[1024];
    c5_image img;
    c5_cref_stats st;
    snprintf(json, sizeof json, mirror_scene, 1);
    CHECK(render_json(json, 1, NULL, &img, &st) == 0);
    CHECK_NEAR(img.rgb[0], 0.5 * 0.2, 1e-7) /* float image */; /* diffuse share 0.5 times ambient */
    CHECK_NEAR(img.rgb[1], 0.5 * 0.6, 1e-7) /* float image */; /* the mirror shows the background */
    CHECK_INT(st.rays[C5_RAY_REFLECT], 1);
    c5_image_free(&img);

    snprintf(json, sizeof json, mirror_scene, 0);
    CHECK(render_json(json, 1, NULL, &img, &st) == 0);
    CHECK_NEAR(img.rgb[1], 0, 0);
    CHECK_INT(st.rays[C5_RAY_REFLECT], 0);
    CHECK_INT(st.ends[C5_CUT_BOUNCES], 1);
    c5_image_free(&img);
}

TEST(cref_two_parallel_mirrors_end_at_bounce_limit)
{
    const char *json =
        "{\"surfaces\": [{\"type\": \"plane\", \"point\": [0, 0, 0], \"normal\": [0, 0, 1],"
        "   \"material\": {\"reflectivity\": 1}},"
        "  {\"type\": \"plane\", \"point\": [0, 0, 10], \"normal\": [0, 0, -1], \"material\": {\"reflectivity\": 1}}],"
        " \"camera\": {\"eye\": [0, 0, 5], \"target\": [1, 0, 4], \"fov\": 10, \"width\": 4, \"height\": 4},"
        " \"render\": {\"max_bounces\": 16}}";
    c5_image img;
    c5_cref_stats st;
    CHECK(render_json(json, 1, NULL, &img, &st) == 0);
    CHECK_INT(st.rays[C5_RAY_REFLECT], 16 * 16);
    CHECK_INT(st.ends[C5_CUT_BOUNCES], 16);
    c5_image_free(&img);
}

static int render_builtin(const char *name, int w, int h, int threads, c5_image *img, c5_cref_stats *st)
{
    static c5_scene s;
    c5_err err;
    c5_supervol sv;
    if (c5_scene_parse(c5_builtin_scene_json(name), NULL, name, &s, &err) != 0 ||
        c5_supervol_build(&s, &sv, &err) != 0) {
        printf("    %s\n", err.msg);
        return -1;
    }
    s.render.width = w;
    s.render.height = h;
    c5_cref_opts o = {.threads = threads, .field = NULL};
    int rc = c5_cref_render(&s, &sv, 0, &o, img, st, &err);
    c5_supervol_free(&sv);
    return rc;
}

TEST(cref_same_bits_for_1_2_7_threads)
{
    c5_image a, b;
    c5_cref_stats sa, sb;
    CHECK(render_builtin("brain_mirrors", 40, 36, 1, &a, &sa) == 0);
    int threads[] = {2, 7};
    for (int i = 0; i < 2; i++) {
        CHECK(render_builtin("brain_mirrors", 40, 36, threads[i], &b, &sb) == 0);
        int same = memcmp(a.rgb, b.rgb, sizeof(float) * 3 * 40 * 36) == 0;
        int same_stats = sa.samples == sb.samples && !memcmp(sa.rays, sb.rays, sizeof sa.rays) &&
                         !memcmp(sa.ends, sb.ends, sizeof sa.ends);
        c5_image_free(&b);
        CHECK_MSG(same && same_stats, "%d threads differ from 1 thread", threads[i]);
    }
    c5_image_free(&a);
}

TEST(cref_every_ray_ends_once_in_builtin_scenes)
{
    for (const c5_builtin_scene *b = c5_builtin_scenes; b->name; b++) {
        c5_image img;
        c5_cref_stats st;
        CHECK(render_builtin(b->name, 24, 24, 0, &img, &st) == 0);
        uint64_t made = 0, ended = 0;
        for (int t = 0; t < C5_RAY_TYPES; t++)
            made += st.rays[t];
        for (int e = C5_END_OPACITY; e <= C5_END_BLOCKED; e++)
            ended += st.ends[e];
        int finite = 1;
        for (int i = 0; i < 24 * 24 * 3; i++)
            finite &= isfinite(img.rgb[i]) && img.rgb[i] >= 0;
        c5_image_free(&img);
        CHECK_MSG(made == ended, "%s: %llu rays made, %llu ended", b->name, (unsigned long long)made,
                  (unsigned long long)ended);
        CHECK_MSG(st.rays[C5_RAY_EYE] == 24 * 24, "%s: eye rays", b->name);
        CHECK_MSG(finite, "%s: non-finite or negative pixel", b->name);
    }
}

/* ---- Marschner-Lobb against its analytic truth ------------------------------------ */

typedef struct {
    const c5_supervol *sv;
    double f_m, alpha;
} ml_ctx;

static void ml_field(const c5_field *f, c5_vec3 p, double *value, c5_vec3 *grad)
{
    const ml_ctx *m = f->ctx;
    c5_supervol_marschner_lobb(m->sv, m->f_m, m->alpha, p, value, grad);
}

static const char *ml_scene =
    "{\"volumes\": [{\"generator\": \"marschner_lobb\", \"dims\": [96, 96, 96], \"f_m\": 6, \"alpha\": 0.25}],"
    " \"transfer_function\": {\"opacity\": [[0, 0], [104, 0], [128, 0.12], [152, 0], [255, 0]],"
    "   \"color\": [[0, 0.2, 0.3, 0.9], [110, 0.2, 0.5, 1.0], [128, 0.95, 0.95, 0.95], [146, 1, 0.55, 0.15],"
    "   [255, 1, 0.3, 0.1]]},"
    " \"camera\": {\"eye\": [230, -130, 170], \"target\": [48, 48, 48], \"fov\": 34, \"width\": 40, \"height\": 40},"
    " \"render\": {\"step\": %g, \"max_opacity\": 1}}";

static double rmse(const c5_image *a, const c5_image *b)
{
    double s = 0;
    size_t n = (size_t)a->w * a->h * 3;
    for (size_t i = 0; i < n; i++)
        s += (a->rgb[i] - b->rgb[i]) * (double)(a->rgb[i] - b->rgb[i]);
    return sqrt(s / n);
}

TEST(cref_marschner_lobb_error_falls_with_step)
{
    static c5_scene s;
    c5_err err;
    c5_supervol sv;
    char json[2048];
    snprintf(json, sizeof json, ml_scene, 1.0 / 16);
    CHECK(c5_scene_parse(json, NULL, "ml", &s, &err) == 0);
    CHECK(c5_supervol_build(&s, &sv, &err) == 0);
    ml_ctx m = {&sv, 6, 0.25};
    c5_field field = {ml_field, &m};
    c5_cref_opts truth_opts = {.threads = 0, .field = &field};
    c5_image truth, img;
    c5_cref_stats st;
    CHECK(c5_cref_render(&s, &sv, 0, &truth_opts, &truth, &st, &err) == 0);
    double steps[] = {4, 2, 1, 0.5}, prev = INFINITY;
    for (int i = 0; i < 4; i++) {
        s.render.step = steps[i];
        c5_cref_opts o = {.threads = 0, .field = NULL};
        CHECK(c5_cref_render(&s, &sv, 0, &o, &img, &st, &err) == 0);
        double e = rmse(&img, &truth);
        c5_image_free(&img);
        printf("    step %g voxel: RMSE against analytic truth %.5f\n", steps[i], e);
        CHECK_MSG(e < prev, "error did not fall: step %g gives %g, the step before %g", steps[i], e, prev);
        prev = e;
    }
    c5_image_free(&truth);
    c5_supervol_free(&sv);
}

TEST(cref_degenerate_path_camera_is_an_error)
{
    /* Opposite up vectors blend to zero half way along the path. The parser refuses that
     * path at 3 frames (test scene_path_degenerate_between_keys); at 2 it is valid, and a
     * caller that sets 3 frames itself past c5_scene_check_path still gets an error. */
    const char *json = "{\"camera\": {\"eye\": [10, 0, 0], \"target\": [0, 0, 0]},"
                       " \"camera_path\": {\"frames\": 2, \"keys\": [{\"eye\": [10, 0, 0], \"target\": [0, 0, 0],"
                       " \"up\": [0, 0, 1]}, {\"eye\": [10, 0, 0], \"target\": [0, 0, 0], \"up\": [0, 0, -1]}]}}";
    static c5_scene s;
    c5_err err;
    c5_supervol sv;
    CHECK(c5_scene_parse(json, NULL, "t", &s, &err) == 0);
    s.path.frames = 3;
    CHECK(c5_scene_check_path(&s, "t", &err) != 0);
    CHECK(c5_supervol_build(&s, &sv, &err) == 0);
    c5_image img;
    c5_cref_stats st;
    c5_cref_opts o = {.threads = 1, .field = NULL};
    CHECK(c5_cref_render(&s, &sv, 0, &o, &img, &st, &err) == 0);
    c5_image_free(&img);
    CHECK(c5_cref_render(&s, &sv, 1, &o, &img, &st, &err) != 0);
    CHECK_HAS(err.msg, "frame 1: camera: up is zero or parallel");
}

/* The in-frame progress hook (c5_cref_opts.progress) sees every tile once, numbered 0..n-1
 * in the order they are taken, one call at a time, and the image does not depend on it. */
typedef struct {
    int calls, tiles, seen[64], in_order;
} tile_log;

static void log_tile(void *ctx, int done, int tiles)
{
    tile_log *l = ctx;
    l->in_order &= done == l->calls;
    l->tiles = tiles;
    if (done >= 0 && done < 64)
        l->seen[done]++;
    l->calls++;
}

TEST(cref_progress_hook_sees_every_tile)
{
    static c5_scene s;
    c5_err err;
    c5_supervol sv;
    CHECK(c5_scene_parse(c5_builtin_scene_json("default"), NULL, "default", &s, &err) == 0);
    s.render.width = 40, s.render.height = 24;
    CHECK(c5_supervol_build(&s, &sv, &err) == 0);
    c5_image a = {0}, b = {0};
    c5_cref_stats st;
    tile_log l = {.in_order = 1};
    c5_cref_opts plain = {.threads = 3}, hooked = {.threads = 3, .progress = log_tile, .progress_ctx = &l};
    CHECK(c5_cref_render(&s, &sv, 0, &plain, &a, &st, &err) == 0);
    CHECK(c5_cref_render(&s, &sv, 0, &hooked, &b, &st, &err) == 0);
    CHECK(!memcmp(a.rgb, b.rgb, sizeof(float) * 3 * 40 * 24));
    CHECK(l.tiles > 1 && l.tiles <= 64 && l.calls == l.tiles && l.in_order);
    int once = 1;
    for (int t = 0; t < l.tiles; t++)
        once &= l.seen[t] == 1;
    CHECK(once);
    c5_image_free(&a);
    c5_image_free(&b);
    c5_supervol_free(&sv);
}
