/* The board model at run-time datapath widths (rtl_model/proc/widths.h): the setter,
 * the shipped widths bit for bit, and per signal that a narrower fraction costs accuracy
 * against cref (double), deterministically.
 *
 * C5_WIDTHS_VERBOSE=1 build/tests/unit widths prints the RMSE against cref of every signal
 * at its shipped width, shipped - 4 and a very narrow width (docs/board-model.md,
 * "Datapath widths at run time"). */
#include <stdlib.h>
#include <string.h>

#include "board.h"
#include "c5_layouts.h"
#include "fxops.h"
#include "harness.h"
#include "metrics.h"
#include "ray.h"
#include "widths.h"

/* ---- the API --------------------------------------------------------------------------- */

TEST(widths_shipped_from_the_spec)
{
    static const char *names[C5_W_COUNT] = {"pos", "dir", "value", "rgba", "opacity", "rgb", "normal"};
    static const int bits[C5_W_COUNT] = {15, 14, 8, 15, 15, 12, 14};
    for (int i = 0; i < C5_W_COUNT; i++) {
        CHECK(strcmp(c5_width_name((c5_width_id)i), names[i]) == 0);
        CHECK_INT(c5_width_shipped((c5_width_id)i), bits[i]);
    }
    /* The formats the model computes in (ray.h) and the spec's (generated) agree; step_vec
     * shares pos's fraction, contribution opacity's. */
    CHECK_INT(c5_width_shipped(C5_W_POS), C5_POS_F);
    CHECK_INT(c5_width_shipped(C5_W_POS), C5_SIG_STEP_VEC_FMT.frac_bits);
    CHECK_INT(c5_width_shipped(C5_W_DIR), C5_DIR_F);
    CHECK_INT(c5_width_shipped(C5_W_RGB), C5_RGB_F);
    CHECK_INT(c5_width_shipped(C5_W_RGB), C5_SIG_SAMPLE_RGB_FMT.frac_bits);
    CHECK_INT(c5_width_shipped(C5_W_OPACITY), C5_RAY_PACKET_CONTRIBUTION_FMT.frac_bits);
    CHECK_INT(c5_width_shipped(C5_W_RGBA), C5_SIG_TF_RGBA_FMT.frac_bits);
}

TEST(widths_set_refuses_with_a_message)
{
    c5_widths w = c5_widths_shipped();
    CHECK(c5_widths_are_shipped(&w));
    c5_err err;
    /* Every width to its shipped value: still shipped (the round trip). */
    for (int i = 0; i < C5_W_COUNT; i++)
        CHECK(c5_widths_set(&w, c5_width_name((c5_width_id)i), c5_width_shipped((c5_width_id)i), &err) == 0);
    CHECK(c5_widths_are_shipped(&w));
    CHECK(c5_widths_set(&w, "sharpness", 4, &err) == -1);
    CHECK_HAS(err.msg, "unknown datapath width 'sharpness'");
    CHECK_HAS(err.msg, "pos, dir, value, rgba, opacity, rgb, normal");
    CHECK(c5_widths_set(&w, "pos", 0, &err) == -1);
    CHECK_HAS(err.msg, "pos=0: must be 1 .. 15");
    CHECK(c5_widths_set(&w, "value", 9, &err) == -1); /* widening is not offered */
    CHECK_HAS(err.msg, "value=9: must be 1 .. 8");
    CHECK(c5_widths_set(&w, "rgb", -3, &err) == -1);
    CHECK_HAS(err.msg, "1 .. 12");
    CHECK(c5_widths_are_shipped(&w)); /* refusals change nothing */
    CHECK(c5_widths_set(&w, "rgb", 1, &err) == 0);
    CHECK_INT(w.frac[C5_W_RGB], 1);
    CHECK(!c5_widths_are_shipped(&w));
    CHECK(c5_widths_set(&w, "rgb", 12, &err) == 0);
    CHECK(c5_widths_are_shipped(&w));
}

TEST(widths_narrow_rounds_half_even_and_clamps)
{
    CHECK_INT(c5_narrow(12345, 0), 12345);
    CHECK_INT(c5_narrow(-12345, 0), -12345);
    CHECK_INT(c5_narrow(0x17, 4), 0x10);  /* 1.4375 -> 1 */
    CHECK_INT(c5_narrow(0x18, 4), 0x20);  /* 1.5 -> 2 (tie to even) */
    CHECK_INT(c5_narrow(0x28, 4), 0x20);  /* 2.5 -> 2 */
    CHECK_INT(c5_narrow(0x29, 4), 0x30);
    CHECK_INT(c5_narrow(-0x18, 4), -0x20); /* symmetric: a negated unit vector rounds alike */
    CHECK_INT(c5_narrow(-0x28, 4), -0x20);
    uint64_t sat = 0;
    /* The top of UQ2.12 narrowed to 8 bits: 16383 rounds to 16384, which the container
     * holds but the narrowed format does not: clamped to 16368 and counted. */
    CHECK_INT(c5_narrow_clamp(C5_RGB_MAX, 4, 0, C5_RGB_MAX, &sat), C5_RGB_MAX - 15);
    CHECK_INT(sat, 1);
    CHECK_INT(c5_narrow_clamp(C5_RGB_MAX, 0, 0, C5_RGB_MAX, &sat), C5_RGB_MAX);
    CHECK_INT(c5_narrow_clamp(100, 3, 0, C5_RGB_MAX, &sat), 96);
    CHECK_INT(sat, 1);
}

/* ---- rendering ------------------------------------------------------------------------- */

/* A shaded volume (gradient normals, compositing) and the same volume with a mirror floor,
 * a glass ball and a shadow-casting light (hit normals, spawned contributions, shadow
 * radiance). Small: every render below is a few milliseconds. */
#define TF "'transfer_function': {'opacity': [[0, 0], [40, 0], [200, 0.5], [255, 0.8]]," \
           " 'color': [[0, 0.9, 0.4, 0.1], [128, 0.5, 0.8, 0.3], [255, 0.2, 0.4, 1]]}"
#define NSCENES 3
static const char *const SCENES[NSCENES] = {
    "{'volumes': [{'generator': 'blobs', 'dims': [16, 16, 16], 'seed': 3}], " TF ","
    " 'lights': [{'type': 'point', 'position': [-30, -20, 25]}],"
    " 'camera': {'eye': [-30, -20, 25], 'target': [8, 8, 8], 'fov': 30, 'width': 32, 'height': 32},"
    " 'render': {'background': [0.1, 0.2, 0.3]}}",
    "{'volumes': [{'generator': 'blobs', 'dims': [16, 16, 16], 'seed': 4}], " TF ","
    " 'lights': [{'type': 'point', 'position': [8, -20, 40], 'shadows': true}],"
    " 'surfaces': [{'type': 'plane', 'point': [0, 0, -1], 'normal': [0, 0, 1],"
    "   'material': {'color': [0.9, 0.8, 0.6], 'reflectivity': 0.4}},"
    "  {'type': 'sphere', 'center': [4, -6, 6], 'radius': 3.5,"
    "   'material': {'color': [0.8, 0.9, 1], 'transparency': 0.6, 'reflectivity': 0.2, 'ior': 1.4}}],"
    " 'camera': {'eye': [-25, -35, 20], 'target': [8, 6, 4], 'fov': 40, 'width': 32, 'height': 32},"
    " 'render': {'max_bounces': 3, 'background': [0.3, 0.3, 0.35]}}",
    /* A stiff table (opacity and colour change within 4 scalar units): the sample value's
     * fraction matters (on the soft table above 2 bits of it cost nothing measurable). */
    "{'volumes': [{'generator': 'blobs', 'dims': [16, 16, 16], 'seed': 3}],"
    " 'transfer_function': {'opacity': [[0, 0], [120, 0], [124, 0.9], [255, 0.9]],"
    "   'color': [[0, 0.9, 0.4, 0.1], [120, 0.9, 0.4, 0.1], [124, 0.1, 0.5, 1], [255, 0.1, 0.5, 1]]},"
    " 'lights': [{'type': 'point', 'position': [-30, -20, 25]}],"
    " 'camera': {'eye': [-30, -20, 25], 'target': [8, 8, 8], 'fov': 30, 'width': 32, 'height': 32},"
    " 'render': {'background': [0.1, 0.2, 0.3]}}",
};

typedef struct {
    c5_scene s;
    c5_supervol sv;
    c5_image ref; /* cref */
    c5_image ship; /* the model, opts.widths == NULL */
} wscene;

static wscene scenes[NSCENES];
static int loaded[NSCENES];

/* Scene i with its cref image and its model image at the shipped widths (once per run). */
static wscene *scene(int i)
{
    if (loaded[i])
        return &scenes[i];
    wscene *w = &scenes[i];
    c5_err err;
    c5_cref_stats cs;
    c5_board_stats bs;
    c5_cref_opts co = {.threads = 1, .field = NULL};
    c5_board_opts bo = {.cells = {2, 2, 2}};
    if (c5_scene_parse(c5t_json(SCENES[i]), NULL, "widths", &w->s, &err) != 0 ||
        c5_supervol_build(&w->s, &w->sv, &err) != 0 || c5_cref_render(&w->s, &w->sv, 0, &co, &w->ref, &cs, &err) != 0 ||
        c5_board_render(&w->s, &w->sv, 0, &bo, &w->ship, &bs, &err) != 0) {
        fprintf(stderr, "widths scene %d: %s\n", i, err.msg);
        return NULL;
    }
    loaded[i] = 1;
    return w;
}

static int render(const wscene *w, const c5_widths *wd, const int cells[3], c5_image *img, c5_board_stats *bs)
{
    c5_err err;
    c5_board_opts o = {.cells = {cells[0], cells[1], cells[2]}, .widths = wd};
    if (c5_board_render(&w->s, &w->sv, 0, &o, img, bs, &err) != 0) {
        fprintf(stderr, "model: %s\n", err.msg);
        return -1;
    }
    return 0;
}

static int same_bits(const c5_image *a, const c5_image *b)
{
    return a->w == b->w && a->h == b->h && !memcmp(a->rgb, b->rgb, sizeof(float) * 3 * (size_t)a->w * a->h);
}

static double rmse(const c5_image *ref, const c5_image *img)
{
    c5_image_diff d;
    c5_err err;
    if (c5_image_compare(ref, img, &d, &err) != 0)
        return -1;
    return d.rmse;
}

static int verbose(void)
{
    const char *v = getenv("C5_WIDTHS_VERBOSE");
    return v && *v && strcmp(v, "0") != 0;
}

static const int SPLIT[3] = {2, 2, 2};

TEST(widths_shipped_are_the_default_bit_for_bit)
{
    c5_widths ship = c5_widths_shipped();
    for (int i = 0; i < NSCENES; i++) {
        wscene *w = scene(i);
        CHECK(w);
        c5_image img = {0};
        c5_board_stats bs;
        CHECK(render(w, &ship, SPLIT, &img, &bs) == 0);
        CHECK_MSG(same_bits(&img, &w->ship), "scene %d: shipped widths differ from opts.widths == NULL", i);
        c5_image_free(&img);
    }
}

TEST(widths_out_of_range_refused_by_the_board)
{
    wscene *w = scene(0);
    CHECK(w);
    c5_widths wd = c5_widths_shipped();
    wd.frac[C5_W_NORMAL] = 15; /* set directly, past the setter */
    c5_board_opts o = {.widths = &wd};
    c5_image img = {0};
    c5_board_stats bs;
    c5_err err;
    CHECK(c5_board_render(&w->s, &w->sv, 0, &o, &img, &bs, &err) == -1);
    CHECK_HAS(err.msg, "normal=15: must be 1 .. 14");
    wd.frac[C5_W_NORMAL] = 0;
    CHECK(c5_board_render(&w->s, &w->sv, 0, &o, &img, &bs, &err) == -1);
    CHECK_HAS(err.msg, "normal=0");
}

/* Per signal: the scene that exercises it, and the narrow widths tried (shipped - 4 and a
 * very narrow one). */
typedef struct {
    c5_width_id id;
    int scene;
    int mid, narrow;
} wcase;

static const wcase CASES[] = {
    {C5_W_POS, 0, 11, 3},     {C5_W_DIR, 0, 10, 3},    {C5_W_VALUE, 2, 4, 2},   {C5_W_RGBA, 0, 11, 4},
    {C5_W_OPACITY, 0, 11, 4}, {C5_W_RGB, 0, 8, 4},     {C5_W_NORMAL, 0, 10, 3}, {C5_W_POS, 1, 11, 3},
    {C5_W_DIR, 1, 10, 3},     {C5_W_OPACITY, 1, 11, 3}, {C5_W_RGB, 1, 8, 3},    {C5_W_NORMAL, 1, 10, 3},
    {C5_W_RGBA, 2, 11, 4},
};

TEST(widths_narrower_signals_cost_accuracy)
{
    for (size_t k = 0; k < sizeof CASES / sizeof CASES[0]; k++) {
        const wcase *c = &CASES[k];
        wscene *w = scene(c->scene);
        CHECK(w);
        const char *name = c5_width_name(c->id);
        double e_ship = rmse(&w->ref, &w->ship);
        c5_image mid = {0}, nar = {0};
        c5_board_stats bs;
        c5_widths wd = c5_widths_shipped();
        wd.frac[c->id] = c->mid;
        CHECK(render(w, &wd, SPLIT, &mid, &bs) == 0);
        wd.frac[c->id] = c->narrow;
        CHECK(render(w, &wd, SPLIT, &nar, &bs) == 0);
        double e_mid = rmse(&w->ref, &mid), e_nar = rmse(&w->ref, &nar);
        if (verbose())
            printf("  widths: scene %d %-7s rmse vs cref: %2d bits %.3e   %2d bits %.3e   %2d bits %.3e\n", c->scene,
                   name, c5_width_shipped(c->id), e_ship, c->mid, e_mid, c->narrow, e_nar);
        CHECK(e_ship >= 0 && e_mid >= 0 && e_nar >= 0);
        CHECK_MSG(!same_bits(&mid, &w->ship), "scene %d: %s at %d bits leaves the image unchanged", c->scene, name,
                  c->mid);
        CHECK_MSG(!same_bits(&nar, &w->ship), "scene %d: %s at %d bits leaves the image unchanged", c->scene, name,
                  c->narrow);
        CHECK_MSG(e_nar > e_ship, "scene %d: %s at %d bits: rmse %.3e not above the shipped %.3e", c->scene, name,
                  c->narrow, e_nar, e_ship);
        CHECK_MSG(e_nar > e_mid, "scene %d: %s: rmse at %d bits %.3e not above that at %d bits %.3e", c->scene, name,
                  c->narrow, e_nar, c->mid, e_mid);
        c5_image_free(&mid);
        c5_image_free(&nar);
    }
}

/* Narrowed runs are deterministic, and (as at the shipped widths) the image does not depend
 * on the cell split: a narrowed signal is still the ray's own packet state. */
TEST(widths_narrowed_runs_are_deterministic)
{
    static const int one[3] = {1, 1, 1};
    c5_widths wd = c5_widths_shipped();
    c5_err err;
    CHECK(c5_widths_set(&wd, "pos", 9, &err) == 0 && c5_widths_set(&wd, "dir", 8, &err) == 0 &&
          c5_widths_set(&wd, "value", 5, &err) == 0 && c5_widths_set(&wd, "rgba", 9, &err) == 0 &&
          c5_widths_set(&wd, "opacity", 9, &err) == 0 && c5_widths_set(&wd, "rgb", 7, &err) == 0 &&
          c5_widths_set(&wd, "normal", 8, &err) == 0);
    for (int i = 0; i < NSCENES; i++) {
        wscene *w = scene(i);
        CHECK(w);
        c5_image a = {0}, b = {0}, c = {0};
        c5_board_stats bs;
        CHECK(render(w, &wd, SPLIT, &a, &bs) == 0);
        CHECK(render(w, &wd, SPLIT, &b, &bs) == 0);
        CHECK(render(w, &wd, one, &c, &bs) == 0);
        CHECK_MSG(!same_bits(&a, &w->ship), "scene %d: every signal narrowed, the image unchanged", i);
        CHECK_MSG(same_bits(&a, &b), "scene %d: two narrowed runs differ", i);
        CHECK_MSG(same_bits(&a, &c), "scene %d: the narrowed image depends on the split", i);
        c5_image_free(&a);
        c5_image_free(&b);
        c5_image_free(&c);
    }
}

/* Where the datapath produces a narrowed signal it lies on the narrowed grid: every packet
 * (pos, dir, contribution, opacity, colour), every step vector, sample value and table
 * lookup the taps see has its dropped fraction bits zero. */
typedef struct {
    int sh[C5_W_COUNT];
    uint64_t packets, samples, steps, off_grid;
} grid_check;

static int on_grid(int64_t v, int s) { return (v & (((int64_t)1 << s) - 1)) == 0; }

static void tap_packet(void *ctx, const uint8_t *pk)
{
    grid_check *g = ctx;
    /* the packet's fields as they are: the position from the cell's corner is on the grid
     * exactly when the grid position is (a corner is a whole voxel) */
    c5_ray_packet_t r;
    c5_ray_packet_unpack(pk, &r);
    g->packets++;
    int ok = on_grid(r.contribution, g->sh[C5_W_OPACITY]) && on_grid(r.opacity, g->sh[C5_W_OPACITY]) &&
             on_grid(r.pos_x, g->sh[C5_W_POS]) && on_grid(r.pos_y, g->sh[C5_W_POS]) &&
             on_grid(r.pos_z, g->sh[C5_W_POS]) && on_grid(r.dir_x, g->sh[C5_W_DIR]) &&
             on_grid(r.dir_y, g->sh[C5_W_DIR]) && on_grid(r.dir_z, g->sh[C5_W_DIR]) &&
             on_grid(r.red, g->sh[C5_W_RGB]) && on_grid(r.green, g->sh[C5_W_RGB]) && on_grid(r.blue, g->sh[C5_W_RGB]);
    g->off_grid += !ok;
}

static void tap_classify(void *ctx, int64_t value, const int64_t rgba[4])
{
    grid_check *g = ctx;
    g->samples++;
    int ok = on_grid(value, g->sh[C5_W_VALUE]);
    for (int ch = 0; ch < 4; ch++)
        ok &= on_grid(rgba[ch], g->sh[C5_W_RGBA]);
    g->off_grid += !ok;
}

static void tap_traverse(void *ctx, const c5_trav_in *in, const c5_trav_out *out)
{
    grid_check *g = ctx;
    g->steps++;
    int ok = 1;
    for (int a = 0; a < 3; a++)
        ok &= on_grid(in->S[a], g->sh[C5_W_POS]) && on_grid(out->pos[a], g->sh[C5_W_POS]);
    g->off_grid += !ok;
}

TEST(widths_narrowed_signals_stay_on_their_grid)
{
    c5_widths wd = c5_widths_shipped();
    wd.frac[C5_W_POS] = 9;
    wd.frac[C5_W_DIR] = 12; /* finer than pos: the step vector is narrowed by its own rounding */
    wd.frac[C5_W_VALUE] = 5;
    wd.frac[C5_W_RGBA] = 10;
    wd.frac[C5_W_OPACITY] = 9;
    wd.frac[C5_W_RGB] = 7;
    wd.frac[C5_W_NORMAL] = 8;
    grid_check g = {0};
    for (int i = 0; i < C5_W_COUNT; i++)
        g.sh[i] = c5_width_shipped((c5_width_id)i) - wd.frac[i];
    c5_taps t = {.ctx = &g, .packet = tap_packet, .classify = tap_classify, .traverse = tap_traverse};
    for (int i = 0; i < NSCENES; i++) {
        wscene *w = scene(i);
        CHECK(w);
        c5_board_opts o = {.cells = {2, 2, 2}, .widths = &wd, .taps = &t};
        c5_image img = {0};
        c5_board_stats bs;
        c5_err err;
        CHECK_MSG(c5_board_render(&w->s, &w->sv, 0, &o, &img, &bs, &err) == 0, "%s", err.msg);
        c5_image_free(&img);
    }
    CHECK(g.packets > 1000 && g.samples > 1000 && g.steps > 1000);
    CHECK_MSG(g.off_grid == 0, "%llu of %llu packets, samples and steps off the narrowed grid",
              (unsigned long long)g.off_grid, (unsigned long long)(g.packets + g.samples + g.steps));
}
