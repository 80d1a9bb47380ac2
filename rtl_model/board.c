/* The board: the DSP (eye rays, SDRAM ray queues, the scheduler, the frame buffer), the
 * RDRAM fetches, the active cell's visit (its eDRAM: board_edram.c) and the processor, with
 * the frame's cycle budget (board.h, docs/board-model.md). */
#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "board_internal.h"
#include "c5_layouts.h"
#include "camera.h"
#include "cell_store.h"
#include "clock.h"
#include "geom.h"
#include "ledger.h"
#include "model_limits.h"
#include "taps.h"

#define RDRAM_BW 800e6

int c5_bd_grow_packets(uint8_t (**pk)[C5_PACKET_BYTES], uint32_t **shadow, size_t cap)
{
    void *p = realloc(*pk, cap * C5_PACKET_BYTES);
    if (!p)
        return -1;
    *pk = p;
    void *s = realloc(*shadow, cap * sizeof **shadow);
    if (!s)
        return -1;
    *shadow = s;
    return 0;
}

static int push_sdram(c5_bd *b, int cell, const uint8_t pk[C5_PACKET_BYTES], uint32_t shadow)
{
    c5_sdram_queue *q = &b->q[cell];
    if (q->n == q->cap) {
        size_t cap = q->cap ? 2 * q->cap : 256;
        if (c5_bd_grow_packets(&q->pk, &q->shadow, cap))
            return -1;
        q->cap = cap;
    }
    q->shadow[q->n] = shadow;
    memcpy(q->pk[q->n++], pk, C5_PACKET_BYTES);
    b->queued++;
    return 0;
}

/* Cells a group holds along an axis (`want`, at most the axis's cells; < 2: one) and the
 * groups along it. */
static void group_axis(int want, int cells, int *g, int *n)
{
    *g = want > 1 ? (want < cells ? want : cells) : 1;
    *n = (cells + *g - 1) / *g;
}

/* The group of `cell` with g cells a group per axis and ng groups per axis. */
int c5_bd_group_of(const c5_bd *b, int cell, const int g[3], const int ng[3])
{
    if (g[0] * g[1] * g[2] == 1)
        return cell;
    const int *n = b->cells.n;
    int x = cell % n[0], y = cell / n[0] % n[1], z = cell / (n[0] * n[1]);
    return x / g[0] + ng[0] * (y / g[1] + ng[1] * (z / g[2]));
}

/* The Cell Tree's unit: the cell, or its group (c5_board_opts.tree_group). */
static int tree_unit(const c5_bd *b, int cell) { return c5_bd_group_of(b, cell, b->group, b->ngroup); }

/* A ray the processor hands on: the ray, or (replayed from a helper's log) the packet the
 * helper packed it into, with its cell, node and instrument node beside it. */
typedef struct {
    const c5_bray *r; /* NULL: pk */
    const uint8_t *pk;
    uint32_t cell, node, shadow;
} handed;

/* The DSP tags a ray with its Cell Tree node and queues it in SDRAM; arrival: it comes
 * from another cell (a spill of the active cell's own ray is not an arrival). */
static void dsp_queue(c5_bd *b, const handed *h, int arrival)
{
    const int timed = b->o->time_tree;
    unsigned long long t0 = timed ? c5_ticks() : 0;
    const int cell = (int)h->cell;
    uint32_t node, id = C5_NODE_NONE, from_id = h->node; /* the nodes' ids in the tree's store */
    if (b->sdram) {
        /* The packet's node is its index among the nodes of the cell it was queued for, the
         * active cell (cell_tree_sdram.h); the DSP's directory gives its id. */
        int from = h->node == C5_NODE_NONE ? -1 : tree_unit(b, b->proc.active);
        from_id = from < 0 ? C5_DEMAND_NONE : c5_sdram_tree_id(b->sdram, from, h->node);
        node = c5_sdram_tree_tag(b->sdram, from, h->node, tree_unit(b, cell), &id);
    } else {
        node = id = c5_ctree_tag(b->tree, h->node, tree_unit(b, cell));
    }
    if (timed)
        b->tree_ticks += c5_ticks() - t0;
    /* The rays each node brings to its cell's queue (stale_plan.h); a spill of the active
     * cell's own ray is not an arrival. */
    if (b->keep->node_rays && node != C5_NODE_NONE && arrival) {
        (b->sdram ? b->sdram->rays : b->keep->node_rays)[id]++;
        b->st->node_count_ops += C5_OPS_NODE_COUNT;
    }
    if (b->certify && arrival)
        c5_mw_shadow_tag(&b->shadow, from_id, node == C5_NODE_NONE ? C5_DEMAND_NONE : id, cell);
    uint32_t shadow = c5_demand_tag(&b->demand, h->shadow, tree_unit(b, cell));
    const c5_taps *t = b->o->taps;
    if (t && t->tree_tag)
        t->tree_tag(t->ctx, h->node, cell, node);
    uint8_t pk[C5_PACKET_BYTES];
    if (h->r) {
        c5_bray q = *h->r;
        q.node = node;
        c5_bd_pack(b, &q, pk);
    } else { /* the helper's packet with the DSP's node: pack(q) (no tap watches, on_enqueue_packet) */
        assert(!t && c5_lay_fits(node, C5_RAY_PACKET_CELL_TREE_NODE_WIDTH, 0));
        memcpy(pk, h->pk, C5_PACKET_BYTES);
        c5_lay_put(pk, C5_RAY_PACKET_CELL_TREE_NODE_LSB, C5_RAY_PACKET_CELL_TREE_NODE_WIDTH, node);
    }
    if (push_sdram(b, cell, pk, shadow) != 0)
        b->oom = 1;
}

void c5_bd_dsp_queue(c5_bd *b, const c5_bray *r, int arrival)
{
    dsp_queue(b, &(handed){r, NULL, r->cell, r->node, r->shadow}, arrival);
}

/* The processor hands a ray on: the active cell's sorter (the ray stays in its cell, so its
 * Cell Tree node stays), else (full, or another cell) over the ray bus to the DSP, which
 * tags it with its node before queueing it in SDRAM. */
static void hand_on(c5_bd *b, const handed *h)
{
    if (b->keep->moves && !b->eye_probe && (int)h->cell != b->proc.active) {
        int from = b->proc.active < 0 ? (int)h->cell : b->proc.active;
        b->keep->moves[(size_t)from * (size_t)b->cells.count + h->cell]++;
    }
    if (b->o->link && c5_bd_link_enqueue(b, h->r))
        return;
    if ((int)h->cell == b->proc.active) {
        if (h->r ? c5_bd_edram_insert(b, h->r, C5_BD_NO_ITEM)
                 : c5_bd_edram_insert_packet(b, h->pk, h->shadow, C5_BD_NO_ITEM))
            return;
        b->st->spills++;
    }
    c5_bd_bus_tap(b, h->r, h->pk, 1);
    dsp_queue(b, h, (int)h->cell != b->proc.active);
    b->st->bus_packets++;
}

static void on_enqueue(void *ctx, const c5_bray *r) { hand_on(ctx, &(handed){r, NULL, r->cell, r->node, r->shadow}); }

/* A replayed ray in the packet its helper made. The link and the taps take the ray (they never
 * run beside helper threads, board_threads.c). */
static void on_enqueue_packet(void *ctx, const uint8_t pk[C5_PACKET_BYTES], uint32_t cell, uint32_t node,
                              uint32_t shadow)
{
    c5_bd *b = ctx;
    if (b->o->link || b->o->taps) {
        c5_bray r;
        c5_bray_unpack(pk, &b->cells, &r);
        r.shadow = shadow;
        on_enqueue(b, &r);
        return;
    }
    hand_on(b, &(handed){NULL, pk, cell, node, shadow});
}

static void on_deliver(void *ctx, uint32_t u, uint32_t v, const int64_t rgb[3])
{
    c5_bd *b = ctx;
    if (b->eye_probe)
        return;
    uint64_t *px = b->fb + 3 * ((size_t)v * (size_t)b->s->render.width + u);
    for (int c = 0; c < 3; c++)
        px[c] += (uint64_t)rgb[c];
}

/* Processes the active cell until its queue (eDRAM and spilled SDRAM part) is empty. */
static void process_cell(c5_bd *b, int cell)
{
    c5_sdram_queue *q = &b->q[cell];
    if (b->threads)
        c5_bd_threads_cell_begin(b, cell);
    for (;;) {
        c5_bd_refill(b, q);
        if (c5_bd_edram_count(b) == 0)
            break;
        c5_rq_in in = {.pop_ready = 1};
        c5_rq_out out;
        c5_bd_edram_step(b, &in, &out);
        uint32_t s = out.pop_payload, item = b->slot_item ? b->slot_item[s] : C5_BD_NO_ITEM;
        b->free_slots[b->n_free++] = s;
        b->st->queue_pops++;
        /* The slot is free again: a replay may insert into it, the ray's own run reads it first. */
        if (item != C5_BD_NO_ITEM && c5_bd_threads_take(b, item))
            continue;
        c5_bray r;
        c5_bray_unpack(b->slot[s], &b->cells, &r);
        r.shadow = b->slot_shadow[s];
        c5_proc_run(&b->proc, &r);
    }
    if (b->threads)
        c5_bd_threads_cell_end(b);
}

static uint64_t fetch_cycles(const c5_board_opts *o, size_t bytes)
{
    double bw = o->host_bw > 0 ? o->host_bw : 132e6;
    double lat = o->host_latency_s > 0 ? o->host_latency_s : o->host_latency_s < 0 ? 0 : 1e-3;
    double s = lat + (double)bytes / fmin(bw, RDRAM_BW);
    return (uint64_t)ceil(s * C5_BD_CLOCK_HZ);
}

uint64_t c5_bd_fetch_cycles(const c5_bd *b, int cell)
{
    return fetch_cycles(b->o, c5_cell_bytes(&b->cells, cell));
}

/* The DSP's eye rays, pixel by pixel, through the processor's set-up unit. */
int c5_bd_generate_eye_rays(c5_bd *b, const c5_supervol *sv, int frame, c5_err *err)
{
    const c5_scene *s = b->s;
    c5_camera cam = b->o->camera ? *b->o->camera : c5_scene_camera_at(s, frame);
    c5_camera_basis basis;
    int64_t O[3];
    if (c5_camera_basis_make(&cam, s->render.width, s->render.height, frame, &basis, err) != 0 ||
        c5_regs_geom_point(cam.eye, sv, O, "the eye", err) != 0)
        return -1;
    c5_bray proto = {.w = C5_ONE15, .type = C5_RAY_EYE, .node = C5_NODE_NONE, .shadow = C5_DEMAND_NONE};
    if (b->threads && !b->px_owner && c5_bd_threads_eye_rays(b, &basis, O, &proto))
        return 0;
    for (int py = 0; py < basis.h; py++)
        for (int px = 0; px < basis.w; px++) {
            if (b->px_owner && !b->eye_probe && b->px_owner[(size_t)py * (size_t)basis.w + (size_t)px] != b->o->link->self)
                continue;
            c5_bd_eye_ray(&b->proc, &basis, O, &proto, px, py);
        }
    return 0;
}

void c5_bd_eye_ray(c5_proc *p, const c5_camera_basis *basis, const int64_t O[3], const c5_bray *proto, int px, int py)
{
    int64_t d[3];
    c5_regs_unit14(c5_camera_pixel_dir(basis, px, py), d);
    c5_bray r = *proto;
    r.u = (uint32_t)px;
    r.v = (uint32_t)py;
    c5_proc_new_ray(p, O, d, C5_T_INF, -1, &r);
}

static void board_free(c5_bd *b)
{
    if (b->q)
        for (int c = 0; c < b->cells.count; c++)
            free(b->q[c].pk), free(b->q[c].shadow);
    free(b->q);
    free(b->slot);
    free(b->slot_shadow);
    c5_demand_free(&b->demand);
    free(b->free_slots);
    free(b->fb);
    c5_rq_free(&b->edram);
    c5_rqh_free(&b->heap);
    free(b->own_tree);
    c5_mw_shadow_free(&b->shadow);
    free(b->out_pk);
    free(b->out_dest);
    free(b->out_t);
    free(b->in_pk);
    free(b->in_t);
    free(b->px_owner);
    for (int k = 0; k < 64; k++)
        free(b->seen_prog[k]), free(b->seen_t[k]);
    c5_rdram_free(&b->mem);
    c5_cell_store_close(b->cstore);
    c5_cells_free(&b->cells);
    c5_bd_threads_free(b);
}

/* A volume-less grid still needs one (empty) cell for the tables. */
static const c5_supervol *grid_or_dummy(const c5_supervol *sv, c5_supervol *dummy, uint8_t *voxel)
{
    if (!c5_supervol_empty(sv))
        return sv;
    memset(dummy, 0, sizeof *dummy);
    dummy->dims[0] = dummy->dims[1] = dummy->dims[2] = 1;
    dummy->spacing = v3(1, 1, 1);
    *voxel = 0;
    dummy->v = voxel;
    return dummy;
}

/* The options' defaults (board.h): the split, the key, the scheduler, the queue's size. */
static void normalise_opts(c5_board_opts *o, const c5_supervol *sv)
{
    for (int a = 0; a < 3; a++)
        if (o->cells[a] < 1)
            o->cells[a] = 0;
    c5_model_auto_split(sv->dims, o->cells); /* < 1: the fewest cells that fit the packet */
    if (!o->key)
        o->key = C5_KEY_MORTON;
    if (!o->sched)
        o->sched = C5_SCHED_MAXWORK;
    if (!o->queue_capacity)
        o->queue_capacity = C5_RQ_DEFAULT_CAPACITY;
    if (c5_supervol_empty(sv))
        o->cells[0] = o->cells[1] = o->cells[2] = 1;

}

/* The frame's state: registers, groups, cells, queues, trees and the processor (the
 * options normalised). 0, or -1 with err (what it allocated freed). */
static int frame_setup(c5_bd *b, const c5_supervol *sv, const c5_supervol *grid, const c5_board_host *host,
                       c5_err *err)
{
    const c5_scene *s = b->s;
    const c5_board_opts *o = b->o;
    c5_board_stats *stats = b->st;
    b->mem.cell = -1;
    if (c5_regs_build(s, sv, o, &b->r, err) != 0)
        return -1;
    int units = 1; /* what the schedule's entries name: cells, or groups */
    for (int a = 0; a < 3; a++) {
        group_axis(o->tree_group[a], o->cells[a], &b->group[a], &b->ngroup[a]);
        group_axis(o->schedule_group[a], o->cells[a], &b->sgroup[a], &b->nsgroup[a]);
        units *= b->nsgroup[a];
    }
    b->cur_group = -1;
    const char *unit = b->sgroup[0] * b->sgroup[1] * b->sgroup[2] > 1 ? "group" : "cell";
    if (o->sched == C5_SCHED_EXTERNAL)
        for (int i = 0; i < o->schedule_len; i++)
            if (o->schedule[i] < 0 || o->schedule[i] >= units)
                return c5_fail(err, "schedule entry %d: %s %d is outside the %d %ss of the split", i, unit,
                               o->schedule[i], units, unit);
    uint8_t alpha_nz[256];
    for (int i = 0; i < 256; i++)
        alpha_nz[i] = b->r.tf[i][3] > 0;
    c5_rq_cfg qcfg = {(uint32_t)o->queue_capacity, 32};
    size_t npx = (size_t)s->render.width * (size_t)s->render.height;
    if ((host ? c5_cells_init_flags(&b->cells, grid->dims, o->cells, host->cell_empty, host->block_empty, err)
              : c5_cells_init(&b->cells, grid, o->cells, alpha_nz, err)) != 0)
        return -1;
    if (!host && grid->store && c5_cell_store_open(grid, &b->cells, &b->cstore, err) != 0) {
        c5_cells_free(&b->cells);
        return -1;
    }
    b->q = calloc((size_t)b->cells.count, sizeof *b->q);
    b->slot = malloc((size_t)o->queue_capacity * C5_PACKET_BYTES);
    b->slot_shadow = malloc((size_t)o->queue_capacity * sizeof *b->slot_shadow);
    b->free_slots = malloc((size_t)o->queue_capacity * sizeof *b->free_slots);
    b->fb = calloc(npx * 3, sizeof *b->fb);
    b->tree = o->tree;
    b->sdram = o->sdram_tree;
    if (!b->tree && (b->tree = b->own_tree = malloc(sizeof *b->own_tree)) != NULL)
        c5_ctree_init(b->tree, 0);
    b->cycle_level = o->queue_model == C5_QUEUE_CYCLE;
    if (!b->q || !b->slot || !b->slot_shadow || !b->free_slots || !b->fb || !b->tree || c5_demand_init(&b->demand) != 0 ||
        (b->cycle_level ? c5_rq_init(&b->edram, &qcfg) : c5_rqh_init(&b->heap, &qcfg)) != 0) {
        board_free(b);
        return c5_fail(err, "out of memory for the board model (or queue capacity %d outside 1..%u)",
                       o->queue_capacity, C5_RQ_MAX_CAPACITY);
    }
    stats->switched_at_load = -1;
    stats->start_overlap = -1;
    const c5_board_out *k = b->keep;
    if (k->moves)
        memset(k->moves, 0, (size_t)b->cells.count * (size_t)b->cells.count * sizeof *k->moves);
    if (k->cell_cycles)
        memset(k->cell_cycles, 0, (size_t)b->cells.count * sizeof *k->cell_cycles);
    if (k->node_rays)
        memset(k->node_rays, 0, C5_TREE_SLOTS * sizeof *k->node_rays);
    if (o->sched == C5_SCHED_EXTERNAL && o->stale_check >= 0 && !o->link && b->sgroup[0] * b->sgroup[1] * b->sgroup[2] == 1 &&
        b->group[0] * b->group[1] * b->group[2] == 1) {
        if (c5_mw_shadow_init(&b->shadow, b->cells.count, b->sdram ? c5_sdram_tree_max_nodes(b->sdram) : 0) != 0) {
            board_free(b);
            return c5_fail(err, "out of memory for the board model");
        }
        b->certify = stats->certified = 1;
    }
    for (uint32_t i = 0; i < (uint32_t)o->queue_capacity; i++)
        b->free_slots[b->n_free++] = (uint32_t)o->queue_capacity - 1 - i;
    c5_proc_init(&b->proc, &b->r, &b->cells, &b->mem, (c5_proc_io){b, on_enqueue, on_deliver, on_enqueue_packet});
    b->proc.taps = o->taps;
    /* Taps observe every step in order, and the link stamps packets with the processor's
     * cycle count as they leave: both on the board's thread alone. Without helpers (out of
     * memory) the same frame. */
    if (!o->taps && !o->link)
        (void)c5_bd_threads_init(b, o->threads);
    stats->stages = b->r.st;
    stats->cells = b->cells.count;
    return 0;
}

/* Loads cell after cell until the frame is over: -1 (every queue empty), -2 (an error of the
 * schedule or the link, err set) or -3 (a cell's fetch failed, err set). */
static int fetch_loop(c5_bd *b, const c5_supervol *grid, const c5_board_host *host, c5_err *err)
{
    const c5_board_opts *o = b->o;
    c5_board_stats *stats = b->st;
    int sched_pos = 0, cell = -1;
    /* An asynchronous board may be given rays for the cell it has just worked off: that cell
     * is still in RDRAM and is not fetched again. (One board, or boards in rounds, never pick
     * the cell just worked off: its queue is empty until another cell's load.) */
    int keep_resident = o->link && o->link->exchange_async;
    while (!b->oom && (cell = c5_bd_next_cell(b, &sched_pos, err)) >= 0) {
        uint64_t fetched = 0; /* cycles */
        if (keep_resident && cell == b->resident) {
            stats->resident_loads++;
        } else {
            if (b->cstore) {
                if (b->mem.cell >= 0)
                    c5_cell_store_release(b->cstore, b->mem.cell);
                c5_rdram_at(&b->mem, &b->cells, cell, c5_cell_store_cell(b->cstore, cell));
                /* a schedule of cells known before the frame: the next one's pages asked of
                 * the disk while this one is worked off */
                if (o->sched == C5_SCHED_EXTERNAL && sched_pos < o->schedule_len &&
                    b->sgroup[0] * b->sgroup[1] * b->sgroup[2] == 1)
                    c5_cell_store_prefetch(b->cstore, o->schedule[sched_pos]);
            } else if ((host ? c5_rdram_place(&b->mem, &b->cells, cell, err) != 0 ||
                                   host->fetch(host->ctx, cell, b->mem.v, c5_cell_bytes(&b->cells, cell), err) != 0
                             : c5_rdram_view(&b->mem, &b->cells, grid, cell, err) != 0)) {
                return -3;
            }
            size_t bytes = c5_cell_bytes(&b->cells, cell);
            stats->fetches++;
            if (b->keep->fetch_log && stats->fetches <= (uint64_t)b->keep->fetch_log_cap)
                b->keep->fetch_log[stats->fetches - 1] = cell;
            stats->fetch_bytes += bytes;
            fetched = fetch_cycles(o, bytes);
            stats->cycles_fetch += fetched;
            b->resident = cell;
        }
        if (b->certify)
            c5_mw_shadow_load(&b->shadow, cell);
        b->proc.active = cell;
        uint64_t c0 = b->proc.st.cycles, p0 = stats->bus_packets;
        b->emit_base = c5_bd_clock(b);
        b->emit_c0 = c0;
        process_cell(b, cell);
        uint64_t work = b->proc.st.cycles - c0 + C5_CYC_PIPELINE, moved = stats->bus_packets - p0;
        stats->cycles_process += work > moved ? work : moved; /* the bus runs beside the pipeline */
        if (b->keep->cell_cycles)
            b->keep->cell_cycles[cell] += fetched + (work > moved ? work : moved);
        stats->last_end = c5_bd_clock(b);
        if (b->cur_entry >= 0) {
            b->progress = b->cur_entry;
            b->progress_t = stats->last_end;
            b->cur_entry = -1;
        }
        if (o->progress)
            o->progress(o->progress_ctx, &(c5_board_progress){stats->fetches, b->queued});
    }
    return cell;
}

int c5_board_render(const c5_scene *s, const c5_supervol *sv, int frame, const c5_board_opts *opts,
                    c5_image *out, c5_board_stats *stats, c5_err *err)
{
    return c5_board_render_keep(s, sv, frame, opts, NULL, out, stats, err);
}

int c5_board_render_keep(const c5_scene *s, const c5_supervol *sv, int frame, const c5_board_opts *opts,
                         const c5_board_out *keep, c5_image *out, c5_board_stats *stats, c5_err *err)
{
    static const c5_board_out none;
    double start = c5_now_s();
    unsigned long long start_ticks = c5_ticks();
    memset(stats, 0, sizeof *stats);
    c5_board_opts o = *opts;
    normalise_opts(&o, sv);
    c5_bd b = {.s = s, .o = &o, .keep = keep ? keep : &none, .st = stats, .resident = -1,
             .wait_since = UINT64_MAX, .progress = -1, .cur_entry = -1};
    c5_camera frame_cam = o.camera ? *o.camera : c5_scene_camera_at(s, frame);
    stats->frame_key = c5_frame_key(&frame_cam, s->render.width, s->render.height);
    c5_supervol dummy;
    uint8_t voxel;
    const c5_supervol *grid = grid_or_dummy(sv, &dummy, &voxel);
    const c5_board_host *host = c5_supervol_empty(sv) ? NULL : o.host;
    size_t npx = (size_t)s->render.width * (size_t)s->render.height;
    if (frame_setup(&b, sv, grid, host, err) != 0)
        return -1;
    if (o.link && (o.taps || c5_bd_eye_owners(&b, sv, frame, err) != 0)) {
        board_free(&b);
        return o.taps ? c5_fail(err, "several boards: taps (golden vectors) are for one board") : -1;
    }
    b.emit_base = stats->cycles_process; /* after the eye-ray probe */
    b.emit_c0 = b.proc.st.cycles;
    if (c5_bd_generate_eye_rays(&b, sv, frame, err) != 0) {
        board_free(&b);
        return -1;
    }
    if (o.sched == C5_SCHED_EXTERNAL && o.prev_start && o.prev_start_len == b.cells.count)
        stats->start_overlap = c5_bd_start_overlap(&b);
    if (b.certify)
        c5_bd_set_budget(&b);
    if (b.keep->start_counts)
        for (int c = 0; c < b.cells.count; c++)
            b.keep->start_counts[c] = (uint32_t)c5_bd_queued_in(&b, c);
    /* Rays that never reach the volume were finished by the set-up: the first visit. */
    uint64_t proc_cycles = b.proc.st.cycles, bus = stats->bus_packets;
    stats->cycles_process += proc_cycles > bus ? proc_cycles : bus;
    stats->last_end = c5_bd_clock(&b);
    if (o.link && o.link->exchange_async) /* nothing sent before the frame began arrives sooner */
        b.known_to = o.link->lookahead - 1;
    int cell = fetch_loop(&b, grid, host, err);
    if (cell == -3) {
        board_free(&b);
        return -1;
    }
    if (b.certify && !b.oom && cell == -1) {
        if (c5_mw_shadow_advance(&b.shadow) >= 0 || b.shadow.broken)
            c5_bd_certificate_lost(&b); /* the shadow cannot finish with every queue empty: a model bug */
        else
            stats->shadow_steps = b.shadow.steps;
    }
    stats->shadow_ops = b.shadow.ops;
    if (b.oom || cell == -2) {
        board_free(&b);
        return cell == -2 ? -1 : c5_fail(err, "out of memory for the DSP's SDRAM ray queues");
    }
    if (c5_image_alloc(out, s->render.width, s->render.height, err) != 0) {
        board_free(&b);
        return -1;
    }
    /* frame_acc is UQ20.12: 32 bits a channel. Far beyond any scene's light, but a clamp
     * here would be counted, never wrapped. */
    if (b.keep->frame_acc)
        memcpy(b.keep->frame_acc, b.fb, npx * 3 * sizeof *b.fb);
    for (size_t i = 0; i < npx * 3; i++) {
        if (b.fb[i] > UINT32_MAX && !o.link) { /* several boards: their sum is clamped */
            b.fb[i] = UINT32_MAX;
            b.proc.st.saturations++;
        }
        out->rgb[i] = c5_rgb_float(b.fb[i]);
    }
    if (o.taps && o.taps->frame)
        o.taps->frame(o.taps->ctx, b.fb, s->render.width, s->render.height);

    c5_bd_collect_stats(&b);
    board_free(&b);
    stats->wall_s = c5_now_s() - start;
    stats->tree_wall_s = c5_ticks_to_s(b.tree_ticks, c5_ticks() - start_ticks, stats->wall_s);
    return 0;
}
