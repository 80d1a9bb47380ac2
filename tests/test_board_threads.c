/* The host's helper threads change no bit (rtl_model/board_threads.c): every built-in scene
 * in several splits, keys and queues, at 2 and 7 threads and with every item replayed from
 * a helper's log, against one thread in every counter, cycle count and the image; and the
 * replay of a recorded run against the run itself (proc/ray_log.h). */
#include <stdlib.h>
#include <string.h>

#include "board.h"
#include "board_equal.h"
#include "builtin_scenes.h"
#include "harness.h"
#include "ray_log.h"
#include "scene_load.h"

static int render(const c5_scene *s, const c5_supervol *sv, c5_board_opts o, c5_image *img, c5_board_stats *st)
{
    c5_err err;
    if (c5_board_render(s, sv, 0, &o, img, st, &err) != 0) {
        c5t_failf(__FILE__, __LINE__, "render: %s", err.msg);
        return -1;
    }
    return 0;
}

TEST(board_threads_same_bits_every_builtin_scene)
{
    const c5_board_opts variants[] = {
        {.cells = {2, 2, 2}},
        {.cells = {0, 0, 0}}, /* the fewest cells (one for most scenes): the longest visits */
        {.cells = {3, 2, 4}, .key = C5_KEY_FIFO},
        {.cells = {2, 2, 2}, .queue_capacity = 8}, /* the sorter full: spills behind the items */
        {.cells = {2, 2, 2}, .queue_model = C5_QUEUE_CYCLE},
    };
    const struct {
        int threads, replay_all;
    } runs[] = {{2, 0}, {7, 0}, {2, 1}, {3, 1}};
    uint64_t replayed_all = 0, items_all = 0;
    for (const c5_builtin_scene *bs = c5_builtin_scenes; bs->name; bs++) {
        c5_scene s;
        c5_supervol sv;
        /* 80x80, and 8x8: too few pixels and rays to hand out, the board's thread runs alone */
        CHECK(c5t_load_scene(bs->name, bs == c5_builtin_scenes ? 8 : 80, &s, &sv) == 0);
        for (size_t v = 0; v < sizeof variants / sizeof variants[0]; v++) {
            c5_image ref;
            c5_board_stats st0;
            if (render(&s, &sv, variants[v], &ref, &st0) != 0)
                break;
            CHECK_INT(st0.helper_runs, 0);
            for (size_t k = 0; k < sizeof runs / sizeof runs[0]; k++) {
                c5_board_opts o = variants[v];
                o.threads = runs[k].threads;
                o.threads_replay_all = runs[k].replay_all;
                c5_image img;
                c5_board_stats st;
                if (render(&s, &sv, o, &img, &st) != 0)
                    break;
                char what[128];
                snprintf(what, sizeof what, "%s variant %zu, %d threads%s", bs->name, v, runs[k].threads,
                         runs[k].replay_all ? ", every item replayed" : "");
                CHECK(c5t_board_stats_equal(what, &st0, &st) == 0);
                CHECK_MSG(c5t_same_image(&ref, &img), "%s: images differ", what);
                /* a run is replayed at most once: each pop, and each pixel's eye ray */
                uint64_t runs_made = st.queue_pops + (uint64_t)s.render.width * (uint64_t)s.render.height;
                CHECK_MSG(st.helper_runs <= runs_made, "%s: %llu replays of %llu runs", what,
                          (unsigned long long)st.helper_runs, (unsigned long long)runs_made);
                if (runs[k].replay_all) {
                    replayed_all += st.helper_runs;
                    items_all += runs_made;
                }
                c5_image_free(&img);
            }
            c5_image_free(&ref);
        }
        c5_supervol_free(&sv);
    }
    /* with every item replayed, most runs are replays (the rest: rays queued during a visit,
     * and visits too small to hand out) */
    CHECK_MSG(replayed_all * 2 > items_all, "%llu of %llu runs replayed", (unsigned long long)replayed_all,
              (unsigned long long)items_all);
}

/* ---- one run recorded and replayed ------------------------------------------------ */

typedef struct {
    c5_bray q[16];
    int nq;
    int64_t fb[3];
    int nd;
} sink;

/* Field by field: padding bytes are not part of a ray. */
static int same_ray(const c5_bray *a, const c5_bray *b)
{
    for (int i = 0; i < 3; i++)
        if (a->pos[i] != b->pos[i] || a->dir[i] != b->dir[i] || a->rgb[i] != b->rgb[i])
            return 0;
    return a->u == b->u && a->v == b->v && a->lifetime == b->lifetime && a->w == b->w && a->opa == b->opa &&
           a->gen == b->gen && a->node == b->node && a->cell == b->cell && a->type == b->type && a->surf == b->surf &&
           a->shadow == b->shadow;
}

static void s_enqueue(void *ctx, const c5_bray *r)
{
    sink *k = ctx;
    if (k->nq < 16)
        k->q[k->nq] = *r;
    k->nq++;
}

static void s_deliver(void *ctx, uint32_t u, uint32_t v, const int64_t rgb[3])
{
    sink *k = ctx;
    for (int c = 0; c < 3; c++)
        k->fb[c] += rgb[c] + (int64_t)u * 7 + (int64_t)v * 13;
    k->nd++;
}

/* A recorded run replayed on a processor whose cache holds what the direct run's held: the
 * same rays handed on, colours delivered, cache hits and misses and counters. Cache runs
 * longer than a log entry holds (C5_RLOG_RUN_MAX) split. */
TEST(ray_log_replay_is_the_run)
{
    c5_ray_rec rec = {0};
    for (int i = 0; i < 70000; i++)
        c5_rlog_access(&rec, 0x123456789aull);
    c5_rlog_access(&rec, 5);
    CHECK_INT(rec.n_acc, 3);
    CHECK_INT(rec.acc[0] >> C5_RLOG_TAG_BITS, C5_RLOG_RUN_MAX);
    CHECK_INT(rec.acc[1] >> C5_RLOG_TAG_BITS, 70000 - C5_RLOG_RUN_MAX);
    c5_rlog_free(&rec);

    c5_scene s;
    c5_supervol sv;
    CHECK(c5t_load_scene("brain_mirrors", 32, &s, &sv) == 0);
    c5_board_opts o = {.cells = {1, 1, 1}};
    c5_frame_regs r;
    c5_cells cells;
    c5_rdram mem = {.cell = -1};
    c5_err err;
    uint8_t nz[256];
    int ok = c5_regs_build(&s, &sv, &o, &r, &err) == 0;
    for (int i = 0; i < 256; i++)
        nz[i] = ok && r.tf[i][3] > 0;
    if (!ok || c5_cells_init(&cells, &sv, o.cells, nz, &err) != 0 || c5_rdram_view(&mem, &cells, &sv, 0, &err) != 0) {
        c5t_failf(__FILE__, __LINE__, "set-up: %s", err.msg);
        c5_supervol_free(&sv);
        return;
    }
    sink direct = {0}, replayed = {0};
    c5_proc p, q, w;
    c5_proc_init(&p, &r, &cells, &mem, (c5_proc_io){&direct, s_enqueue, s_deliver, NULL});
    c5_proc_init(&q, &r, &cells, &mem, (c5_proc_io){&replayed, s_enqueue, s_deliver, NULL});
    p.active = q.active = 0;
    int runs = 0;
    for (int k = 0; k < 200; k++) { /* rays through the volume, each run both ways */
        c5_bray ray = {.w = C5_ONE15, .type = C5_RAY_EYE, .node = C5_NODE_NONE, .cell = 0,
                       .lifetime = C5_LIFE_NONE, .u = (uint32_t)k, .v = 1};
        for (int a = 0; a < 3; a++)
            ray.pos[a] = ((int64_t)(sv.dims[a] / 2) << C5_POS_F) + (int64_t)((k * (a + 3)) % 11 - 5) * 1000;
        ray.dir[0] = 9000 - 90 * k, ray.dir[1] = 12000, ray.dir[2] = -6000 + 60 * k;
        c5_bray a = ray;
        c5_proc_run(&p, &a);
        c5_rlog_recorder(&w, &q, &rec);
        c5_rlog_begin(&rec);
        c5_bray b = ray;
        c5_proc_run(&w, &b);
        size_t bytes = c5_rlog_size(&rec);
        uint64_t *log = malloc(bytes);
        CHECK(log && !rec.oom);
        if (!log)
            break;
        c5_rlog_write(&rec, log);
        c5_rlog_replay(&q, log);
        free(log);
        /* the recorder's counters, as a helper's, join the board's processor */
        uint64_t *dst = (uint64_t *)&q.st;
        const uint64_t *src = (const uint64_t *)&w.st;
        for (size_t i = 0; i < sizeof q.st / sizeof(uint64_t); i++)
            dst[i] += src[i];
        runs++;
    }
    CHECK_INT(runs, 200);
    CHECK(p.st.samples > 1000 && p.st.cache_misses > 0 && p.st.cache_hits > 0);
    CHECK(!memcmp(&p.st, &q.st, sizeof p.st));
    CHECK(!memcmp(p.cache_tag, q.cache_tag, sizeof p.cache_tag));
    CHECK_INT(direct.nq, replayed.nq);
    CHECK_INT(direct.nd, replayed.nd);
    CHECK(!memcmp(direct.fb, replayed.fb, sizeof direct.fb));
    for (int i = 0; i < direct.nq && i < 16; i++)
        CHECK_MSG(same_ray(&direct.q[i], &replayed.q[i]), "ray %d handed on differs", i);
    c5_rlog_free(&rec);
    c5_rdram_free(&mem);
    c5_cells_free(&cells);
    c5_supervol_free(&sv);
}
