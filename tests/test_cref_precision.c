/* cref's own stability: the stiff and extreme scenes of the stability
 * suite (tests/stab_scenes.c) rendered by cref in double (c5_cref_render) and in long
 * double (c5_cref_render_long, the same sources compiled with c5_real = long double,
 * cref/real.h). The difference is cref's own rounding as the display sees it; each case
 * checks it against a bound far below one 8-bit display step (1/255 = 0.0039) and so far
 * below the board model's error bounds (docs/stability.md), which is what makes cref a
 * trustworthy yardstick for the model.
 *
 * Besides the bounds each case checks: both images finite; the same sample and ray counts
 * in both precisions (no decision flipped); the long double render the same bits on 1 and
 * 3 threads.
 *
 * C5_STAB_VERBOSE=1 build/tests/unit precision prints, per case, max |double - long| and
 * the rmse (display units, over every channel of every pixel), where the largest
 * difference is, and the board model's error against cref on the same scene with the ratio
 * of the two (docs/stability.md, "Is cref itself stable?"). */
#include <float.h>
#include <stdlib.h>
#include <string.h>

#include "board.h"
#include "cref.h"
#include "harness.h"
#include "metrics.h"
#include "stab_scenes.h"

/* The bound of a case on max |double - long double| and on the rmse of that difference. */
typedef struct {
    double max_abs, rmse;
} prec_bound;

/* The bounds. A display step is 1/255 = 0.0039; the board model's bounds in
 * docs/stability.md are 6.2e-5 (the background's one rounding) to 1.0 (the stiff jump's
 * flipped pixel). cref's double against its long double, on the sums before the float
 * rounding, measures 4e-17 to 5.5e-12: double's 1.1e-16 relative rounding times the
 * arithmetic behind each pixel, with no sample, hit, refraction or early termination
 * decided differently (the counts are equal). Each bound is 100x the measured value,
 * rounded up to a power of ten: it catches cref losing two orders of precision, or one
 * decision flipping (a sample in or out: 1e-3 and more), and every bound is at most 1e-9,
 * 4 million times below a display step and 60,000 times below the model's tightest bound.
 * The float images must be equal or neighbouring floats in every value (PREC_MAX_ULPS). */
#define P(max, rmse) ((prec_bound){max, rmse})
static const int PREC_MAX_ULPS = 1;

static int prec_finite(const c5_image *im, const char *who)
{
    for (size_t i = 0; i < (size_t)im->w * im->h * 3; i++)
        if (!isfinite(im->rgb[i]) || im->rgb[i] < 0)
            return stab_fail("%s: pixel %zu channel %zu is %g", who, i / 3, i % 3, (double)im->rgb[i]);
    return 0;
}

/* max |a - b| and the rmse over n values; *at: where the largest is. */
static void prec_diff(const double *a, const double *b, size_t n, double *max_abs, double *rmse, size_t *at)
{
    double sum = 0;
    *max_abs = 0;
    *at = 0;
    for (size_t i = 0; i < n; i++) {
        double e = fabs(a[i] - b[i]);
        sum += e * e;
        if (e > *max_abs) {
            *max_abs = e;
            *at = i;
        }
    }
    *rmse = sqrt(sum / (double)n);
}

static uint64_t prec_rays(const c5_cref_stats *st)
{
    uint64_t n = 0;
    for (int t = 0; t < C5_RAY_TYPES; t++)
        n += st->rays[t];
    return n;
}

static uint64_t absdiff(uint64_t a, uint64_t b) { return a > b ? a - b : b - a; }

/* Float steps between two non-negative finite floats. */
static uint32_t ulps(float a, float b)
{
    uint32_t ia, ib;
    memcpy(&ia, &a, 4);
    memcpy(&ib, &b, 4);
    return ia > ib ? ia - ib : ib - ia;
}

/* Renders the scene in both precisions and checks the bound on the unrounded sums (raw),
 * the float images (PREC_MAX_ULPS) and the counts (equal); when verbose also the model,
 * for the ratio. */
static double prec_last_max; /* the last prec_run's max |double - long| on the sums */

static int prec_run(const char *label, const stab_scene *sc, prec_bound b)
{
    c5_image d = {0}, l = {0}, l3 = {0}, m = {0};
    c5_cref_stats sd, sl, sl3;
    c5_image_diff fl;
    c5_err err;
    c5_cref_opts o1 = {.threads = 1}, o2 = {.threads = 2}, o3 = {.threads = 3};
    size_t n = (size_t)sc->s.render.width * sc->s.render.height * 3;
    double *rd = calloc(n, sizeof *rd), *rl = calloc(n, sizeof *rl);
    int rc = -1;
    if (!rd || !rl) {
        stab_fail("out of memory");
        goto done;
    }
    if (c5_cref_render_raw(&sc->s, &sc->sv, 0, &o2, 0, &d, rd, &sd, &err) != 0 ||
        c5_cref_render_raw(&sc->s, &sc->sv, 0, &o1, 1, &l, rl, &sl, &err) != 0 ||
        c5_cref_render_long(&sc->s, &sc->sv, 0, &o3, &l3, &sl3, &err) != 0) {
        stab_fail("cref: %s", err.msg);
        goto done;
    }
    if (prec_finite(&d, "double") || prec_finite(&l, "long double"))
        goto done;
    if (memcmp(l.rgb, l3.rgb, sizeof(float) * n) != 0 || sl.samples != sl3.samples) {
        stab_fail("long double: 1 and 3 threads differ");
        goto done;
    }
    if (c5_image_compare(&d, &l, &fl, &err) != 0) {
        stab_fail("compare: %s", err.msg);
        goto done;
    }
    double max_raw, rmse_raw;
    size_t at;
    prec_diff(rd, rl, n, &max_raw, &rmse_raw, &at);
    prec_last_max = max_raw;
    uint32_t max_ulps = 0;
    for (size_t i = 0; i < n; i++)
        if (ulps(d.rgb[i], l.rgb[i]) > max_ulps)
            max_ulps = ulps(d.rgb[i], l.rgb[i]);
    size_t px = (at / 3) % (size_t)d.w, py = (at / 3) / (size_t)d.w;
    uint64_t dsam = absdiff(sd.samples, sl.samples), dray = absdiff(prec_rays(&sd), prec_rays(&sl));
    if (getenv("C5_STAB_VERBOSE")) {
        c5_board_stats bs;
        c5_image_diff dm = {0};
        c5_board_opts bo = {.cells = {1, 1, 1}};
        int have_model = c5_board_render(&sc->s, &sc->sv, 0, &bo, &m, &bs, &err) == 0 &&
                         c5_image_compare(&d, &m, &dm, &err) == 0;
        printf("    %-34s raw max %.3g rmse %.3g (%.3g / %.3g); float max %.3g rmse %.3g, %llu differ;"
               " largest (%zu,%zu) ch %zu = %.17g; samples %+lld rays %+lld",
               label, max_raw, rmse_raw, b.max_abs, b.rmse, fl.max_abs_err, fl.rmse,
               (unsigned long long)fl.differing, px, py, at % 3, rd[at],
               (long long)sl.samples - (long long)sd.samples,
               (long long)prec_rays(&sl) - (long long)prec_rays(&sd));
        if (have_model)
            printf("; model max %.3g rmse %.3g, ratio %.2g / %.2g\n", dm.max_abs_err, dm.rmse,
                   dm.max_abs_err > 0 ? max_raw / dm.max_abs_err : 0, dm.rmse > 0 ? rmse_raw / dm.rmse : 0);
        else
            printf("; model: %s\n", err.msg);
    }
    /* The bound holds for both: the sums, and the floats the yardstick hands out. */
    if (!(max_raw <= b.max_abs) || !(rmse_raw <= b.rmse) || !(fl.max_abs_err <= b.max_abs) || !(fl.rmse <= b.rmse)) {
        stab_fail("%s: double vs long double: sums max %.4g rmse %.4g, floats max %.4g rmse %.4g (bounds %.4g, "
                  "%.4g); largest at pixel (%zu,%zu) channel %zu: %.17g vs %.17g",
                  label, max_raw, rmse_raw, fl.max_abs_err, fl.rmse, b.max_abs, b.rmse, px, py, at % 3, rd[at],
                  rl[at]);
        goto done;
    }
    if (max_ulps > (uint32_t)PREC_MAX_ULPS) {
        stab_fail("%s: float images %u float steps apart (at most %d)", label, max_ulps, PREC_MAX_ULPS);
        goto done;
    }
    if (dsam != 0 || dray != 0) { /* a decision flipped: a sample in or out, a hit, a TIR, a cut */
        stab_fail("%s: samples %llu vs %llu, rays %llu vs %llu", label, (unsigned long long)sd.samples,
                  (unsigned long long)sl.samples, (unsigned long long)prec_rays(&sd),
                  (unsigned long long)prec_rays(&sl));
        goto done;
    }
    rc = 0;
done:
    free(rd);
    free(rl);
    c5_image_free(&d);
    c5_image_free(&l);
    c5_image_free(&l3);
    c5_image_free(&m);
    return rc;
}

#define PREC(label, sc, b) CHECK_MSG(prec_run(label, sc, b) == 0, "%s", stab_msg)
#define PREC_BUILD(call) CHECK_MSG((call) == 0, "%s", stab_msg)

/* A case with one scene and one camera. */
#define PREC_CASE(name, builder, label, bound) \
    TEST(name)                                 \
    {                                          \
        static stab_scene sc;                  \
        PREC_BUILD(builder(&sc));              \
        PREC(label, &sc, bound);               \
        c5_supervol_free(&sc.sv);              \
    }

/* Each bound: 100x measured, up to a power of ten (above); the measured max / rmse in the
 * comment, and docs/stability.md's table. The largest are the cases with the most arithmetic
 * between the eye and the sample: */
/* 3.8e-14 / 1.3e-15: no sample lands within 1e-14 of the jump or a face in either precision */
PREC_CASE(precision_stiff_opacity_jump, stab_scene_stiff_jump, "stiff opacity jump", P(1e-11, 1e-12))
/* 2.3e-13 / 5.0e-15: 1 - (1 - 0.5)^50 is 1 - 9e-16 in double; the table's pow in long double */
PREC_CASE(precision_stiff_extinction, stab_scene_stiff_extinction, "stiff extinction", P(1e-10, 1e-12))
/* 4.1e-13 / 1.3e-14: the gradient 255 a voxel times position rounding */
PREC_CASE(precision_step_edge, stab_scene_step_edge, "step edge 0|255", P(1e-10, 1e-11))
/* 1.4e-14 / 9.7e-16: trilinear and gradient sums; shading's pow(N.H, 20) */
PREC_CASE(precision_marschner_lobb, stab_scene_marschner_lobb, "marschner-lobb 41^3", P(1e-11, 1e-13))
/* 2.1e-13 / 8.0e-15: refraction and TIR: the same rays reflect in both (counts equal) */
PREC_CASE(precision_total_internal_reflection, stab_scene_tir, "total internal reflection", P(1e-10, 1e-12))
/* 2.9e-15 / 3.4e-16: 15 bounces, every reflection exact on axis-aligned mirrors up to rounding */
PREC_CASE(precision_parallel_mirrors, stab_scene_mirrors, "parallel mirrors", P(1e-12, 1e-13))
/* 5.5e-12 / 3.4e-13, the largest: positions 4000 voxels from the eye, 4000 x 1.1e-16 = 4e-13
 * voxel, times the blobs' slope */
PREC_CASE(precision_fov_half_degree, stab_scene_fov_narrow, "fov 0.5 from 4000 voxels", P(1e-9, 1e-10))
/* 8.2e-16 / 5.2e-17 */
PREC_CASE(precision_fov_170_degrees, stab_scene_fov_wide, "fov 170", P(1e-13, 1e-14))
/* 5.6e-17 / 7.5e-18 */
PREC_CASE(precision_volume_1x1x1, stab_scene_volume_1, "1^3 volume", P(1e-14, 1e-15))
/* 4.2e-17 / 3.9e-18 */
PREC_CASE(precision_volume_1x1xN, stab_scene_volume_rod, "1x1x64 volume", P(1e-14, 1e-15))
/* 1.3e-14 / 6.0e-16 */
PREC_CASE(precision_volume_512x512x1, stab_scene_volume_slab, "512x512x1 volume", P(1e-11, 1e-13))
/* 1.8e-15 / 7.7e-16 on values up to 15 */
PREC_CASE(precision_saturation_ray_colour, stab_scene_sat_ray_colour, "saturated ray colour", P(1e-12, 1e-13))
/* 1.2e-14 / 7.8e-16 on values up to 13.5 */
PREC_CASE(precision_saturation_shadow_radiance, stab_scene_sat_shadow, "saturated shadow-ray radiance",
          P(1e-11, 1e-13))
/* 6.8e-13 / 1.7e-13 on values up to ~2000 (a double step at 1024..2048 is 2.3e-13): relative 5e-16 */
PREC_CASE(precision_saturation_frame_acc, stab_scene_sat_frame_acc, "frame_acc near 2000", P(1e-10, 1e-10))

/* Worst of the 7 cameras 2.6e-14 / 2.2e-15. */
TEST(precision_axis_rays_on_cell_faces_edges_corners)
{
    static stab_scene sc;
    PREC_BUILD(stab_scene_axis_rays(&sc));
    for (int i = 0; i < STAB_N_AXIS_CAMS; i++) {
        const stab_cam *c = &stab_axis_cams[i];
        stab_camera(&sc, c->eye, c->target, c->up);
        PREC(c->label, &sc, P(1e-11, 1e-12));
    }
    c5_supervol_free(&sc.sv);
}

/* Worst of the 4 heights 9.3e-13 / 2.0e-13 (eye 1e-4 above the floor); in the plane the
 * middle row is exactly parallel (no hit) in both precisions. */
TEST(precision_grazing_plane)
{
    static stab_scene sc;
    PREC_BUILD(stab_scene_grazing(&sc));
    for (int i = 0; i < STAB_N_GRAZING; i++) {
        char label[64];
        snprintf(label, sizeof label, "grazing, eye at z = %g", stab_grazing_heights[i]);
        stab_grazing_camera(&sc, i);
        PREC(label, &sc, P(1e-10, 1e-12));
    }
    c5_supervol_free(&sc.sv);
}

/* Worst of the 6 eyes 1.7e-14 / 9.0e-16. */
TEST(precision_camera_inside_and_on_cell_boundaries)
{
    static stab_scene sc;
    PREC_BUILD(stab_scene_camera_inside(&sc));
    for (int i = 0; i < STAB_N_INSIDE_CAMS; i++) {
        const stab_cam *c = &stab_inside_cams[i];
        stab_camera(&sc, c->eye, c->target, c->up);
        PREC(c->label, &sc, P(1e-11, 1e-13));
    }
    c5_supervol_free(&sc.sv);
}

/* Worst of the 4 1.7e-14 / 2.4e-15 (alpha 1 at 255: the sample's position decides nothing,
 * the table entry 254..255 interpolation does). */
TEST(precision_all_zero_and_all_255_volumes)
{
    static stab_scene sc;
    for (int i = 0; i < STAB_N_CONSTANT; i++) {
        PREC_BUILD(stab_scene_constant(&sc, i));
        PREC(stab_constant_cases[i].label, &sc, P(1e-11, 1e-12));
        c5_supervol_free(&sc.sv);
    }
}

/* The long double build is wider than double (x87: 64-bit mantissa) and does compute
 * differently: were it double again, every difference above would be 0 and prove nothing. */
TEST(precision_long_double_build_is_wider)
{
    CHECK(LDBL_MANT_DIG > DBL_MANT_DIG);
    static stab_scene sc;
    PREC_BUILD(stab_scene_marschner_lobb(&sc));
    PREC("marschner-lobb 41^3", &sc, P(1e-11, 1e-13));
    CHECK_MSG(prec_last_max > 0, "double and long double cref give the same sums: is the long build long?");
    c5_supervol_free(&sc.sv);
}
