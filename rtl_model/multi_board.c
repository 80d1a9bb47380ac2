/* Several boards on one super volume: the cell assignment, the round-by-round exchange with
 * its modelled cost, the summed frame buffer and statistics (multi_board.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mb_async.h"
#include "model_limits.h"
#include "multi_board.h"

/* 1 GbE: 1000BASE-T, 125 MB/s; 50 us as above. 10 GbE: 1.25 GB/s; 15 us, MPI over TCP on
 * 10 GbE is of that order. PCIe 4.0 x16: 16 GT/s x 16 lanes x 128/130 / 8 bits = 31.5 GB/s;
 * 1 us, a switch hop and a DMA doorbell. */
const c5_link_preset c5_link_presets[] = {
    {"1gbe", 125e6, 50e-6},
    {"10gbe", 1.25e9, 15e-6},
    {"pcie4x16", 31.5e9, 1e-6},
    {NULL, 0, 0},
};

const c5_link_preset *c5_link_preset_find(const char *name)
{
    for (const c5_link_preset *p = c5_link_presets; p->name; p++)
        if (!strcmp(p->name, name))
            return p;
    return NULL;
}

const char *c5_mb_mode_name(c5_mb_mode m) { return m == C5_MB_ROUNDS ? "rounds" : "async"; }

c5_mb_mode c5_mb_mode_parse(const char *s)
{
    return !strcmp(s, "async") ? C5_MB_ASYNC : !strcmp(s, "rounds") ? C5_MB_ROUNDS : 0;
}

const char *c5_assign_name(c5_assign_rule r)
{
    return r == C5_ASSIGN_SLAB ? "slab" : r == C5_ASSIGN_MOD ? "mod" : r == C5_ASSIGN_TREE ? "tree"
           : r == C5_ASSIGN_LOAD ? "load" : "kd";
}

c5_assign_rule c5_assign_parse(const char *s)
{
    return !strcmp(s, "slab") ? C5_ASSIGN_SLAB : !strcmp(s, "kd") ? C5_ASSIGN_KD : !strcmp(s, "mod") ? C5_ASSIGN_MOD
           : !strcmp(s, "tree") ? C5_ASSIGN_TREE : !strcmp(s, "load") ? C5_ASSIGN_LOAD : 0;
}

/* The axis with the most cells of the box [lo, hi); ties to the later axis (z, the volume's
 * slowest), so that slabs and the first k-d cut agree on cubes. */
static int longest(const int lo[3], const int hi[3])
{
    int a = 2;
    for (int i = 1; i >= 0; i--)
        if (hi[i] - lo[i] > hi[a] - lo[a])
            a = i;
    return a;
}

static void kd(const int n[3], const int lo[3], const int hi[3], int b0, int nb, uint16_t *owner)
{
    int a = longest(lo, hi), ext = hi[a] - lo[a];
    if (nb == 1 || ext == 1) {
        for (int z = lo[2]; z < hi[2]; z++)
            for (int y = lo[1]; y < hi[1]; y++)
                for (int x = lo[0]; x < hi[0]; x++)
                    owner[x + n[0] * (y + n[1] * z)] = (uint16_t)b0;
        return;
    }
    /* Cut the longest axis in the middle and share the boards out in proportion to the
     * cells on each side, at least one and at most one a cell on each. */
    int cut = lo[a] + ext / 2;
    long slice = (long)(hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]) / ext;
    long cl = slice * (cut - lo[a]), cr = slice * (hi[a] - cut);
    long left = (2L * nb * (cut - lo[a]) + ext) / (2L * ext);
    left = left > cl ? cl : left;
    left = left < nb - cr ? nb - cr : left;
    left = left < 1 ? 1 : left > nb - 1 ? nb - 1 : left;
    int h1[3] = {hi[0], hi[1], hi[2]}, l2[3] = {lo[0], lo[1], lo[2]};
    h1[a] = cut;
    l2[a] = cut;
    kd(n, lo, h1, b0, (int)left, owner);
    kd(n, l2, hi, b0 + (int)left, nb - (int)left, owner);
}

/* The k-d split on cell weights w: the longest axis cut where the weight on each side is
 * closest to its boards' share (half the boards on the left), each side keeping at least one
 * cell a board. */
static void kd_weighted(const int n[3], const int lo[3], const int hi[3], int b0, int nb, const uint64_t *w,
                        uint16_t *owner)
{
    int a = longest(lo, hi), ext = hi[a] - lo[a];
    if (nb == 1 || ext == 1) {
        kd(n, lo, hi, b0, 1, owner);
        return;
    }
    long slice = (long)(hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]) / ext;
    int left = nb / 2, best = -1;
    double total = 0, best_d = 0;
    for (int z = lo[2]; z < hi[2]; z++)
        for (int y = lo[1]; y < hi[1]; y++)
            for (int x = lo[0]; x < hi[0]; x++)
                total += (double)w[x + n[0] * (y + n[1] * z)];
    double acc = 0;
    for (int cut = lo[a] + 1; cut < hi[a]; cut++) {
        int p[3];
        for (p[0] = lo[0]; p[0] < hi[0]; p[0]++) /* the slice at cut - 1 */
            for (p[1] = lo[1]; p[1] < hi[1]; p[1]++)
                for (p[2] = lo[2]; p[2] < hi[2]; p[2]++)
                    if (p[a] == cut - 1)
                        acc += (double)w[p[0] + n[0] * (p[1] + n[1] * p[2])];
        if (slice * (cut - lo[a]) < left || slice * (hi[a] - cut) < nb - left)
            continue;
        double d = fabs(acc * nb - total * left);
        if (best < 0 || d < best_d)
            best = cut, best_d = d;
    }
    if (best < 0) { /* too few cells for half the boards on each side: the plain rule */
        kd(n, lo, hi, b0, nb, owner);
        return;
    }
    int h1[3] = {hi[0], hi[1], hi[2]}, l2[3] = {lo[0], lo[1], lo[2]};
    h1[a] = best;
    l2[a] = best;
    kd_weighted(n, lo, h1, b0, left, w, owner);
    kd_weighted(n, l2, hi, b0 + left, nb - left, w, owner);
}

int c5_mb_assign_tree(const int n[3], int boards, const uint64_t *moves, uint16_t *owner, c5_err *err)
{
    if (boards < 1 || boards > C5_MB_MAX_BOARDS)
        return c5_fail(err, "boards: %d is outside 1..%d", boards, C5_MB_MAX_BOARDS);
    int count = n[0] * n[1] * n[2];
    uint64_t *w = calloc((size_t)count, sizeof *w);
    if (!w)
        return c5_fail(err, "out of memory");
    for (int c = 0; c < count; c++) {
        w[c] = 1;
        for (int a = 0; a < count; a++)
            w[c] += moves[(size_t)a * count + c];
    }
    int lo[3] = {0, 0, 0};
    kd_weighted(n, lo, n, 0, boards, w, owner);
    uint64_t load[C5_MB_MAX_BOARDS] = {0}, conn[C5_MB_MAX_BOARDS], cap = 0;
    int cells[C5_MB_MAX_BOARDS] = {0};
    for (int c = 0; c < count; c++)
        load[owner[c]] += w[c], cells[owner[c]]++;
    uint64_t total = 0, heaviest = 0;
    for (int k = 0; k < boards; k++)
        cap = load[k] > cap ? load[k] : cap, total += load[k];
    for (int c = 0; c < count; c++)
        heaviest = w[c] > heaviest ? w[c] : heaviest;
    /* Cells move to the board they trade most rays with: fewer rays cross boards, and no
     * board ends with more weight than the heaviest after the split and 10 %, or the mean and
     * one cell. A bounded number of passes. */
    cap += cap / 10;
    if (total / (uint64_t)boards + heaviest > cap)
        cap = total / (uint64_t)boards + heaviest;
    for (int pass = 0; pass < 8; pass++) {
        int moved = 0;
        for (int c = 0; c < count; c++) {
            int k0 = owner[c], best = k0;
            if (cells[k0] == 1)
                continue;
            memset(conn, 0, sizeof conn);
            for (int d = 0; d < count; d++)
                if (d != c)
                    conn[owner[d]] += moves[(size_t)c * count + d] + moves[(size_t)d * count + c];
            for (int k = 0; k < boards; k++)
                if (k != k0 && conn[k] > conn[best] && load[k] + w[c] <= cap)
                    best = k;
            if (best != k0) {
                owner[c] = (uint16_t)best;
                load[k0] -= w[c], load[best] += w[c];
                cells[k0]--, cells[best]++;
                moved++;
            }
        }
        if (!moved)
            break;
    }
    free(w);
    return 0;
}

int c5_mb_assign_load(const int n[3], int boards, const uint64_t *cost, uint16_t *owner, c5_err *err)
{
    if (boards < 1 || boards > C5_MB_MAX_BOARDS)
        return c5_fail(err, "boards: %d is outside 1..%d", boards, C5_MB_MAX_BOARDS);
    int count = n[0] * n[1] * n[2];
    uint64_t *w = calloc((size_t)(count > 0 ? count : 1), sizeof *w);
    if (!w)
        return c5_fail(err, "out of memory");
    for (int c = 0; c < count; c++) /* + 1: a cell nobody loaded still goes somewhere */
        w[c] = cost[c] + 1;
    int lo[3] = {0, 0, 0};
    kd_weighted(n, lo, n, 0, boards, w, owner);
    /* The k-d blocks balance only as finely as their cuts: then the busiest board hands a cell
     * to a neighbouring board (a face away) while that lowers the busiest's cycles without
     * making the other busier than it was; a bounded number of moves. */
    uint64_t load[C5_MB_MAX_BOARDS] = {0};
    int cells[C5_MB_MAX_BOARDS] = {0};
    for (int c = 0; c < count; c++)
        load[owner[c]] += w[c], cells[owner[c]]++;
    for (int move = 0; move < count; move++) {
        int big = 0;
        for (int k = 1; k < boards; k++)
            if (load[k] > load[big])
                big = k;
        int best_c = -1, best_k = -1;
        uint64_t best_peak = load[big];
        for (int c = 0; c < count && cells[big] > 1; c++) {
            if (owner[c] != big)
                continue;
            int p[3] = {c % n[0], c / n[0] % n[1], c / (n[0] * n[1])};
            for (int d = 0; d < 6; d++) {
                int q[3] = {p[0], p[1], p[2]};
                q[d / 2] += d % 2 ? 1 : -1;
                if (q[d / 2] < 0 || q[d / 2] >= n[d / 2])
                    continue;
                int k = owner[q[0] + n[0] * (q[1] + n[1] * q[2])];
                uint64_t peak = load[k] + w[c] > load[big] - w[c] ? load[k] + w[c] : load[big] - w[c];
                if (k != big && peak < best_peak)
                    best_peak = peak, best_c = c, best_k = k;
            }
        }
        if (best_c < 0)
            break;
        owner[best_c] = (uint16_t)best_k;
        load[big] -= w[best_c], load[best_k] += w[best_c];
        cells[big]--, cells[best_k]++;
    }
    free(w);
    return 0;
}

void c5_mb_history_free(c5_mb_history *h)
{
    free(h->moves);
    free(h->cost);
    memset(h, 0, sizeof *h);
}

int c5_mb_assign(c5_assign_rule rule, const int n[3], int boards, uint16_t *owner, c5_err *err)
{
    if (boards < 1 || boards > C5_MB_MAX_BOARDS)
        return c5_fail(err, "boards: %d is outside 1..%d", boards, C5_MB_MAX_BOARDS);
    long count = (long)n[0] * n[1] * n[2];
    if (rule == C5_ASSIGN_MOD) {
        for (long c = 0; c < count; c++)
            owner[c] = (uint16_t)(c % boards);
    } else if (rule == C5_ASSIGN_SLAB) {
        int zero[3] = {0, 0, 0}, a = longest(zero, n), o1 = a == 0 ? 1 : 0, o2 = a == 2 ? 1 : 2;
        for (int z = 0; z < n[2]; z++)
            for (int y = 0; y < n[1]; y++)
                for (int x = 0; x < n[0]; x++) {
                    int p[3] = {x, y, z};
                    long i = ((long)p[a] * n[o2] + p[o2]) * n[o1] + p[o1]; /* its place, axis a slowest */
                    owner[x + n[0] * (y + n[1] * z)] = (uint16_t)(i * boards / count);
                }
    } else { /* kd, and the tree rule without a previous frame */
        int lo[3] = {0, 0, 0};
        kd(n, lo, n, 0, boards, owner);
    }
    return 0;
}

void c5_mb_split(const c5_board_opts *o, const c5_supervol *sv, int cells[3])
{
    for (int a = 0; a < 3; a++)
        cells[a] = o->cells[a] < 1 ? 0 : o->cells[a];
    c5_model_auto_split(sv->dims, cells);
    if (c5_supervol_empty(sv))
        cells[0] = cells[1] = cells[2] = 1;
}

/* What a board tells the others after each exchange. */
typedef struct {
    uint64_t busy;            /* its cycles since the previous exchange */
    uint64_t sent, received;  /* packets this exchange */
} round_rec;

typedef struct {
    const c5_mb_transport *t;
    c5_mb_stats *ms;
    uint64_t last_cycles;
    round_rec *all;           /* [boards] */
} mb_link;

static uint64_t link_cycles(const c5_mb_stats *ms, uint64_t packets_out, uint64_t packets_in)
{
    uint64_t most = packets_out > packets_in ? packets_out : packets_in;
    return (uint64_t)llround(ms->link_latency_s * C5_MB_CLOCK_HZ) +
           (uint64_t)ceil((double)(most * C5_PACKET_BYTES) / ms->link_bw * C5_MB_CLOCK_HZ);
}

/* c5_board_link.exchange: the packets across, then every board's round figures to every
 * board, which all turn into the same modelled round time and the same verdict. */
static int mb_exchange(void *ctx, const uint8_t (*out)[C5_PACKET_BYTES], const uint16_t *dest, size_t n_out,
                       const c5_board_stats *so_far, const uint8_t (**in)[C5_PACKET_BYTES], size_t *n_in,
                       c5_err *err)
{
    mb_link *l = ctx;
    c5_mb_stats *ms = l->ms;
    if (l->t->alltoall(l->t->ctx, out, dest, n_out, in, n_in, err) != 0)
        return -1;
    round_rec me = {so_far->cycles - l->last_cycles, n_out, *n_in};
    l->last_cycles = so_far->cycles;
    if (l->t->allgather(l->t->ctx, &me, sizeof me, l->all, err) != 0)
        return -1;
    uint64_t busy = 0, port = 0, moved = 0;
    for (int k = 0; k < ms->boards; k++) {
        const round_rec *r = &l->all[k];
        uint64_t lc = link_cycles(ms, r->sent, r->received);
        busy = r->busy > busy ? r->busy : busy;
        port = lc > port ? lc : port;
        moved += r->sent;
        ms->board[k].busy_cycles += r->busy;
        ms->board[k].link_cycles += lc;
        ms->board[k].packets_sent += r->sent;
        ms->board[k].packets_received += r->received;
    }
    ms->frame_cycles += busy + port;
    ms->link_packets += moved;
    ms->rounds++;
    return moved > 0;
}

void c5_board_stats_add(c5_board_stats *a, const c5_board_stats *b)
{
#define ADD(x) a->x += b->x
#define MAX(x) a->x = b->x > a->x ? b->x : a->x
    for (int t = 0; t < C5_RAY_TYPES; t++)
        ADD(rays[t]);
    for (int e = 0; e < C5_END_KINDS; e++)
        ADD(ends[e]);
    ADD(samples); ADD(samples_leaped); ADD(cycles); ADD(cycles_process); ADD(cycles_fetch); ADD(board_s);
    ADD(fetches); ADD(fetch_bytes); ADD(bus_packets); ADD(spills); ADD(queue_pops); ADD(cache_hits);
    ADD(cache_misses); ADD(saturations); ADD(sched_loads); ADD(sched_skipped); ADD(sched_fallback);
    ADD(sched_switches); ADD(shadow_ops); ADD(node_count_ops); ADD(tree_tags); ADD(tree_reads); ADD(tree_writes);
    ADD(tree_wall_s); ADD(wall_s); ADD(helper_runs); ADD(helper_wakes); ADD(link_sent); ADD(link_received);
    ADD(link_rounds); ADD(cycles_eye_owner); ADD(cycles_idle); ADD(resident_loads);
    MAX(queue_max); MAX(last_end); MAX(tree_nodes); MAX(tree_slots); MAX(tree_demand_nodes); MAX(tree_demand_slots);
    MAX(tree_demand_slots6);
#undef ADD
#undef MAX
    a->tree_overflow |= b->tree_overflow;
    a->stages.gradients |= b->stages.gradients;
    a->stages.shadow |= b->stages.shadow;
    a->stages.reflect |= b->stages.reflect;
    a->stages.refract |= b->stages.refract;
    a->stages.scheduling |= b->stages.scheduling;
    a->cells = b->cells;
}

static void finish_stats(c5_mb_stats *ms)
{
    uint64_t most = 0, all = 0;
    for (int k = 0; k < ms->boards; k++) {
        c5_mb_board *b = &ms->board[k];
        b->idle_cycles = ms->frame_cycles - b->busy_cycles - (ms->mode == C5_MB_ROUNDS ? b->link_cycles : 0);
        most = b->busy_cycles > most ? b->busy_cycles : most;
        all += b->busy_cycles;
    }
    ms->balance = most ? (double)all / ms->boards / (double)most : 1;
    ms->link_bytes = ms->link_packets * C5_PACKET_BYTES;
    ms->frame_s = (double)ms->frame_cycles / C5_MB_CLOCK_HZ;
}

void c5_mb_add(c5_mb_stats *sum, const c5_mb_stats *f)
{
    int first = sum->boards == 0;
    if (first) {
        sum->boards = f->boards;
        sum->mode = f->mode;
        sum->assign = f->assign;
        sum->link_bw = f->link_bw;
        sum->link_latency_s = f->link_latency_s;
    }
    sum->rounds += f->rounds;
    sum->exchanges += f->exchanges;
    sum->frame_cycles += f->frame_cycles;
    sum->link_packets += f->link_packets;
    for (int k = 0; k < f->boards; k++) {
        c5_mb_board *a = &sum->board[k];
        const c5_mb_board *b = &f->board[k];
        a->cells = b->cells;
        a->busy_cycles += b->busy_cycles;
        a->link_cycles += b->link_cycles;
        a->packets_sent += b->packets_sent;
        a->packets_received += b->packets_received;
        a->fetches += b->fetches;
        a->fetch_bytes += b->fetch_bytes;
        a->rays_processed += b->rays_processed;
        a->resident_loads += b->resident_loads;
    }
    if (first)
        sum->sum = f->sum;
    else
        c5_board_stats_add(&sum->sum, &f->sum);
    sum->sum.cycles = sum->frame_cycles;
    finish_stats(sum);
    sum->sum.board_s = sum->frame_s;
}

/* The summed frame buffer into the image, clamped to frame_acc's 32 bits as one board does. */
static int to_image(const c5_scene *s, const uint64_t *acc, c5_image *out, uint64_t *saturations, c5_err *err)
{
    if (c5_image_alloc(out, s->render.width, s->render.height, err) != 0)
        return -1;
    size_t n = (size_t)s->render.width * (size_t)s->render.height * 3;
    for (size_t i = 0; i < n; i++) {
        uint64_t v = acc[i];
        if (v > UINT32_MAX) {
            v = UINT32_MAX;
            (*saturations)++;
        }
        out->rgb[i] = c5_rgb_float(v);
    }
    return 0;
}

int c5_mb_render(const c5_scene *s, const c5_supervol *sv, int frame, const c5_board_opts *base,
                 const c5_board_out *keep, const c5_mb_opts *mo, const c5_mb_transport *t, c5_image *out,
                 c5_mb_stats *ms, c5_err *err)
{
    memset(ms, 0, sizeof *ms);
    int nb = t->size;
    if (nb < 1 || nb > C5_MB_MAX_BOARDS)
        return c5_fail(err, "boards: %d is outside 1..%d", nb, C5_MB_MAX_BOARDS);
    ms->boards = nb;
    ms->mode = mo->mode ? mo->mode : C5_MB_ASYNC;
    ms->assign = mo->assign ? mo->assign : C5_ASSIGN_KD;
    ms->link_bw = mo->link_bw > 0 ? mo->link_bw : C5_LINK_BW_DEFAULT;
    ms->link_latency_s = mo->link_latency_s > 0 ? mo->link_latency_s : mo->link_latency_s < 0 ? 0 : C5_LINK_LATENCY_DEFAULT;
    int n[3];
    c5_mb_split(base, sv, n);
    int count = n[0] * n[1] * n[2];
    size_t nacc = (size_t)s->render.width * (size_t)s->render.height * 3;
    uint16_t *owner = malloc((size_t)count * sizeof *owner);
    uint64_t *acc = malloc(nacc * sizeof *acc);
    round_rec *all = malloc((size_t)nb * sizeof *all);
    c5_board_stats *every = malloc((size_t)nb * sizeof *every);
    uint32_t *moves = NULL;
    uint64_t *moves64 = NULL, *cost = NULL;
    int rc = -1;
    if (!owner || !acc || !all || !every) {
        c5_fail(err, "out of memory for %d boards", nb);
        goto done;
    }
    c5_mb_history *h = ms->assign == C5_ASSIGN_TREE && count <= C5_MB_TREE_MAX_CELLS ? mo->history : NULL;
    c5_mb_history *hl = ms->assign == C5_ASSIGN_LOAD ? mo->history : NULL;
    if (h && h->cells == count && h->moves ? c5_mb_assign_tree(n, nb, h->moves, owner, err) != 0
        : hl && hl->cells == count && hl->cost ? c5_mb_assign_load(n, nb, hl->cost, owner, err) != 0
                                               : c5_mb_assign(ms->assign, n, nb, owner, err) != 0)
        goto done;
    if (hl && !(cost = malloc((size_t)count * sizeof *cost))) {
        c5_fail(err, "out of memory for the load rule's %d cells", count);
        goto done;
    }
    size_t nmoves = (size_t)count * (size_t)count;
    if (h && (!(moves = malloc(nmoves * sizeof *moves)) || !(moves64 = malloc(nmoves * sizeof *moves64)))) {
        c5_fail(err, "out of memory for the tree rule's %d x %d table", count, count);
        goto done;
    }
    for (int c = 0; c < count; c++)
        ms->board[owner[c]].cells++;
    mb_link ml = {t, ms, 0, all};
    c5_mb_async as;
    int async = ms->mode == C5_MB_ASYNC && nb > 1;
    if (async && c5_mb_async_init(&as, t, ms, err) != 0)
        goto done;
    c5_board_link link = {.ctx = &ml, .self = t->rank, .boards = nb, .owner = owner, .exchange = mb_exchange};
    if (async)
        link = (c5_board_link){.ctx = &as, .self = t->rank, .boards = nb, .owner = owner,
                               .lookahead = as.lookahead, .exchange_async = c5_mb_async_exchange,
                               .reports = c5_mb_async_reports};
    c5_board_opts o = *base;
    memcpy(o.cells, n, sizeof o.cells);
    o.link = nb > 1 ? &link : NULL;
    c5_board_out k = keep ? *keep : (c5_board_out){0};
    k.cell_cycles = cost;
    k.frame_acc = acc;
    k.moves = moves;
    c5_board_stats mine;
    c5_image img;
    int rendered = c5_board_render_keep(s, sv, frame, &o, &k, &img, &mine, err);
    uint64_t port = async ? (as.tx_busy > as.rx_busy ? as.tx_busy : as.rx_busy) : 0, *ports = NULL;
    if (async) {
        ms->exchanges = as.exchanges;
        c5_mb_async_free(&as);
    }
    if (rendered != 0)
        goto done;
    c5_image_free(&img);
    if (nb == 1) {
        ms->frame_cycles = mine.cycles;
        ms->board[0].busy_cycles = mine.cycles;
    }
    /* Every board's statistics to every board, the frame buffers added. */
    if (t->allgather(t->ctx, &mine, sizeof mine, every, err) != 0 || t->sum_u64(t->ctx, acc, nacc, err) != 0)
        goto done;
    if (async) {
        if (!(ports = malloc((size_t)nb * sizeof *ports))) {
            c5_fail(err, "out of memory for %d boards", nb);
            goto done;
        }
        if (t->allgather(t->ctx, &port, sizeof port, ports, err) != 0) {
            free(ports);
            goto done;
        }
        /* Credit recovery ends the frame: the last board to run out of work returns the last
         * credit to board 0 (a latency), which announces the end (another). */
        uint64_t last = 0, detect = 2 * (uint64_t)llround(ms->link_latency_s * C5_MB_CLOCK_HZ);
        for (int b = 0; b < nb; b++) {
            const c5_board_stats *e = &every[b];
            last = e->last_end > last ? e->last_end : last;
            ms->board[b].busy_cycles = e->cycles_process + e->cycles_fetch;
            ms->board[b].link_cycles = (ports[b] + C5_MB_TICKS - 1) / C5_MB_TICKS;
            ms->board[b].packets_sent = e->link_sent;
            ms->board[b].packets_received = e->link_received;
            ms->board[b].resident_loads = e->resident_loads;
            ms->link_packets += e->link_sent;
        }
        free(ports);
        ms->frame_cycles = last + detect;
    }
    ms->sum = every[0];
    for (int k = 0; k < nb; k++) {
        if (k)
            c5_board_stats_add(&ms->sum, &every[k]);
        ms->board[k].fetches = every[k].fetches;
        ms->board[k].fetch_bytes = every[k].fetch_bytes;
        ms->board[k].rays_processed = every[k].queue_pops;
    }
    if (h) { /* this frame's traffic of every board, for the next frame's assignment */
        for (size_t i = 0; i < nmoves; i++)
            moves64[i] = moves[i];
        if (t->sum_u64(t->ctx, moves64, nmoves, err) != 0)
            goto done;
        free(h->moves);
        h->moves = moves64;
        moves64 = NULL;
        h->cells = count;
    }
    if (hl) { /* every board's cycles per cell, for the next frame's assignment */
        if (t->sum_u64(t->ctx, cost, (size_t)count, err) != 0)
            goto done;
        free(hl->cost);
        hl->cost = cost;
        cost = NULL;
        hl->cells = count;
    }
    uint64_t clamped = 0; /* one board clamped its own buffer, counted in its saturations */
    if (to_image(s, acc, out, &clamped, err) != 0)
        goto done;
    if (nb > 1)
        ms->sum.saturations += clamped;
    finish_stats(ms);
    ms->sum.cycles = ms->frame_cycles;
    ms->sum.board_s = ms->frame_s;
    rc = 0;
done:
    free(owner);
    free(acc);
    free(all);
    free(every);
    free(moves);
    free(moves64);
    free(cost);
    return rc;
}
