/* The certificate (docs/cell-tree.md, "The certificate"): on generated camera paths and under
 * schedules made to lose, the board following a schedule never fetches more than Max Work plus
 * the frame's budget (the path's exact bank plus one allowance), its shadow of Max Work finds
 * exactly Max Work's fetches, the bank never falls below minus one allowance, and the image
 * never depends on the schedule. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "board.h"
#include "camera_motion.h"
#include "dsp_sched.h"
#include "harness.h"
#include "ledger.h"
#include "rng.h"
#include "scene_load.h"
#include "sched_report.h"

static c5_scene scene;
static c5_supervol grid;
static c5_ctree trees[2];

static int load(const char *name, int size)
{
    c5_supervol_free(&grid);
    memset(&grid, 0, sizeof grid);
    if (c5t_load_scene(name, size, &scene, &grid) != 0)
        return -1;
    scene.camera = c5_scene_camera_at(&scene, 0);
    scene.path.n_keys = 0;
    return 0;
}

/* node_rays: the packets tagged with each node, or NULL. */
static int render_rays(const c5_board_opts *o, uint32_t *node_rays, c5_image *img, c5_board_stats *st)
{
    c5_err err;
    c5_board_out keep = {.node_rays = node_rays};
    if (c5_board_render_keep(&scene, &grid, 0, o, &keep, img, st, &err) != 0) {
        fprintf(stderr, "render: %s\n", err.msg);
        return -1;
    }
    return 0;
}

static int render(const c5_board_opts *o, c5_image *img, c5_board_stats *st)
{
    return render_rays(o, NULL, img, st);
}

static int same_bits(const c5_image *a, const c5_image *b)
{
    return a->w == b->w && a->h == b->h && !memcmp(a->rgb, b->rgb, sizeof(float) * 3 * (size_t)a->w * a->h);
}

/* What a followed frame must hold, or a message: fetches within Max Work's plus the budget,
 * the shadow's Max Work equal to the Max Work run's, the same image. */
static int frame_holds(const c5_board_stats *mw, const c5_board_stats *ct, const c5_image *a, const c5_image *b,
                       char *why, size_t n)
{
    if (!same_bits(a, b))
        return snprintf(why, n, "the image differs from Max Work's"), 0;
    if (!ct->certified || ct->shadow_broken)
        return snprintf(why, n, "no certificate (budget %lld, broken %d)", (long long)ct->ledger_budget,
                        ct->shadow_broken), 0;
    if (ct->shadow_steps != mw->fetches)
        return snprintf(why, n, "the shadow found %llu Max Work fetches, Max Work made %llu",
                        (unsigned long long)ct->shadow_steps, (unsigned long long)mw->fetches), 0;
    /* A budget below 0 (a deficit larger than the allowance) lets no load past the shadow's:
     * the frame makes at most Max Work's fetches; so does a frame identical to the tree's. */
    int64_t budget = ct->ledger_budget > 0 && !ct->identical ? ct->ledger_budget : 0;
    if ((int64_t)ct->fetches > (int64_t)mw->fetches + budget)
        return snprintf(why, n, "%llu fetches > Max Work's %llu + budget %lld", (unsigned long long)ct->fetches,
                        (unsigned long long)mw->fetches, (long long)budget), 0;
    if (!ct->identical && ct->lead_max > budget)
        return snprintf(why, n, "the lead reached %lld, over the budget %lld", (long long)ct->lead_max,
                        (long long)ct->ledger_budget), 0;
    return 1;
}

/* One path as `cube5 schedule` runs it: frame f under Max Work and following frame f-1's
 * schedule (paper's rule) under the certificate. 0 with the path's sums and the DSP's bank, or
 * -1 with a message naming the frame. */
static int run_path(const int cells[3], const c5_motion *m, int frames, uint64_t *sum_mw, uint64_t *sum_ct,
                    int64_t *bank, int64_t *lowest, char *why, size_t why_n)
{
    c5_dsp_sched_result prev = {0};
    c5_stale_plan plan = {0};
    static uint32_t node_rays[C5_TREE_SLOTS];
    int have_prev = 0, rc = -1;
    *sum_mw = *sum_ct = 0;
    *lowest = 0;
    c5_camera base = scene.camera;
    for (int f = 0; f < frames; f++) {
        c5_camera cam = c5_motion_camera(&base, m, f);
        c5_board_opts o = {.cells = {cells[0], cells[1], cells[2]}, .tree = &trees[0], .camera = &cam};
        c5_image a = {0}, b = {0};
        c5_board_stats mw, ct;
        c5_ctree_init(&trees[0], 0);
        if (render_rays(&o, node_rays, &a, &mw) != 0)
            goto done;
        c5_ctree *tree = &trees[0];
        if (have_prev && prev.next.len > 0) {
            o.sched = C5_SCHED_EXTERNAL;
            o.schedule = prev.next.cells;
            o.schedule_len = prev.next.len;
            o.plan = &plan;
            o.tree = tree = &trees[1];
            c5_ctree_init(tree, 0);
            if (render_rays(&o, node_rays, &b, &ct) != 0)
                goto done;
            char w[200];
            int ok = frame_holds(&mw, &ct, &a, &b, w, sizeof w);
            c5_image_free(&b);
            if (!ok) {
                snprintf(why, why_n, "frame %d: %s", f, w);
                c5_image_free(&a);
                goto done;
            }
            *sum_mw += mw.fetches;
            *sum_ct += ct.fetches;
        }
        c5_image_free(&a);
        c5_err err;
        c5_dsp_sched_opts so = {.report = c5_dsp_sched_report, .rule = C5_SPLIT_MOST_LEAVES};
        c5_dsp_sched_result next;
        c5_stale_plan now_plan;
        if (c5_dsp_schedule(tree, &so, &next, &err) != 0 ||
            c5_stale_plan_make(tree, node_rays, next.next.cells, next.next.len, o.sched ? o.schedule : NULL,
                               o.sched ? o.schedule_len : 0, &now_plan, &err) != 0)
            goto done;
        c5_stale_plan_settle(&now_plan, f ? &plan : NULL, o.sched ? ct.fetches : mw.fetches,
                             o.sched ? ct.frame_key : mw.frame_key);
        /* A followed frame loses at most bank + allowance: the bank stays >= -allowance (or
         * where it was, when it was lower);
         * a frame of Max Work leaves it as it was. */
        int64_t a_f = c5_ledger_allowance(&plan);
        if (o.sched ? now_plan.bank < (plan.bank < -a_f ? plan.bank : -a_f) : f && now_plan.bank != plan.bank) {
            snprintf(why, why_n, "frame %d: the bank went to %lld (allowance %lld)", f,
                     (long long)now_plan.bank, (long long)a_f);
            c5_stale_plan_free(&now_plan);
            c5_dsp_sched_free(&next);
            goto done;
        }
        if (now_plan.bank < *lowest)
            *lowest = now_plan.bank;
        c5_stale_plan_free(&plan);
        plan = now_plan;
        c5_dsp_sched_free(&prev);
        prev = next;
        have_prev = 1;
    }
    *bank = plan.bank;
    rc = 0;
done:
    c5_dsp_sched_free(&prev);
    c5_stale_plan_free(&plan);
    return rc;
}

/* The guarantee on generated paths: still, slow and fast orbits, random jumps (every few
 * frames and by probability), a dolly through the scene, over even and uneven splits; the
 * DSP's bank is the path's exact balance. */
static void certificate_holds(const char *name)
{
    static const int splits[4][3] = {{2, 2, 2}, {3, 3, 3}, {2, 3, 1}, {3, 1, 2}};
    c5_motion motions[7] = {
        {0},
        {.orbit_deg = 2},
        {.orbit_deg = 8},
        {.orbit_deg = 30},
        {.jumps = 1, .jump_seed = 5, .jump_every = 3},
        {.orbit_deg = 4, .jumps = 1, .jump_seed = 9, .jump_prob = 0.3},
        {.dolly = 0.9},
    };
    CHECK(load(name, 48) == 0);
    for (int s = 0; s < 4; s++)
        for (int k = 0; k < 7; k++) {
            uint64_t mw, ct;
            int64_t bank, lowest;
            char w[300] = "";
            int rc = run_path(splits[s], &motions[k], 6, &mw, &ct, &bank, &lowest, w, sizeof w);
            CHECK_MSG(rc == 0, "%s split %dx%dx%d motion %d: %s", name, splits[s][0], splits[s][1], splits[s][2], k,
                      w);
            CHECK_MSG(rc != 0 || bank == (int64_t)mw - (int64_t)ct, "%s split %dx%dx%d motion %d: bank %lld, balance %lld",
                      name, splits[s][0], splits[s][1], splits[s][2], k, (long long)bank,
                      (long long)mw - (long long)ct);
        }
}

TEST(certificate_holds_brain_mirrors) { certificate_holds("brain_mirrors"); }
TEST(certificate_holds_default) { certificate_holds("default"); }
TEST(certificate_holds_lobster_tunnel) { certificate_holds("lobster_tunnel"); }
TEST(certificate_holds_clouds_lake) { certificate_holds("clouds_lake"); }

/* Schedules made to lose: random cell sequences (cells repeated, cells without rays, the
 * schedule too short or far too long) under random budgets from a bank of 0 to 6 loads, at
 * random views. The board stays within Max Work plus the budget and its shadow is exact;
 * without the certificate the same schedules go past that bound (the check can fail). */
TEST(certificate_holds_against_losing_schedules)
{
    static const int splits[3][3] = {{2, 2, 2}, {3, 3, 3}, {3, 2, 2}};
    CHECK(load("brain_mirrors", 32) == 0);
    c5_camera base = scene.camera;
    uint64_t rng = 0x5eedULL;
    int over_unchecked = 0, cases = 0;
    for (int t = 0; t < 36; t++) {
        const int *cells = splits[t % 3];
        int n = cells[0] * cells[1] * cells[2];
        c5_motion m = {.jumps = 1, .jump_seed = (uint64_t)t + 1, .jump_every = 1};
        c5_camera cam = c5_motion_camera(&base, &m, t % 4);
        int len = (int)(c5_splitmix64(&rng) % (uint64_t)(3 * n + 1));
        int *sched = malloc(sizeof(int) * (size_t)(len ? len : 1));
        for (int i = 0; i < len; i++)
            sched[i] = (int)(c5_splitmix64(&rng) % (uint64_t)n);
        c5_stale_plan p = {.valid = 1, .maxwork_loads = 4, .len = len, .lag_loads = -1, /* allowance 1 */
                           .bank = (int64_t)(c5_splitmix64(&rng) % 7)};
        c5_board_opts o = {.cells = {cells[0], cells[1], cells[2]}, .camera = &cam};
        c5_image a = {0}, b = {0}, u = {0};
        c5_board_stats mw, ct, un;
        CHECK(render(&o, &a, &mw) == 0);
        o.sched = C5_SCHED_EXTERNAL;
        o.schedule = sched;
        o.schedule_len = len;
        o.plan = &p;
        CHECK(render(&o, &b, &ct) == 0);
        char w[200];
        CHECK_MSG(frame_holds(&mw, &ct, &a, &b, w, sizeof w), "case %d (%d cells, %d entries): %s", t, n, len, w);
        CHECK_INT(ct.ledger_budget, p.bank + c5_ledger_allowance(&p));
        o.stale_check = -1;
        CHECK(render(&o, &u, &un) == 0);
        over_unchecked += (int64_t)un.fetches > (int64_t)mw.fetches + ct.ledger_budget;
        cases++;
        c5_image_free(&a), c5_image_free(&b), c5_image_free(&u);
        free(sched);
    }
    CHECK_MSG(over_unchecked > 0, "no schedule of %d went past Max Work + budget unchecked: the test cannot fail",
              cases);
}

/* Frame 0 of scene `name` at size x size over 3x3x3 cells under Max Work (its tree in
 * trees[0], the packets of each node in node_rays) and the DSP's schedule of that tree (the
 * paper's rule). 0, or -1. */
static int own_frame(const char *name, int size, uint32_t *node_rays, c5_image *img, c5_board_stats *mw,
                     c5_dsp_sched_result *sch)
{
    c5_err err;
    c5_dsp_sched_opts so = {.report = c5_dsp_sched_report, .rule = C5_SPLIT_MOST_LEAVES};
    if (load(name, size) != 0)
        return -1;
    c5_ctree_init(&trees[0], 0);
    c5_board_opts o = {.cells = {3, 3, 3}, .tree = &trees[0]};
    return render_rays(&o, node_rays, img, mw) == 0 && c5_dsp_schedule(&trees[0], &so, sch, &err) == 0 ? 0 : -1;
}

/* A frame with the camera registers of the tree's frame builds that tree: the board follows
 * the schedule by the exact replay (its replayed loads when no more than Max Work's, else Max
 * Work's); a camera moved by a hair is another frame. */
TEST(certificate_identical_frame_follows_its_exact_replay)
{
    static uint32_t node_rays[C5_TREE_SLOTS];
    c5_image a = {0}, b = {0};
    c5_board_stats mw, ct;
    c5_err err;
    c5_dsp_sched_result sch;
    c5_stale_plan p;
    CHECK(own_frame("default", 48, node_rays, &a, &mw, &sch) == 0);
    CHECK(c5_stale_plan_make(&trees[0], node_rays, sch.next.cells, sch.next.len, NULL, 0, &p, &err) == 0);
    c5_stale_plan_settle(&p, NULL, mw.fetches, mw.frame_key);
    CHECK_MSG(p.sched_loads < p.maxwork_loads, "the schedule replays %d loads, Max Work %d", p.sched_loads,
              p.maxwork_loads);
    c5_board_opts f = {.cells = {3, 3, 3}, .sched = C5_SCHED_EXTERNAL, .schedule = sch.next.cells,
                       .schedule_len = sch.next.len, .plan = &p};
    CHECK(render(&f, &b, &ct) == 0);
    CHECK(same_bits(&a, &b));
    CHECK(ct.identical && ct.shadow_loads == 0 && ct.shadow_steps == mw.fetches);
    CHECK_INT(ct.fetches, p.sched_loads);
    c5_image_free(&b);
    p.sched_loads = p.maxwork_loads + 1; /* a schedule the replay finds longer: Max Work's frame */
    CHECK(render(&f, &b, &ct) == 0);
    CHECK(ct.identical && ct.ledger_budget == 0 && ct.sched_loads == 0);
    CHECK_INT(ct.fetches, mw.fetches);
    c5_image_free(&b);
    c5_camera cam = scene.camera;
    cam.eye.x += 1e-9;
    f.camera = &cam;
    CHECK(render(&f, &b, &ct) == 0);
    CHECK(!ct.identical && ct.frame_key != mw.frame_key);
    c5_image_free(&a), c5_image_free(&b);
    c5_dsp_sched_free(&sch);
    c5_stale_plan_free(&p);
}

/* A tree that overflows the DSP RAM while the board follows: the shadow cannot place the
 * packets the frozen tree answers with no node, says so, and Max Work takes the rest of the
 * frame; the image is the same bits. */
TEST(certificate_lost_when_the_tree_overflows)
{
    static uint32_t node_rays[C5_TREE_SLOTS];
    c5_image a = {0}, b = {0};
    c5_board_stats mw, ct;
    c5_dsp_sched_result sch;
    CHECK(own_frame("brain_mirrors", 32, node_rays, &a, &mw, &sch) == 0);
    c5_stale_plan p = {.valid = 1, .maxwork_loads = (int)mw.fetches, .len = sch.next.len, .lag_loads = -1,
                       .bank = 1000};
    c5_ctree_init(&trees[1], 40);
    c5_board_opts f = {.cells = {3, 3, 3}, .sched = C5_SCHED_EXTERNAL, .schedule = sch.next.cells,
                       .schedule_len = sch.next.len, .plan = &p, .tree = &trees[1]};
    CHECK(render(&f, &b, &ct) == 0);
    CHECK(ct.tree_overflow);
    CHECK(ct.certified && ct.shadow_broken && ct.shadow_steps == 0);
    CHECK(same_bits(&a, &b));
    c5_image_free(&a), c5_image_free(&b);
    c5_dsp_sched_free(&sch);
}

/* A schedule of the frame's own tree with no bank: the lead it would need is refused, and the
 * shadow's loads take the frame; with a bank as large as Max Work's loads, the schedule is
 * followed to the end and saves what it saves unchecked. */
TEST(certificate_budget_decides_how_far_the_board_follows)
{
    static uint32_t node_rays[C5_TREE_SLOTS];
    c5_image a = {0}, b = {0}, u = {0};
    c5_board_stats mw, ct, un;
    c5_dsp_sched_result sch;
    CHECK(own_frame("brain_mirrors", 48, node_rays, &a, &mw, &sch) == 0);
    c5_board_opts f = {.cells = {3, 3, 3}, .sched = C5_SCHED_EXTERNAL, .schedule = sch.next.cells,
                       .schedule_len = sch.next.len, .stale_check = -1};
    CHECK(render(&f, &u, &un) == 0);
    CHECK_MSG(un.fetches + 5 < mw.fetches, "the own schedule saves too little to test: %llu against %llu",
              (unsigned long long)un.fetches, (unsigned long long)mw.fetches);
    c5_stale_plan p = {.valid = 1, .maxwork_loads = 1, .len = sch.next.len, .lag_loads = -1, .bank = 0};
    f.stale_check = 0;
    f.plan = &p;
    CHECK(render(&f, &b, &ct) == 0);
    char w[200];
    CHECK_MSG(frame_holds(&mw, &ct, &a, &b, w, sizeof w), "bank 0: %s", w);
    CHECK_INT(ct.ledger_budget, 1);
    CHECK(ct.sched_switches > 0 && ct.shadow_loads > 0 && ct.switch_reason == C5_SWITCH_BUDGET);
    c5_image_free(&b);
    p.bank = (int64_t)mw.fetches;
    CHECK(render(&f, &b, &ct) == 0);
    CHECK_MSG(frame_holds(&mw, &ct, &a, &b, w, sizeof w), "large bank: %s", w);
    CHECK_INT(ct.shadow_loads, 0);
    CHECK_INT(ct.sched_switches, 0);
    CHECK_INT(ct.fetches, un.fetches);
    c5_image_free(&a), c5_image_free(&b), c5_image_free(&u);
    c5_dsp_sched_free(&sch);
}

/* The DSP's replay (stale_plan.h) on a frame's own tree, with the rays the board counted per
 * node, gives the loads Max Work made in that frame and the loads of following the frame's
 * own schedule, exactly. */
TEST(stale_replay_is_exact_on_the_own_tree)
{
    static const int splits[2][3] = {{2, 2, 2}, {3, 3, 3}};
    static const char *names[2] = {"clouds_lake", "lobster_tunnel"};
    static uint32_t node_rays[C5_TREE_SLOTS];
    for (int i = 0; i < 2; i++)
        for (int k = 0; k < 2; k++) {
            CHECK(load(names[i], 32) == 0);
            c5_ctree_init(&trees[0], 0);
            c5_board_opts o = {.cells = {splits[k][0], splits[k][1], splits[k][2]}, .tree = &trees[0]};
            c5_image img, img2;
            c5_board_stats st, st2;
            c5_err err;
            c5_dsp_sched_result sch;
            c5_stale_plan p;
            c5_dsp_sched_opts so = {.report = c5_dsp_sched_report, .rule = C5_SPLIT_MOST_LEAVES};
            CHECK(render_rays(&o, node_rays, &img, &st) == 0);
            CHECK(c5_dsp_schedule(&trees[0], &so, &sch, &err) == 0);
            CHECK(c5_stale_plan_make(&trees[0], node_rays, sch.next.cells, sch.next.len, NULL, 0, &p, &err) == 0);
            CHECK(p.valid);
            CHECK_INT(p.maxwork_loads, st.fetches);
            CHECK_INT(p.lag_loads, -1);
            c5_board_opts f = {.cells = {splits[k][0], splits[k][1], splits[k][2]}, .sched = C5_SCHED_EXTERNAL,
                               .schedule = sch.next.cells, .schedule_len = sch.next.len, .stale_check = -1};
            CHECK(render(&f, &img2, &st2) == 0);
            CHECK_INT(p.sched_loads, st2.fetches);
            int loads = 0;
            for (int e = 0; e < p.len; e++) /* an entry expected to find rays is a load */
                loads += p.pred[e] > 0;
            CHECK(loads <= p.sched_loads);
            c5_image_free(&img), c5_image_free(&img2);
            c5_dsp_sched_free(&sch);
            c5_stale_plan_free(&p);
        }
}
