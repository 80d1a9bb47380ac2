/* A stale schedule (docs/cell-tree.md, "Stale schedules"): on generated camera paths the
 * board following the previous frame's Cell Tree schedule, with its online detection, never
 * makes more than 2 % (or one) more fetches than Max Work in a frame, nor more over a path;
 * the repair's corner cases; the image never depends on the schedule. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "board.h"
#include "camera_motion.h"
#include "dsp_sched.h"
#include "harness.h"
#include "scene_load.h"

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

static int render(const c5_board_opts *o, c5_image *img, c5_board_stats *st)
{
    c5_err err;
    if (c5_board_render(&scene, &grid, 0, o, img, st, &err) != 0) {
        fprintf(stderr, "render: %s\n", err.msg);
        return -1;
    }
    return 0;
}

static int same_bits(const c5_image *a, const c5_image *b)
{
    return a->w == b->w && a->h == b->h && !memcmp(a->rgb, b->rgb, sizeof(float) * 3 * (size_t)a->w * a->h);
}

/* The per-frame promise: at most 2 % more fetches than Max Work, or one more. */
static uint64_t allowed(uint64_t mw)
{
    uint64_t two = (uint64_t)ceil(1.02 * (double)mw);
    return two > mw + 1 ? two : mw + 1;
}

/* One path: frame f under Max Work and following frame f-1's schedule (paper's rule), as
 * `cube5 schedule` runs it. Returns the number of frames over the promise (and the path's
 * sums, and the bank the DSP kept); stale_check as the board's option; -1 on error. */
static int run_path(const int cells[3], const c5_motion *m, int frames, int stale_check, uint64_t *sum_mw,
                    uint64_t *sum_ct, int *switches, int64_t *bank, char *why, size_t why_n)
{
    int ncells = cells[0] * cells[1] * cells[2], bad = 0;
    uint32_t *start[2] = {calloc((size_t)ncells, 4), calloc((size_t)ncells, 4)};
    c5_dsp_sched_result prev = {0};
    c5_stale_plan plan = {0};
    static uint32_t node_rays[C5_TREE_SLOTS];
    int have_prev = 0;
    *sum_mw = *sum_ct = 0;
    *switches = 0;
    c5_camera base = scene.camera;
    for (int f = 0; f < frames; f++) {
        c5_camera cam = c5_motion_camera(&base, m, f);
        uint32_t *now = start[f & 1], *before = start[(f & 1) ^ 1];
        c5_board_opts o = {.cells = {cells[0], cells[1], cells[2]}, .tree = &trees[0], .camera = &cam,
                           .start_counts = now, .node_rays = node_rays};
        c5_image a = {0}, b = {0};
        c5_board_stats mw, ct;
        c5_ctree_init(&trees[0], 0);
        if (render(&o, &a, &mw) != 0)
            return -1;
        c5_ctree *tree = &trees[0];
        if (have_prev && prev.next.len > 0) {
            o.sched = C5_SCHED_EXTERNAL;
            o.schedule = prev.next.cells;
            o.schedule_len = prev.next.len;
            o.stale_check = stale_check;
            o.prev_start = before;
            o.prev_start_len = ncells;
            o.plan = &plan;
            o.start_counts = NULL;
            o.tree = tree = &trees[1];
            c5_ctree_init(tree, 0);
            if (render(&o, &b, &ct) != 0)
                return -1;
            if (!same_bits(&a, &b)) {
                snprintf(why, why_n, "frame %d: image differs from Max Work's", f);
                return -1;
            }
            *sum_mw += mw.fetches;
            *sum_ct += ct.fetches;
            *switches += (int)ct.sched_switches;
            if (ct.fetches > allowed(mw.fetches)) {
                if (!bad)
                    snprintf(why, why_n, "frame %d: %llu fetches against Max Work's %llu", f,
                             (unsigned long long)ct.fetches, (unsigned long long)mw.fetches);
                bad++;
            }
            c5_image_free(&b);
        }
        c5_image_free(&a);
        c5_err err;
        c5_dsp_sched_opts so = {.rule = C5_SPLIT_MOST_LEAVES};
        c5_dsp_sched_result next;
        c5_stale_plan now_plan;
        if (c5_dsp_schedule(tree, &so, &next, &err) != 0 ||
            c5_stale_plan_make(tree, node_rays, next.next.cells, next.next.len, o.sched ? o.schedule : NULL,
                               o.sched ? o.schedule_len : 0, &now_plan, &err) != 0)
            return -1;
        c5_stale_plan_settle(&now_plan, f ? &plan : NULL, o.sched ? ct.fetches : mw.fetches);
        c5_stale_plan_free(&plan);
        plan = now_plan;
        c5_dsp_sched_free(&prev);
        prev = next;
        have_prev = 1;
    }
    *bank = plan.bank;
    c5_dsp_sched_free(&prev);
    c5_stale_plan_free(&plan);
    free(start[0]);
    free(start[1]);
    return bad;
}

/* The promise on generated paths: still, slow and fast orbits, random jumps (every few
 * frames and by probability), a dolly through the scene, over even and uneven splits. */
static void never_worse_on(const char *name, int size, int stale_check, int *bad_frames, int *bad_paths,
                           char *why, size_t why_n)
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
    *bad_frames = *bad_paths = 0;
    if (load(name, size) != 0) {
        *bad_frames = -1;
        return;
    }
    for (int s = 0; s < 4; s++)
        for (int k = 0; k < 7; k++) {
            uint64_t mw, ct;
            int sw;
            char w[200] = "";
            int64_t bank;
            int bad = run_path(splits[s], &motions[k], 6, stale_check, &mw, &ct, &sw, &bank, w, sizeof w);
            if (bad >= 0 && bank != (int64_t)mw - (int64_t)ct) { /* the ledger is the path's exact balance */
                snprintf(w, sizeof w, "the DSP's bank %lld, the path's balance %lld", (long long)bank,
                         (long long)mw - (long long)ct);
                bad = -1;
            }
            if (bad < 0) {
                *bad_frames = -1;
                snprintf(why, why_n, "%s: %s", name, w);
                return;
            }
            if (bad && !*bad_frames)
                snprintf(why, why_n, "%s split %dx%dx%d motion %d: %s", name, splits[s][0], splits[s][1],
                         splits[s][2], k, w);
            *bad_frames += bad;
            if (ct > mw) {
                if (!*bad_paths && !*bad_frames)
                    snprintf(why, why_n, "%s split %dx%dx%d motion %d: path %llu > Max Work's %llu", name,
                             splits[s][0], splits[s][1], splits[s][2], k, (unsigned long long)ct,
                             (unsigned long long)mw);
                (*bad_paths)++;
            }
        }
}

/* One case per built-in scene, so that a failure names it. paths: whether the path promise
 * is checked too (clouds_lake: not yet, docs/cell-tree.md "Stale schedules", what does not
 * hold: one path one fetch over). */
static void never_worse(const char *name, int paths_too)
{
    int frames, paths;
    char why[300] = "";
    never_worse_on(name, 48, 0, &frames, &paths, why, sizeof why);
    CHECK_MSG(frames == 0 && (!paths_too || paths == 0), "%d frames, %d paths over Max Work: %s", frames, paths, why);
}

TEST(stale_never_worse_brain_mirrors) { never_worse("brain_mirrors", 1); }
TEST(stale_never_worse_default) { never_worse("default", 1); }
TEST(stale_never_worse_lobster_tunnel) { never_worse("lobster_tunnel", 1); }
TEST(stale_never_worse_clouds_lake) { never_worse("clouds_lake", 1); }

/* The property test can fail: the same paths without the detection (the paper's board)
 * break the promise somewhere. */
TEST(stale_paths_break_the_promise_without_the_check)
{
    int frames, paths;
    char why[300] = "";
    never_worse_on("brain_mirrors", 48, -1, &frames, &paths, why, sizeof why);
    CHECK_MSG(frames > 0, "no frame over the promise without the check: the paths do not test it");
}

/* The frame under Max Work, its start queues and its own schedule (paper's rule). */
typedef struct {
    c5_image img;
    c5_board_stats st;
    uint32_t start[64];
    c5_dsp_sched_result sch;
} mw_frame;

static int maxwork_frame(const int cells[3], mw_frame *m)
{
    c5_ctree_init(&trees[0], 0);
    c5_board_opts o = {.cells = {cells[0], cells[1], cells[2]}, .tree = &trees[0], .start_counts = m->start};
    c5_err err;
    c5_dsp_sched_opts so = {.rule = C5_SPLIT_MOST_LEAVES};
    if (render(&o, &m->img, &m->st) != 0 || c5_dsp_schedule(&trees[0], &so, &m->sch, &err) != 0)
        return -1;
    return 0;
}

static void mw_free(mw_frame *m)
{
    c5_image_free(&m->img);
    c5_dsp_sched_free(&m->sch);
}

/* Follows `sched` with the check on (prev_start: m's own, unless given). */
static int follow(const int cells[3], const mw_frame *m, const int *sched, int len, const uint32_t *prev_start,
                  const c5_stale_thresholds *t, c5_image *img, c5_board_stats *st)
{
    c5_board_opts o = {.cells = {cells[0], cells[1], cells[2]}, .sched = C5_SCHED_EXTERNAL, .schedule = sched,
                       .schedule_len = len, .prev_start = prev_start ? prev_start : m->start,
                       .prev_start_len = cells[0] * cells[1] * cells[2]};
    if (t)
        o.stale = *t;
    return render(&o, img, st);
}

/* Every fetch is the schedule's or Max Work's; a switch is reported whole or not at all. */
static int consistent(const c5_board_stats *st)
{
    if (st->sched_loads + st->sched_fallback != st->fetches)
        return 0;
    if (st->sched_switches)
        return st->switched_at_load >= 0 && (uint64_t)st->switched_at_load <= st->fetches &&
               st->switch_reason != C5_SWITCH_NONE && st->sched_loads == (uint64_t)st->switched_at_load;
    return st->switched_at_load == -1 && st->switch_reason == C5_SWITCH_NONE;
}

TEST(stale_corner_cases)
{
    static const int cells[3] = {3, 3, 3};
    CHECK(load("clouds_lake", 32) == 0); /* cells no ray reaches at this view */
    mw_frame m = {0};
    CHECK(maxwork_frame(cells, &m) == 0);
    CHECK(m.sch.next.len > 4);
    c5_image img;
    c5_board_stats st;

    /* An empty schedule: Max Work's frame, nothing followed, no switch. */
    CHECK(follow(cells, &m, NULL, 0, NULL, NULL, &img, &st) == 0);
    CHECK(same_bits(&img, &m.img));
    CHECK_INT(st.fetches, m.st.fetches);
    CHECK_INT(st.sched_switches, 0);
    CHECK(consistent(&st));
    c5_image_free(&img);

    /* The frame's own schedule: followed to its end, never switched. */
    CHECK(follow(cells, &m, m.sch.next.cells, m.sch.next.len, NULL, NULL, &img, &st) == 0);
    CHECK(same_bits(&img, &m.img));
    CHECK_INT(st.sched_switches, 0);
    CHECK_INT(st.sched_fallback, 0);
    CHECK(st.fetches <= m.st.fetches);
    CHECK(consistent(&st));
    c5_image_free(&img);

    /* Cells that never hold a ray (not in the frame's tree), named many times: every ray
     * waits in a cell the schedule never visits, so Max Work from the first load, which is
     * then Max Work's frame. */
    int in_tree[27] = {0}, empty[64], n_empty = 0;
    for (int i = 0; i < m.sch.next.len; i++)
        in_tree[m.sch.next.cells[i]] = 1;
    for (int c = 0; c < 27; c++)
        if (!in_tree[c])
            for (int r = 0; r < 2 && n_empty < 64; r++)
                empty[n_empty++] = c;
    CHECK_MSG(n_empty >= C5_STALE_SKIP_MIN, "only %d entries of rayless cells at this view", n_empty);
    CHECK(follow(cells, &m, empty, n_empty, NULL, NULL, &img, &st) == 0);
    CHECK(same_bits(&img, &m.img));
    CHECK_INT(st.sched_switches, 1);
    CHECK_INT(st.switch_reason, C5_SWITCH_ORPHANS);
    CHECK_INT(st.switched_at_load, 0);
    CHECK_INT(st.fetches, m.st.fetches);
    CHECK(consistent(&st));
    c5_image_free(&img);

    /* The same entries before the frame's own schedule: passed empty, they switch to Max
     * Work at the next load. */
    int *skips = malloc(sizeof(int) * (size_t)(n_empty + m.sch.next.len));
    memcpy(skips, empty, sizeof(int) * (size_t)n_empty);
    memcpy(skips + n_empty, m.sch.next.cells, sizeof(int) * (size_t)m.sch.next.len);
    CHECK(follow(cells, &m, skips, n_empty + m.sch.next.len, NULL, NULL, &img, &st) == 0);
    free(skips);
    CHECK(same_bits(&img, &m.img));
    CHECK_INT(st.sched_switches, 1);
    CHECK_INT(st.switch_reason, C5_SWITCH_SKIPS);
    CHECK_INT(st.switched_at_load, 1);
    CHECK(consistent(&st));
    c5_image_free(&img);

    /* A schedule naming every cell once: whatever it costs, the same image, every fetch
     * accounted for. */
    int every[27];
    for (int c = 0; c < 27; c++)
        every[c] = c;
    CHECK(follow(cells, &m, every, 27, NULL, NULL, &img, &st) == 0);
    CHECK(same_bits(&img, &m.img));
    CHECK(consistent(&st));
    c5_image_free(&img);

    /* A schedule that runs out (its first three entries): Max Work finishes the frame; a
     * schedule spent is not a switch, unless a signal fired before. */
    CHECK(follow(cells, &m, m.sch.next.cells, 3, NULL, NULL, &img, &st) == 0);
    CHECK(same_bits(&img, &m.img));
    CHECK(st.sched_fallback > 0);
    CHECK(consistent(&st));
    c5_image_free(&img);

    /* A switch on the first load: start queues unlike the previous frame's (all its rays in
     * one other cell): Max Work's frame exactly. */
    uint32_t other[64] = {0};
    int lone = 0;
    for (int c = 0; c < 27; c++)
        if (m.start[c] == 0)
            lone = c;
    other[lone] = 1000;
    CHECK(follow(cells, &m, m.sch.next.cells, m.sch.next.len, other, NULL, &img, &st) == 0);
    CHECK(same_bits(&img, &m.img));
    CHECK_INT(st.sched_switches, 1);
    CHECK_INT(st.switch_reason, C5_SWITCH_START);
    CHECK_INT(st.switched_at_load, 0);
    CHECK_INT(st.sched_loads, 0);
    CHECK_INT(st.fetches, m.st.fetches);
    c5_image_free(&img);

    /* A switch at the schedule's last entry: the own schedule cut before its last entry
     * that still finds rays, and a rayless cell put in its place, leaves those rays in a cell
     * no entry left visits; Max Work finishes the frame. */
    int len = m.sch.next.len, *last = malloc(sizeof(int) * (size_t)len), switched = 0;
    for (int k = len - 1; k > 0 && !switched; k--) {
        memcpy(last, m.sch.next.cells, sizeof(int) * (size_t)k);
        last[k] = empty[0];
        CHECK(follow(cells, &m, last, k + 1, NULL, NULL, &img, &st) == 0);
        CHECK(same_bits(&img, &m.img));
        CHECK(consistent(&st));
        c5_image_free(&img);
        if (st.sched_switches) {
            switched = 1;
            CHECK_INT(st.switch_reason, C5_SWITCH_ORPHANS);
            CHECK_INT(st.sched_loads + st.sched_skipped, k); /* every entry before the last passed */
            CHECK(st.fetches > (uint64_t)st.switched_at_load);
        }
    }
    free(last);
    CHECK(switched);

    /* The DSP's replay says the schedule makes no fewer loads than Max Work on the tree it
     * came from: not followed at all, Max Work's frame. The same with a one-frame-old
     * schedule that lost on the previous frame. */
    c5_stale_plan p = {.valid = 1, .maxwork_loads = (int)m.st.fetches, .sched_loads = (int)m.st.fetches,
                       .lag_loads = -1, .len = m.sch.next.len, .pred = calloc((size_t)m.sch.next.len, 4)};
    for (int i = 0; i < p.len; i++)
        p.pred[i] = 1; /* every entry expected to find rays: nothing unexpected */
    c5_board_opts po = {.cells = {3, 3, 3}, .sched = C5_SCHED_EXTERNAL, .schedule = m.sch.next.cells,
                        .schedule_len = m.sch.next.len, .plan = &p};
    CHECK(render(&po, &img, &st) == 0);
    CHECK(same_bits(&img, &m.img));
    CHECK_INT(st.switch_reason, C5_SWITCH_NO_GAIN);
    CHECK_INT(st.switched_at_load, 0);
    CHECK_INT(st.fetches, m.st.fetches);
    CHECK(consistent(&st));
    c5_image_free(&img);
    /* The ledger: with one frame's allowance banked, the least gain the replay accepts is
     * followed; with nothing banked, only first_risk allowances of gain; a deficit adds to
     * what is asked. */
    int allowance = (int)ceil(1.02 * (double)m.st.fetches) - (int)m.st.fetches;
    if (allowance < 1)
        allowance = 1;
    p.bank = allowance;
    p.sched_loads = (int)m.st.fetches - C5_STALE_GAIN_MIN_LOADS; /* just enough gain ... */
    CHECK(render(&po, &img, &st) == 0);
    CHECK_INT(st.sched_switches, 0);
    c5_image_free(&img);
    for (int bank = allowance - 1; bank >= -2; bank -= 1 + allowance) { /* nothing banked, then a deficit */
        int need = (bank < 0 ? -bank : 0) + C5_STALE_FIRST_RISK * allowance;
        p.bank = bank;
        p.sched_loads = (int)m.st.fetches - need + 1;
        CHECK(render(&po, &img, &st) == 0);
        CHECK_INT(st.switch_reason, C5_SWITCH_LEDGER);
        CHECK_INT(st.switched_at_load, 0);
        CHECK_INT(st.fetches, m.st.fetches);
        CHECK(st.switch_value == need - 1);
        c5_image_free(&img);
        p.sched_loads = (int)m.st.fetches - need;
        CHECK(render(&po, &img, &st) == 0);
        CHECK_INT(st.sched_switches, 0);
        c5_image_free(&img);
    }
    po.stale.first_risk = -1; /* the ledger off: nothing banked, the least gain followed */
    p.sched_loads = (int)m.st.fetches - C5_STALE_GAIN_MIN_LOADS;
    CHECK(render(&po, &img, &st) == 0);
    CHECK_INT(st.sched_switches, 0);
    c5_image_free(&img);
    po.stale.first_risk = 0;
    p.bank = allowance;
    p.lag_loads = (int)m.st.fetches; /* ... but the previous frame's schedule saved nothing */
    CHECK(render(&po, &img, &st) == 0);
    CHECK_INT(st.switch_reason, C5_SWITCH_LAG);
    CHECK_INT(st.fetches, m.st.fetches);
    c5_image_free(&img);
    p.len = 1; /* a replay of another schedule is not used */
    CHECK(render(&po, &img, &st) == 0);
    CHECK_INT(st.sched_switches, 0);
    c5_image_free(&img);
    free(p.pred);

    /* The check off: the same schedules are followed to their end. */
    c5_board_opts o = {.cells = {3, 3, 3}, .sched = C5_SCHED_EXTERNAL, .schedule = empty, .schedule_len = n_empty,
                       .stale_check = -1};
    CHECK(render(&o, &img, &st) == 0);
    CHECK(same_bits(&img, &m.img));
    CHECK_INT(st.sched_switches, 0);
    CHECK_INT(st.sched_skipped, n_empty);
    c5_image_free(&img);
    mw_free(&m);
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
            c5_board_opts o = {.cells = {splits[k][0], splits[k][1], splits[k][2]}, .tree = &trees[0],
                               .node_rays = node_rays};
            c5_image img, img2;
            c5_board_stats st, st2;
            c5_err err;
            c5_dsp_sched_result sch;
            c5_stale_plan p;
            c5_dsp_sched_opts so = {.rule = C5_SPLIT_MOST_LEAVES};
            CHECK(render(&o, &img, &st) == 0);
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
