/* Numerical stability suite: the board model against cref on scenes built
 * to break fixed-point arithmetic: stiff transfer functions, the Marschner-Lobb signal, rays
 * along axes, cell faces, edges and corners, grazing hits, total internal reflection, two
 * parallel mirrors, cameras inside the volume and on cell boundaries, extreme fields of view,
 * degenerate and extreme volume shapes and contents, and every fixed-point accumulator
 * driven to its saturation limit.
 *
 * Every case goes through stab_run, which checks the three properties of the suite:
 *  1. both images finite (and >= 0);
 *  2. max |model - cref| and the rmse within the case's named bound (docs/stability.md
 *     lists each bound, why, and what it measured);
 *  3. the same bits again: cref on 1 thread and on 3, the model twice with the same split
 *     and once with a single cell (the image does not depend on the split,
 *     docs/board-model.md).
 * Scenes beyond the packet formats are refused by the model by design: those cases check
 * the refusal and its message (stab_refused) and that cref still renders them.
 *
 * C5_STAB_VERBOSE=1 build/tests/unit stability prints every measured error. */
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "board.h"
#include "harness.h"
#include "metrics.h"
#include "regs.h"
#include "sample_pipe.h"
#include "stab_scenes.h"

/* ---- the harness of the suite ----------------------------------------------------------- */

/* The error bound of a case: all three must hold. */
typedef struct {
    double max_err; /* max |model - cref| over every channel of every pixel */
    double rmse;    /* over every channel (docs/compare.md) */
    double far;     /* fraction of channel values off by more than 4 display steps (4/255) */
} stab_bound;

typedef struct {
    stab_bound bound;
    int cells[3];     /* the model's split; 0: one cell */
    double ref_clamp; /* > 0: cref clamped to this first (the model's format saturates there by design) */
    uint32_t tree;    /* > 0: a Cell Tree of this many slots is built and checked */
} stab_case;

typedef struct {
    c5_cref_stats cs;
    c5_board_stats bs;
    c5_image_diff d;
    c5_image ref, img; /* kept only when stab_run is asked to (keep) */
} stab_out;

static int finite_image(const c5_image *im, const char *who)
{
    for (size_t i = 0; i < (size_t)im->w * im->h * 3; i++)
        if (!isfinite(im->rgb[i]) || im->rgb[i] < 0)
            return stab_fail("%s: pixel %zu channel %zu is %g", who, i / 3, i % 3, (double)im->rgb[i]);
    return 0;
}

static int same_bits(const c5_image *a, const c5_image *b)
{
    return a->w == b->w && a->h == b->h && !memcmp(a->rgb, b->rgb, sizeof(float) * 3 * (size_t)a->w * a->h);
}

static int cref_once(const stab_scene *sc, int threads, c5_image *img, c5_cref_stats *st)
{
    c5_err err;
    c5_cref_opts o = {.threads = threads, .field = NULL};
    if (c5_cref_render(&sc->s, &sc->sv, 0, &o, img, st, &err) != 0)
        return stab_fail("cref: %s", err.msg);
    return finite_image(img, "cref");
}

static int board_once(const stab_scene *sc, const int cells[3], uint32_t tree, c5_image *img, c5_board_stats *st)
{
    c5_err err;
    c5_board_opts o = {.cells = {cells[0], cells[1], cells[2]}};
    c5_ctree *t = NULL;
    if (tree) {
        if (!(t = malloc(sizeof *t)))
            return stab_fail("out of memory");
        c5_ctree_init(t, tree);
        o.tree = t;
    }
    int rc = c5_board_render(&sc->s, &sc->sv, 0, &o, img, st, &err);
    free(t);
    if (rc != 0)
        return stab_fail("model: %s", err.msg);
    return finite_image(img, "model");
}

/* Renders the scene with both renderers and checks the suite's three properties. 0, or -1
 * with the reason in stab_msg. keep: leave both images in out (free with stab_free). */
static int stab_run(const char *label, const stab_scene *sc, const stab_case *c, stab_out *out, int keep)
{
    static const int one[3] = {0, 0, 0}; /* the fewest cells: one up to 256 voxels a side */
    c5_image ref = {0}, ref3 = {0}, img = {0}, img2 = {0}, img1 = {0}, cmp = {0};
    c5_cref_stats cs3;
    c5_board_stats bs2, bs1;
    int rc = -1;
    memset(out, 0, sizeof *out);
    if (cref_once(sc, 1, &ref, &out->cs) || cref_once(sc, 3, &ref3, &cs3) ||
        board_once(sc, c->cells, c->tree, &img, &out->bs) || board_once(sc, c->cells, c->tree, &img2, &bs2) ||
        board_once(sc, one, 0, &img1, &bs1))
        goto done;
    if (!same_bits(&ref, &ref3) || out->cs.samples != cs3.samples) {
        stab_fail("cref: 1 and 3 threads differ");
        goto done;
    }
    if (!same_bits(&img, &img2) || !same_bits(&img, &img1)) {
        stab_fail("model: a second run or the single-cell split gives other bits");
        goto done;
    }
    c5_err err;
    cmp = ref;
    if (c->ref_clamp > 0) { /* what cref would give through the model's saturating format */
        if (c5_image_alloc(&cmp, ref.w, ref.h, &err) != 0) {
            stab_fail("%s", err.msg);
            goto done;
        }
        for (size_t i = 0; i < (size_t)ref.w * ref.h * 3; i++)
            cmp.rgb[i] = ref.rgb[i] < c->ref_clamp ? ref.rgb[i] : (float)c->ref_clamp;
    }
    if (c5_image_compare(&cmp, &img, &out->d, &err) != 0) {
        stab_fail("compare: %s", err.msg);
        goto done;
    }
    double far = (double)(out->d.hist[6] + out->d.hist[7] + out->d.hist[8]) / (double)out->d.values;
    if (getenv("C5_STAB_VERBOSE"))
        printf("    %-34s max|e| %.3g (%.3g)  rmse %.3g (%.3g)  >4 steps %.4f (%.4f)  saturations %llu\n", label,
               out->d.max_abs_err, c->bound.max_err, out->d.rmse, c->bound.rmse, far, c->bound.far,
               (unsigned long long)out->bs.saturations);
    if (!(out->d.max_abs_err <= c->bound.max_err) || !(out->d.rmse <= c->bound.rmse) || !(far <= c->bound.far)) {
        stab_fail("%s: max|e| %.4g (bound %.4g), rmse %.4g (bound %.4g), beyond 4 steps %.4f (bound %.4f)", label,
                  out->d.max_abs_err, c->bound.max_err, out->d.rmse, c->bound.rmse, far, c->bound.far);
        goto done;
    }
    rc = 0;
done:
    if (cmp.rgb != ref.rgb)
        c5_image_free(&cmp);
    if (keep && rc == 0) {
        out->ref = ref;
        out->img = img;
    } else {
        c5_image_free(&ref);
        c5_image_free(&img);
    }
    c5_image_free(&ref3);
    c5_image_free(&img2);
    c5_image_free(&img1);
    if (rc != 0 && !strstr(stab_msg, label)) { /* name the case in every message */
        char m[sizeof stab_msg];
        memcpy(m, stab_msg, sizeof m);
        stab_fail("%s: %.900s", label, m);
    }
    return rc;
}

static void stab_free(stab_out *o)
{
    c5_image_free(&o->ref);
    c5_image_free(&o->img);
}

/* A scene the model refuses by design: the message names the format, and cref renders it
 * (finite). */
static int stab_refused(const char *label, const stab_scene *sc, const int cells[3], const char *needle)
{
    c5_image img;
    c5_board_stats bs;
    c5_cref_stats cs;
    c5_err err;
    c5_board_opts o = {.cells = {cells[0], cells[1], cells[2]}};
    if (c5_board_render(&sc->s, &sc->sv, 0, &o, &img, &bs, &err) == 0) {
        c5_image_free(&img);
        return stab_fail("%s: the model rendered a scene it must refuse", label);
    }
    if (!strstr(err.msg, needle))
        return stab_fail("%s: refusal \"%s\" does not name \"%s\"", label, err.msg, needle);
    int rc = cref_once(sc, 2, &img, &cs);
    c5_image_free(&img);
    return rc;
}

#define STAB(label, sc, c, out, keep) CHECK_MSG(stab_run(label, sc, c, out, keep) == 0, "%s", stab_msg)
#define STAB_LOAD(sc, ...) CHECK_MSG(stab_load(sc, __VA_ARGS__) == 0, "%s", stab_msg)
/* A scene of tests/stab_scenes.c. */
#define STAB_BUILD(call) CHECK_MSG((call) == 0, "%s", stab_msg)
#define STAB_REFUSED(label, sc, cells, needle) \
    CHECK_MSG(stab_refused(label, sc, cells, needle) == 0, "%s", stab_msg)

/* A float image value in the model's UQ2.12 colour: the float is the exact raw / 4096. */
#define RGB_MAX_F ((double)C5_RGB_MAX / (1 << C5_RGB_F))

/* ---- stiff transfer functions ----------------------------------------------------------- */

/* Opacity jumps from 0 at scalar 127 to 1 at 128 across a ramp (17 a voxel): the table is
 * linear between entries, so alpha changes by 1 per scalar unit there, and the model's
 * scalar error (UQ8.8 rounding, the position's error from the SQ1.14 direction: ~2^-15 x
 * distance) goes into alpha at that slope. */
/* STIFF_JUMP: a sample within rounding of the box face (at alpha 1) flips a whole pixel: max is the scene's
 * largest value (only a wrap or runaway exceeds it); measured 0.87 / 0.023 / 0.23 %, rmse and share doubled. */
static const stab_bound STIFF_JUMP = {1.0, 0.05, 0.005};
/* Extinction x step far above 1: opacity per unit_distance 0.02 with the step 1 (50 units a
 * step), so every sample above the threshold is opaque to double precision. */
/* STIFF_EXTINCTION: measured 0.018 / 4.8e-4 / 0.03 %: 1.7x, 2x, 3x; one display step is 0.0039. */
static const stab_bound STIFF_EXTINCTION = {0.03, 0.001, 0.001};
/* A step edge 0 | 255 between voxels: the largest central difference (255) and gradient
 * (SQ8.8 stays below 256, no saturation). */
/* STIFF_EDGE: slope 255 a voxel x position error 2^-15 x ~50 voxels moves alpha at the edge,
 * and the lights' fade (|g|^2 below a quarter step a voxel) the shading where the edge's
 * gradient starts; measured 0.070 / 0.0023 / 0.23 %, 2x. */
static const stab_bound STIFF_EDGE = {0.14, 0.0046, 0.0046};

TEST(stability_stiff_opacity_jump)
{
    static stab_scene sc;
    STAB_BUILD(stab_scene_stiff_jump(&sc));
    stab_out o;
    stab_case c = {STIFF_JUMP, {2, 2, 2}, 0, 0};
    STAB("stiff opacity jump", &sc, &c, &o, 0);
    CHECK_INT(o.bs.saturations, 0);
    c5_supervol_free(&sc.sv);
}

TEST(stability_stiff_extinction)
{
    static stab_scene sc;
    STAB_BUILD(stab_scene_stiff_extinction(&sc));
    stab_out o;
    stab_case c = {STIFF_EXTINCTION, {2, 2, 2}, 0, 0};
    STAB("stiff extinction", &sc, &c, &o, 0);
    c5_supervol_free(&sc.sv);
}

TEST(stability_step_edge_max_gradient)
{
    static stab_scene sc;
    STAB_BUILD(stab_scene_step_edge(&sc));
    stab_out o;
    stab_case c = {STIFF_EDGE, {2, 2, 2}, 0, 0};
    STAB("step edge 0|255", &sc, &c, &o, 0);
    CHECK_INT(o.bs.saturations, 0);
    c5_supervol_free(&sc.sv);
}

/* ---- the Marschner-Lobb signal ---------------------------------------------------------- */

/* The classic 41^3 test signal (f_m 6, alpha 0.25) through a thin tent around 128: the
 * worst case for interpolation and gradient precision; shaded, step 1/2 voxel. */
/* MARSCHNER_LOBB: measured 0.0032 / 2.8e-4 / 0: 2.5x and 2x; below 2 display steps everywhere. */
static const stab_bound MARSCHNER_LOBB = {0.008, 0.0006, 0};

TEST(stability_marschner_lobb)
{
    static stab_scene sc;
    STAB_BUILD(stab_scene_marschner_lobb(&sc));
    stab_out o;
    stab_case c = {MARSCHNER_LOBB, {2, 2, 2}, 0, 0};
    STAB("marschner-lobb 41^3", &sc, &c, &o, 0);
    CHECK_INT(o.bs.saturations, 0);
    c5_supervol_free(&sc.sv);
}

/* ---- rays along axes, cell faces, edges and corners ------------------------------------- */

/* 17x17 images: the centre pixel's ray is exactly the view axis. Every camera below puts
 * that ray (and, for the axis-parallel ones, a column or row of rays) on a cell face, a
 * cell edge, a voxel face or through a cell corner of the 2x2x2 split. */
/* AXIS_RAYS: measured 0.013 / 0.0013 (worst camera, -z along the cell edge): 2x; no value off
 * by 4 steps. The lights' fade (docs/rendering-spec.md sec. 4.3) adds the gradient's magnitude
 * to what the renderers may differ in, and this 16^3 field's edges rise over 6 voxels, so
 * many samples lie below a quarter value step a voxel: with the fade off the same cameras
 * give 0.0072 / 8.7e-4. */
static const stab_bound AXIS_RAYS = {0.026, 0.0026, 0};

TEST(stability_axis_rays_on_cell_faces_edges_corners)
{
    static stab_scene sc;
    STAB_BUILD(stab_scene_axis_rays(&sc));
    const stab_cam *cams = stab_axis_cams;
    for (size_t i = 0; i < STAB_N_AXIS_CAMS; i++) {
        stab_camera(&sc, cams[i].eye, cams[i].target, cams[i].up);
        stab_out o;
        stab_case c = {AXIS_RAYS, {2, 2, 2}, 0, 0};
        STAB(cams[i].label, &sc, &c, &o, 0);
    }
    c5_supervol_free(&sc.sv);
}

/* ---- grazing hits on planes ------------------------------------------------------------- */

/* A diffuse, partly reflective floor z = 0 (the grid's bottom face) lit by a shadow-casting
 * light, seen from 0.05 and 1e-4 above it, from inside its plane (exactly parallel: no
 * hit) and from just below. */
/* GRAZING: measured 0.025 / 8.7e-4 / 0.07 % (worst height): 2x. */
static const stab_bound GRAZING = {0.05, 0.002, 0.002};
/* The eye 1e-4 above the floor, with the headlight at the eye: the floor hits lie within
 * 0.013 voxel of the eye and the light ~3.3 geom_coord LSBs (2^-15) above the floor, so the
 * hit point's rounding (up to 1/2 LSB in height) moves N.L by up to ~15 %: the error goes
 * as 1/height (0.0055 / 0.0041 / 0.0021 / 0.0011 rmse at 1e-4, 4, 8, 16 LSBs; cube5 compare
 * with this scene). Not the epsilon (eye rays take every hit now; with the spawned rays'
 * 1/64 voxel the rmse was 0.071).
 * GRAZING_LOW: measured 0.029 / 0.0055 / 2.6 %: 2x (the max bound 0.05 kept). */
static const stab_bound GRAZING_LOW = {0.05, 0.011, 0.052};

TEST(stability_grazing_plane)
{
    static stab_scene sc;
    STAB_BUILD(stab_scene_grazing(&sc));
    for (int i = 0; i < STAB_N_GRAZING; i++) {
        char label[64];
        snprintf(label, sizeof label, "grazing, eye at z = %g", stab_grazing_heights[i]);
        stab_grazing_camera(&sc, i);
        stab_out o;
        stab_case c = {stab_grazing_heights[i] == 1e-4 ? GRAZING_LOW : GRAZING, {2, 2, 2}, 0, 0};
        STAB(label, &sc, &c, &o, 0);
    }
    c5_supervol_free(&sc.sv);
}

/* ---- total internal reflection ---------------------------------------------------------- */

/* A fully transparent bubble (ior 0.6 < 1) in front of the volume: rays entering it beyond
 * the critical angle asin(0.6) reflect totally; a glass ball (ior 1.5) beside it refracts.
 * Neither reflects by its material, so every reflected ray is a TIR ray. */
/* TIR: measured 0.018 / 6.5e-4 / 0.04 % with max_opacity 0.95: 2x (the ring's edge is a
 * silhouette); with the default 0.99 since 2026-11-21, 0.0051 / 3.0e-4 / 0. */
static const stab_bound TIR = {0.04, 0.0015, 0.001};

TEST(stability_total_internal_reflection)
{
    static stab_scene sc;
    STAB_BUILD(stab_scene_tir(&sc));
    stab_out o;
    stab_case c = {TIR, {2, 2, 2}, 0, 0};
    STAB("total internal reflection", &sc, &c, &o, 0);
    /* Both renderers find total internal reflections. */
    CHECK(o.cs.rays[C5_RAY_REFLECT] > 0 && o.bs.rays[C5_RAY_REFLECT] > 0);
    CHECK_MSG(fabs((double)o.bs.rays[C5_RAY_REFLECT] - (double)o.cs.rays[C5_RAY_REFLECT]) <=
                  0.05 * (double)o.cs.rays[C5_RAY_REFLECT] + 4,
              "reflected rays: model %llu, cref %llu", (unsigned long long)o.bs.rays[C5_RAY_REFLECT],
              (unsigned long long)o.cs.rays[C5_RAY_REFLECT]);
    c5_supervol_free(&sc.sv);
}

/* ---- two parallel mirrors --------------------------------------------------------------- */

/* Perfect mirrors z = -1 and z = 17 around the volume, min_weight 0: only the bounce limit
 * (15, the packet's generation field) ends a ray. The model runs with a Cell Tree in the full
 * DSP RAM and in 2 slots (it overflows, the frame must stay right). */
/* MIRRORS: measured 9.4e-4 / 1.7e-4: 2x; the mirrors' images stay within a quarter display step. */
static const stab_bound MIRRORS = {0.002, 0.0004, 0};

TEST(stability_parallel_mirrors)
{
    static stab_scene sc;
    STAB_BUILD(stab_scene_mirrors(&sc));
    const uint32_t trees[] = {C5_TREE_MAX_SLOTS, 2};
    for (int i = 0; i < 2; i++) {
        stab_out o;
        stab_case c = {MIRRORS, {2, 2, 2}, 0, trees[i]};
        STAB(i ? "parallel mirrors, 2-slot tree" : "parallel mirrors, full tree", &sc, &c, &o, 0);
        CHECK(o.cs.ends[C5_CUT_BOUNCES] > 0 && o.bs.ends[C5_CUT_BOUNCES] > 0);
        CHECK_MSG(fabs((double)o.bs.ends[C5_CUT_BOUNCES] - (double)o.cs.ends[C5_CUT_BOUNCES]) <=
                      0.02 * (double)o.cs.ends[C5_CUT_BOUNCES] + 4,
                  "bounce-limited rays: model %llu, cref %llu", (unsigned long long)o.bs.ends[C5_CUT_BOUNCES],
                  (unsigned long long)o.cs.ends[C5_CUT_BOUNCES]);
        CHECK(o.bs.tree_nodes > 0);
        CHECK_INT(o.bs.tree_overflow, i == 1);
    }
    /* 16 bounces do not fit the packet's 4-bit generation: refused by design. */
    sc.s.render.max_bounces = 16;
    STAB_REFUSED("parallel mirrors, 16 bounces", &sc, ((int[3]){2, 2, 2}), "generation");
    c5_supervol_free(&sc.sv);
}

/* ---- the camera inside the volume, on cell boundaries ----------------------------------- */

/* Rays that start inside the grid: their first sample is at the eye. On a boundary the eye's
 * cell is decided by half-open boxes in both renderers. */
/* CAMERA_INSIDE: measured 0.0025 / 2.2e-4 (worst eye): 2x. */
static const stab_bound CAMERA_INSIDE = {0.005, 0.0005, 0};

TEST(stability_camera_inside_and_on_cell_boundaries)
{
    static stab_scene sc;
    STAB_BUILD(stab_scene_camera_inside(&sc));
    const stab_cam *cams = stab_inside_cams;
    for (size_t i = 0; i < STAB_N_INSIDE_CAMS; i++) {
        stab_camera(&sc, cams[i].eye, cams[i].target, cams[i].up);
        stab_out o;
        stab_case c = {CAMERA_INSIDE, {2, 2, 2}, 0, 0};
        STAB(cams[i].label, &sc, &c, &o, 0);
    }
    c5_supervol_free(&sc.sv);
}

/* ---- fields of view of 0.5 and 170 degrees ---------------------------------------------- */

/* 0.5 degrees from 4000 voxels away (geom coordinates near their 8000 limit): neighbouring
 * pixels' directions differ by ~3 SQ1.14 steps, whose rounding (2^-15 rad) moves a ray by
 * up to 0.12 voxel at that distance: the error is the blobs' value change over 0.1 voxel. */
/* FOV_NARROW: direction rounding x 4000 voxels; measured 0.16 / 0.012 / 7 %: 2x. */
static const stab_bound FOV_NARROW = {0.3, 0.025, 0.15};
/* FOV_WIDE: measured 6.1e-4 / 2.1e-5: 2.5x and 5x (rmse near the float floor of the sum). */
static const stab_bound FOV_WIDE = {0.0015, 0.0001, 0};

TEST(stability_fov_half_degree)
{
    static stab_scene sc;
    STAB_BUILD(stab_scene_fov_narrow(&sc));
    stab_out o;
    stab_case c = {FOV_NARROW, {2, 2, 2}, 0, 0};
    STAB("fov 0.5 from 4000 voxels", &sc, &c, &o, 0);
    /* Beyond geom_coord's reach (SQ13.15, 8000 min spacings) the eye is refused by design. */
    sc.s.camera.eye = v3(-8100, 12, 12);
    STAB_REFUSED("eye 8100 voxels away", &sc, ((int[3]){2, 2, 2}), "SQ13.15");
    c5_supervol_free(&sc.sv);
}

TEST(stability_fov_170_degrees)
{
    static stab_scene sc;
    STAB_BUILD(stab_scene_fov_wide(&sc));
    stab_out o;
    stab_case c = {FOV_WIDE, {2, 2, 2}, 0, 0};
    STAB("fov 170", &sc, &c, &o, 0);
    c5_supervol_free(&sc.sv);
}

/* ---- degenerate and extreme volume shapes ----------------------------------------------- */

/* VOL_1: measured 2.3e-4 / 4.5e-5: 2x; UQ2.12 and alpha roundings only. */
static const stab_bound VOL_1 = {0.0005, 0.0001, 0};
/* VOL_1x1xN: measured 4.3e-4 / 3.2e-5: 2x and 3x. */
static const stab_bound VOL_1x1xN = {0.001, 0.0001, 0};
/* VOL_SLAB: a sample within 0.02 voxel (685 voxels x 2^-15 x sqrt 3) of the 1-voxel slab's faces flips;
 * measured 0.13 / 0.0046 / 0.39 %: 2x. */
static const stab_bound VOL_SLAB = {0.3, 0.01, 0.01};

TEST(stability_volume_1x1x1)
{
    static stab_scene sc;
    STAB_BUILD(stab_scene_volume_1(&sc));
    stab_out o;
    stab_case c = {VOL_1, {1, 1, 1}, 0, 0};
    STAB("1^3 volume", &sc, &c, &o, 0);
    CHECK(o.cs.samples > 0 && o.bs.samples > 0);
    c5_supervol_free(&sc.sv);
}

TEST(stability_volume_1x1xN)
{
    static stab_scene sc;
    STAB_BUILD(stab_scene_volume_rod(&sc));
    stab_out o;
    stab_case c = {VOL_1x1xN, {1, 1, 4}, 0, 0};
    STAB("1x1x64 volume", &sc, &c, &o, 0);
    CHECK(o.bs.samples > 0);
    c5_supervol_free(&sc.sv);
    /* A rod of 512 sampled every 0.1 voxel is 5120 samples long: beyond the 12-bit lifetime. */
    STAB_LOAD(&sc, "{'volumes': [{'generator': 'ramp', 'dims': [1, 1, 512], 'axis': 2}], " TF_SOFT ", " CAM(8, 30)
                   ", 'render': {'step': 0.1}}");
    STAB_REFUSED("1x1x512 at step 0.1", &sc, ((int[3]){1, 1, 2}), "lifetime");
    c5_supervol_free(&sc.sv);
    /* A cell of 257 voxels does not fit the packet position's 8 integer bits; two cells do. */
    STAB_LOAD(&sc, "{'volumes': [{'generator': 'ramp', 'dims': [1, 1, 513], 'axis': 2}], " TF_SOFT ", " CAM(8, 30)
                   "}");
    STAB_REFUSED("1x1x513 in 2 cells", &sc, ((int[3]){1, 1, 2}), "UQ8.15");
    c5_supervol_free(&sc.sv);
}

TEST(stability_volume_512x512x1)
{
    static stab_scene sc;
    STAB_BUILD(stab_scene_volume_slab(&sc));
    stab_out o;
    stab_case c = {VOL_SLAB, {4, 4, 1}, 0, 0};
    STAB("512x512x1 volume", &sc, &c, &o, 0);
    c5_supervol_free(&sc.sv);
}

/* ---- all-zero and all-255 volumes ------------------------------------------------------- */

/* All zero with alpha 0 at table entries 0 and 1 (a sample between entries 0 and 1 could
 * see entry 1's alpha, so the emptiness flags look at both): every cell and block is leaped, the image is the background
 * (UQ2.12: 0.3 -> 1229/4096, 4.9e-5 off). */
/* ZERO_EMPTY: half a UQ2.12 step (2^-13): the background's one rounding. */
static const stab_bound ZERO_EMPTY = {6.2e-5, 6.2e-5, 0};
/* CONSTANT_FOG: measured 7.8e-4 / 2.8e-4 (worst case): 2x. */
static const stab_bound CONSTANT_FOG = {0.0016, 0.0006, 0};

TEST(stability_all_zero_and_all_255_volumes)
{
    static stab_scene sc;
    for (int i = 0; i < STAB_N_CONSTANT; i++) {
        STAB_BUILD(stab_scene_constant(&sc, i));
        stab_out o;
        stab_case c = {i == 0 ? ZERO_EMPTY : CONSTANT_FOG, {2, 2, 2}, 0, 0};
        STAB(stab_constant_cases[i].label, &sc, &c, &o, 0);
        if (i == 0)
            CHECK_INT(o.bs.samples, 0); /* nothing visible: everything leaped */
        c5_supervol_free(&sc.sv);
    }
}

/* ---- saturation of the fixed-point accumulators ----------------------------------------- */

/* Accumulators of the model and where each saturates (docs/bit-layouts.md):
 *   ray colour red/green/blue   UQ2.12, clamps at 4 - 2^-12       (sample_pipe.h c5_composite)
 *   light_term                  UQ4.12, clamps at 16 - 2^-12      (sample_pipe.h c5_shade, hit_unit.c)
 *   shaded_rgb                  UQ4.12, clamps at 16 - 2^-12      (sample_pipe.h c5_shade)
 *   shadow-ray radiance         UQ2.12, clamps at 4 - 2^-12       (hit_unit.c)
 *   opacity                     UQ1.15, bounded by 1 by construction (A + T alpha <= 1)
 *   frame_acc                   UQ20.12, clamps at 2^20 - 2^-12   (board.c): no scene reaches it
 *                               (a surface's local light is at most 16 since light_term clamps)
 * Each is driven past its limit and must stop exactly there (never wrap, never go down). */

/* Ray colour: a constant volume shaded by ambient 15.9 (the limit is 16) gives every ray
 * ~15 in red and green; the model's colour stops at 4 - 2^-12. Against cref clamped there,
 * only the unsaturated blue channel and rounding remain. */
/* SAT_RAY_RGB: measured 2.4e-4 / 4.7e-5: 2x; the saturated channels are exact. */
static const stab_bound SAT_RAY_RGB = {0.0005, 0.0001, 0};
/* Shadow-ray radiance: a floor lit only through shadow rays by a light of intensity 15.9:
 * up to 12.7 per ray in cref, 4 - 2^-12 in the model; below the clamp the rounding of
 * w k c diffuse I N.L (UQ2.12). */
/* SAT_SHADOW_RGB: measured 9.8e-4 / 2.0e-4: 2x. */
static const stab_bound SAT_SHADOW_RGB = {0.002, 0.0004, 0};
/* light_term: a white floor (kdiff 1) under 8 non-shadow lights of intensity 15.9 with
 * diffuse and ambient 15.9: cref's local light reaches ~2000, the model's light_term stops
 * at 16 - 2^-12, and the pixel is W k c light_term = light_term. cref's dimmest pixel is far
 * above 16: every one of the 576 pixels saturates (once each), so against cref clamped
 * there the image is exact. */
/* SAT_LIGHT_TERM: measured 0 / 0 / 0. */
static const stab_bound SAT_LIGHT_TERM = {0, 0, 0};

TEST(stability_saturation_ray_colour)
{
    static stab_scene sc;
    STAB_BUILD(stab_scene_sat_ray_colour(&sc));
    stab_out o;
    stab_case c = {SAT_RAY_RGB, {2, 2, 2}, RGB_MAX_F, 0};
    STAB("saturated ray colour", &sc, &c, &o, 1);
    CHECK(o.bs.saturations > 0);
    int clamped = 0;
    for (size_t i = 0; i < (size_t)o.img.w * o.img.h * 3; i++) {
        CHECK_MSG(o.img.rgb[i] <= RGB_MAX_F, "value %g above the UQ2.12 limit", (double)o.img.rgb[i]);
        if (o.ref.rgb[i] >= RGB_MAX_F) { /* saturated exactly at the limit: not wrapped, not below */
            CHECK_MSG(o.img.rgb[i] == (float)RGB_MAX_F, "saturated value %g, limit %g", (double)o.img.rgb[i],
                      RGB_MAX_F);
            clamped++;
        }
    }
    CHECK(clamped > 0);
    stab_free(&o);
    c5_supervol_free(&sc.sv);
}

TEST(stability_saturation_shadow_radiance)
{
    static stab_scene sc;
    STAB_BUILD(stab_scene_sat_shadow(&sc));
    stab_out o;
    stab_case c = {SAT_SHADOW_RGB, {1, 1, 1}, RGB_MAX_F, 0};
    STAB("saturated shadow-ray radiance", &sc, &c, &o, 1);
    CHECK(o.bs.saturations > 0);
    int clamped = 0, free_ = 0;
    for (size_t i = 0; i < (size_t)o.img.w * o.img.h * 3; i++) {
        CHECK_MSG(o.img.rgb[i] <= RGB_MAX_F, "value %g above the UQ2.12 limit", (double)o.img.rgb[i]);
        if (o.ref.rgb[i] >= RGB_MAX_F) {
            CHECK_MSG(o.img.rgb[i] == (float)RGB_MAX_F, "saturated value %g", (double)o.img.rgb[i]);
            clamped++;
        } else if (o.ref.rgb[i] > 0.5) {
            free_++;
        }
    }
    CHECK(clamped > 0 && free_ > 0); /* both sides of the limit are in the picture */
    stab_free(&o);
    c5_supervol_free(&sc.sv);
}

#define LIGHT_MAX_F (65535.0 / 4096) /* light_term UQ4.12 */

TEST(stability_saturation_light_term)
{
    static stab_scene sc;
    STAB_BUILD(stab_scene_sat_frame_acc(&sc));
    stab_out o;
    stab_case c = {SAT_LIGHT_TERM, {1, 1, 1}, LIGHT_MAX_F, 0};
    STAB("light_term saturated", &sc, &c, &o, 1);
    CHECK(o.bs.saturations > 0);
    int clamped = 0;
    for (size_t i = 0; i < (size_t)o.img.w * o.img.h * 3; i++) {
        CHECK_MSG(o.img.rgb[i] <= LIGHT_MAX_F, "value %g above the UQ4.12 limit", (double)o.img.rgb[i]);
        if (o.ref.rgb[i] >= 2 * LIGHT_MAX_F) { /* well beyond the limit: exactly at it, not wrapped */
            CHECK_MSG(o.img.rgb[i] == (float)LIGHT_MAX_F, "saturated value %g", (double)o.img.rgb[i]);
            clamped++;
        }
    }
    CHECK(clamped > 0);
    stab_free(&o);
    c5_supervol_free(&sc.sv);
    /* Intensity 16 is beyond light_term UQ4.12: refused by design. */
    STAB_LOAD(&sc, "{'lights': [{'type': 'directional', 'direction': [0, 0, -1], 'intensity': 16}], " CAM(8, 30) "}");
    STAB_REFUSED("light intensity 16", &sc, ((int[3]){1, 1, 1}), "UQ4.12");
    c5_supervol_free(&sc.sv);
}

/* The datapath blocks at their limits, directly: shaded_rgb (UQ4.12) and the ray colour and
 * opacity of c5_composite, with every input at the largest value its format holds. */
static const double SAT_UNIT_LSB = 1; /* the clamped results are exact; unclamped ones within one LSB of the double */

TEST(stability_saturation_datapath_blocks)
{
    static stab_scene sc;
    char lights[1024] = "";
    for (int i = 0; i < 8; i++)
        snprintf(lights + strlen(lights), sizeof lights - strlen(lights),
                 "%s{'type': 'directional', 'direction': [0, 0, -1], 'intensity': 15.99}", i ? ", " : "");
    STAB_LOAD(&sc, "{'volumes': [{'generator': 'constant', 'dims': [4, 4, 4]}], 'transfer_function':"
                   " {'opacity': [[0, 1]], 'color': [[0, 1, 1, 1]], 'shading': {'ambient': 15.99, 'diffuse': 15.99,"
                   " 'specular': 15.99, 'specular_power': 1}}, 'lights': [%s], " CAM(8, 30) "}",
              lights);
    c5_frame_regs r;
    c5_err err;
    c5_board_opts bo = {.cells = {1, 1, 1}};
    CHECK_MSG(c5_regs_build(&sc.s, &sc.sv, &bo, &r, &err) == 0, "%s", err.msg);
    c5_supervol_free(&sc.sv);

    /* shaded_rgb: the gradient points away from the lights (N = -g/|g| faces them), the view
     * along the light: N.L = N.H = 1. In double: c (ka + kd 8 I) + ks 8 I = 2062 >> 16. */
    c5_sample smp = {.value = 0, .grad = {0, 0, -(255 << 8)}};
    const int64_t gpos[3] = {0, 0, 0}, dir[3] = {0, 0, -(1 << 14)};
    const int64_t rgba_max[4] = {C5_ONE15, C5_ONE15, C5_ONE15, C5_ONE15};
    int64_t c[3];
    uint64_t sat = 0;
    c5_shade(&r, &smp, rgba_max, gpos, dir, c, &sat);
    for (int ch = 0; ch < 3; ch++)
        CHECK_INT(c[ch], 65535); /* 16 - 2^-12, not wrapped */
    CHECK_INT(sat, 5); /* light_term k and ks (2062 and 2046 >> 16), then the 3 channels */
    /* Below the limit the same block is exact to one LSB: a dim colour, ambient only (zero
     * gradient): c ka = 0.001 x 15.99. */
    smp.grad[2] = 0;
    const int64_t rgba_dim[4] = {33, 33, 33, C5_ONE15}; /* 33 / 2^15 = 0.001007 */
    sat = 0;
    c5_shade(&r, &smp, rgba_dim, gpos, dir, c, &sat);
    double want = 33.0 / C5_ONE15 * 15.99 * 4096; /* the exact product in UQ4.12 LSBs */
    CHECK_NEAR((double)c[0], want, SAT_UNIT_LSB);
    CHECK_INT(sat, 0);

    /* Ray colour and opacity: the largest contribution (2 - 2^-15), alpha 1, colour at
     * shaded_rgb's limit: the colour stops at 4 - 2^-12, the opacity at exactly 1. */
    c5_bray ray = {.w = (1 << 16) - 1};
    const int64_t cmax[3] = {65535, 65535, 65535};
    sat = 0;
    CHECK(c5_composite(&r, &ray, C5_ONE15, cmax, &sat) == 1);
    for (int ch = 0; ch < 3; ch++)
        CHECK_INT(ray.rgb[ch], C5_RGB_MAX);
    CHECK_INT(ray.opa, C5_ONE15);
    CHECK_INT(sat, 3);
    /* Once opaque, further samples change nothing (T = 0): no drift past 1, no wrap. */
    for (int i = 0; i < 10000; i++)
        c5_composite(&r, &ray, C5_ONE15, cmax, &sat);
    CHECK_INT(ray.opa, C5_ONE15);
    for (int ch = 0; ch < 3; ch++)
        CHECK_INT(ray.rgb[ch], C5_RGB_MAX);
    /* Opacity under many small alphas: rounding half to even of T alpha never pushes A
     * past 1 (A + round(T alpha) <= A + T = 1). */
    c5_bray fog = {.w = C5_ONE15};
    const int64_t cdim[3] = {1, 1, 1};
    for (int i = 0; i < 100000; i++) {
        c5_composite(&r, &fog, 1 + i % 7, cdim, &sat);
        CHECK_MSG(fog.opa <= C5_ONE15, "opacity %lld above 1 after %d samples", (long long)fog.opa, i + 1);
    }
}
