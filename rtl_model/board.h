/* The board model: a bit-accurate, cycle-counting model of the Frank-Kaufman board (DSP,
 * one ray processor with its eDRAM ray queue, one RDRAM holding one cell) rendering one
 * frame of a scene. docs/board-model.md describes the blocks, the cycle model and every
 * decision; docs/bit-layouts.md (generated from spec/layouts.toml) every bit.
 *
 * The image does not depend on the cell split, the queue key or the processing order:
 * each ray's arithmetic depends only on its own packet, and the frame buffer adds integers. */
#ifndef C5_BOARD_H
#define C5_BOARD_H

#include <stdint.h>

#include "cell_tree.h"
#include "cell_tree_sdram.h"
#include "cref.h"
#include "fixed.h"
#include "image.h"
#include "stale_plan.h"
#include "scene.h"
#include "supervol.h"
#include "taps.h"
#include "widths.h"

/* Sort key of the active cell's ray queue (docs/board-model.md, "queue key"). */
typedef enum {
    C5_KEY_MORTON = 1, /* Z-order code of the ray's next voxel inside the cell (default) */
    C5_KEY_FIFO = 2,   /* arrival order: a plain FIFO, for comparison */
} c5_queue_key;

/* How the model steps the eDRAM ray queue (docs/ray-queue.md). Both give the same outputs
 * every cycle, so the same image, counters and cycles; only the host time differs. */
typedef enum {
    C5_QUEUE_EQUIV = 1, /* its equivalent model, a stable heap (rq_heap.h): the default */
    C5_QUEUE_CYCLE = 2, /* the clock-level insertion sorter, register by register (ray_queue.h) */
} c5_queue_model;

/* Which cell the DSP loads next when the active queue is empty. */
typedef enum {
    C5_SCHED_MAXWORK = 1,   /* the online Max Work rule: most queued rays, ties to the lowest id */
    C5_SCHED_MINWORK = 2,   /* fewest queued rays first: a deliberately different order (tests) */
    C5_SCHED_EXTERNAL = 3,  /* follow opts.schedule (skipping cells without rays), then Max Work */
} c5_sched_kind;

/* The board with its volume in the host's memory (the emulated board, board_emu/): the grid
 * handed to c5_board_render is a shell (dims, spacing, origin; v == NULL), the empty-cell
 * and empty-block flags come precomputed, and every cell load asks the host for the bytes. */
typedef struct {
    void *ctx;
    /* Fills dst with the cell and its ghost layers as c5_rdram holds them (x fastest,
     * c5_cell_bytes bytes); 0, or -1 with a message (the frame stops with it). */
    int (*fetch)(void *ctx, int cell, uint8_t *dst, size_t bytes, c5_err *err);
    const uint8_t *cell_empty;  /* one byte per cell of the split, as c5_cells_init computes */
    const uint8_t *block_empty; /* one byte per 8^3 block of the grid */
} c5_board_host;

struct c5_board_progress;
struct c5_board_stats;

/* What an asynchronous board tells the others at each of the simulation's exchanges
 * (c5_board_link.exchange_async). Times are board cycles from the frame's start. */
typedef struct {
    uint64_t next;        /* the earliest time it may send another packet: its clock while rays
                           * wait in its queues, else the earliest arrival in its in-box;
                           * UINT64_MAX: neither */
    int64_t progress;     /* the plan across boards: the last entry it passed (-1: none), and
                           * when (its load's end) */
    uint64_t progress_t;
} c5_link_report;

/* One of several boards sharing the super volume (rtl_model/multi_board.h,
 * docs/multi-board.md): each board owns some cells; a ray leaving for a cell another board
 * owns goes to it as its 32-byte packet, exchanged in rounds or, asynchronously, as the link
 * carries it. */
typedef struct {
    void *ctx;
    int self, boards;      /* this board's number, 0..boards-1 */
    const uint16_t *owner; /* [cells of the split]: the board owning each cell */
    /* Asynchronous boards (exchange_async set, exchange unused): the board runs on its own
     * clock; a packet handed on at time t reaches its board at t + the link's time, at least
     * `lookahead` cycles (the latency) later. The simulation exchanges the packets sent up to a
     * common time B (every board's report.next is at least B) and then every board knows each
     * arrival up to B + lookahead: it loads cells while its clock is within that, else takes
     * part in the next exchange. out[i] goes to dest[i], handed on at t_out[i] (times not
     * decreasing); the exchange sends all of them, and returns the
     * packets for this board known to arrive by B + lookahead with their arrival times (the
     * link's memory, valid until the next call), and B. 1: go on, 0: every board is idle and
     * nothing is in flight, -1 with a message. */
    uint64_t lookahead;
    int (*exchange_async)(void *ctx, const c5_link_report *me, const uint8_t (*out)[C5_PACKET_BYTES],
                          const uint16_t *dest, const uint64_t *t_out, size_t n_out,
                          const uint8_t (**in)[C5_PACKET_BYTES], const uint64_t **t_in, size_t *n_in,
                          uint64_t *bound, c5_err *err);
    const c5_link_report *(*reports)(void *ctx); /* every board's report at the last exchange */
    /* Called when this board's queues are empty: hands over the packets for other boards
     * (out[i] goes to board dest[i]) with the board's counters so far (cycles filled in),
     * and receives the packets the other boards sent this board (*in, *n_in: the link's
     * memory, valid until the next call). 1: rays are queued somewhere (go on), 0: every
     * board is idle and no packet is in flight (the frame is over), -1 with a message. */
    int (*exchange)(void *ctx, const uint8_t (*out)[C5_PACKET_BYTES], const uint16_t *dest, size_t n_out,
                    const struct c5_board_stats *so_far, const uint8_t (**in)[C5_PACKET_BYTES], size_t *n_in,
                    c5_err *err);
} c5_board_link;

/* Boards a link joins at most (the multi-board layer's C5_MB_MAX_BOARDS). */
#define C5_LINK_MAX_BOARDS 64

/* Why the board stopped following a schedule (c5_board_stats.switch_reason). */
typedef enum {
    C5_SWITCH_NONE = 0,
    C5_SWITCH_BUDGET = 1, /* the next scheduled load would take the lead over Max Work's shadow past
                           * the frame's budget: the shadow's cell is loaded instead */
} c5_switch_reason;

typedef struct {
    int cells[3];            /* split of the grid into cells per axis; < 1: the fewest cells of at most 256 voxels (c5_model_auto_split) */
    c5_queue_key key;        /* 0: C5_KEY_MORTON */
    c5_sched_kind sched;     /* 0: C5_SCHED_MAXWORK */
    const int *schedule;     /* C5_SCHED_EXTERNAL: cell ids in load order (the Cell Tree's), or
                              * group ids with tree_group */
    int schedule_len;
    /* The DSP's RAM, which the caller provides and the frame fills: */
    c5_ctree *tree;          /* the DSP's Cell Tree of this frame, filled here after the caller's
                              * c5_ctree_init (which sets its capacity); NULL: built and dropped */
    c5_sdram_tree *sdram_tree; /* the DSP's Cell Tree in its SDRAM (cell_tree_sdram.h), filled here
                              * after the caller's c5_sdram_tree_init, instead of `tree`; NULL: the
                              * tree is on chip. Its per-node counts go to its rays[], not
                              * c5_board_out.node_rays (which then only asks for them) */
    int tree_group[3];       /* the Cell Tree this frame builds, over groups of cells: cells a group
                              * holds along each axis (group id = x + gx (y + gy z) over the grid
                              * of groups); < 2 on every axis: over single cells */
    int schedule_group[3];   /* the same for the external schedule's entries (the tree it was
                              * made from): each scheduled group is worked off, Max Work among its
                              * cells, until none holds a ray */
    int queue_capacity;      /* eDRAM sorter entries, 0: 256 */
    c5_queue_model queue_model; /* 0: C5_QUEUE_EQUIV */
    int all_stages;          /* 1: keep every stage on even when the scene does not need it */
    double host_bw;          /* bytes/s from host memory/disk to RDRAM, 0: 132e6 (PCI 33 MHz x 32 bit) */
    double host_latency_s;   /* per fetch, 0: 1e-3 (a disk seek); < 0: none */
    const c5_taps *taps;     /* observers of the blocks for golden vectors, or NULL */
    const c5_board_host *host; /* NULL: the model reads the super volume itself */
    const c5_camera *camera; /* NULL: the scene's camera of the frame (the camera registers) */
    const c5_widths *widths; /* datapath fraction widths, NULL: shipped (widths.h, cube5 sweep) */
    /* Called after every cell visit, for a progress line in long frames; NULL: none. */
    void (*progress)(void *ctx, const struct c5_board_progress *p);
    void *progress_ctx;
    /* The certificate while following an external schedule of cells over a tree of cells
     * (docs/cell-tree.md, "The certificate"): the DSP runs Max Work's shadow on the frame's
     * tree (mw_shadow.h) and follows the schedule only while its loads beyond the shadow's
     * steps stay within the budget, the path's bank plus one allowance; else it loads the
     * shadow's cell. The frame then never fetches more than Max Work plus the budget. The
     * image never depends on it. */
    int stale_check;         /* 0: on (default); -1: off, the schedule is followed to its end (the
                              * paper's board), then Max Work */
    const uint32_t *prev_start; /* rays each cell's queue held when the previous frame's set-up
                                 * ended (c5_board_out.start_counts of that frame), or NULL */
    int prev_start_len;      /* entries of prev_start: the split's cells */
    /* The DSP's replay of the previous frame's tree (stale_plan.h), or NULL: its bank (the
     * path's exact saving so far) and Max Work's loads set the budget. */
    const c5_stale_plan *plan;
    /* Several boards (rtl_model/multi_board.h): NULL: this board owns every cell. With a
     * link the board generates only the eye rays of its pixels (those whose first queued ray
     * is for a cell it owns; pixels with none: pixel index mod boards), and taps must be NULL. */
    const c5_board_link *link;
    /* Several asynchronous boards, the plan across boards (docs/multi-board.md): the schedule
     * is the pooled tree's, for every board's cells; this board follows its own cells' entries,
     * and entry i waits until board k has passed entry sched_dep[i * boards + k] (-1: none;
     * plan_deps.h). NULL: the schedule is this board's own. */
    const int *sched_dep;
    /* Host threads for the frame, the calling one included (board_threads.c; docs/board-model.md,
     * "Host threads"); < 2: the calling thread alone. The image, every counter and every cycle
     * count are the same for any count. With taps or a link the calling thread runs alone. */
    int threads;
    /* With threads > 1: the calling thread runs no ray a helper could run, it waits for the
     * helper's log and replays it (tests of the replay: every item takes that path). */
    int threads_replay_all;
    /* The DSP's Cell Tree tags timed on the host into stats.tree_wall_s (the schedule report's
     * build host_s). 0: not timed, tree_wall_s 0: two reads of the time-stamp counter a tag,
     * some 12 ns each on the VM, on the board's thread, which every other thread waits on. */
    int time_tree;
} c5_board_opts;

/* What a frame leaves beside its image and counters, each where the caller gives room for it
 * (NULL: not kept). */
typedef struct {
    int *fetch_log;          /* the cells fetched, in order (the first fetch_log_cap); a frame's
                              * fetches are a schedule of its own tree, which the window rule
                              * starts from (docs/cell-tree.md) */
    int fetch_log_cap;
    uint32_t *start_counts;  /* [cells]: rays each cell's queue holds when the set-up ends (the
                              * next frame's c5_board_opts.prev_start) */
    uint32_t *node_rays;     /* [C5_TREE_SLOTS]: packets tagged with each node slot */
    uint64_t *frame_acc;     /* [width x height x 3]: the frame buffer's integer sums before the
                              * clamp (what several boards add up) */
    uint32_t *moves;         /* [cells x cells]: rays handed on from the active cell (row) to
                              * another cell (column); rays the eye-ray set-up queues count on
                              * their cell's diagonal (the --assign tree rule's input) */
    uint64_t *cell_cycles;   /* [cells]: the board cycles of each cell's loads, fetch and processing
                              * (the --assign load rule's input) */
} c5_board_out;

/* Where a frame is (c5_board_opts.progress). */
typedef struct c5_board_progress {
    uint64_t fetches;     /* cell fetches so far */
    uint64_t rays_queued; /* rays waiting in the DSP's SDRAM queues */
} c5_board_progress;

/* The stages the scene needs (docs/board-model.md, "what runs"). */
typedef struct {
    int gradients;  /* volume shading: lights and shading on and a volume */
    int shadow;     /* shadow rays: a shadow-casting light and a diffuse surface */
    int reflect;    /* reflected rays: a reflective or refractive-sphere (TIR) material */
    int refract;    /* refracted rays: a transparent material */
    int scheduling; /* more than one cell */
} c5_board_stages;

typedef struct c5_board_stats {
    uint64_t rays[C5_RAY_TYPES];
    uint64_t samples;        /* samples taken through the datapath */
    uint64_t samples_leaped; /* sample positions passed by leaps over empty blocks and cells */
    uint64_t ends[C5_END_KINDS];
    uint64_t cycles;         /* board cycles of the frame = process + fetch_stall */
    uint64_t cycles_process; /* cycles the processor works (samples, ray issue, hits, bus) */
    uint64_t cycles_fetch;   /* cycles stalled while a cell is fetched into RDRAM */
    double board_s;          /* cycles / 100 MHz */
    uint64_t fetches, fetch_bytes;
    uint64_t bus_packets;    /* ray packets over the ray bus (exits to the DSP, spills) */
    uint64_t spills;         /* rays that found the eDRAM queue full and went to SDRAM */
    uint64_t queue_pops;     /* rays taken from the eDRAM sorter */
    uint32_t queue_max;      /* largest eDRAM queue occupancy */
    uint64_t cache_hits, cache_misses; /* voxel-block cache model (the queue key's benefit) */
    uint64_t saturations;    /* datapath results clamped (all datapaths together) */
    uint64_t sched_loads;    /* fetches that followed the external schedule */
    uint64_t sched_skipped;  /* schedule entries passed over: the cell had no rays */
    uint64_t sched_fallback; /* fetches chosen by Max Work after the schedule ran out */
    uint64_t sched_waits;    /* several boards following the plan across boards: waits for another
                              * board's progress */
    uint64_t sched_switches; /* loads taken from Max Work's shadow while schedule entries were left */
    int64_t switched_at_load;  /* the fetch index (0-based) of the first of them; -1: none */
    c5_switch_reason switch_reason;
    double switch_value;     /* the lead at that load */
    uint64_t frame_key;      /* the camera registers of the frame (eye, target, up, field of view,
                              * image size), hashed: frames with one key trace the same rays */
    int identical;           /* the frame's key is the previous tree's: its replay is this frame */
    int certified;           /* the frame followed a schedule under the certificate (not Max Work, the
                              * paper's board or a schedule of groups) */
    int64_t ledger_budget;   /* then: loads it may make beyond Max Work's (bank + allowance) */
    int64_t lead_max;        /* the largest lead: the board's loads less the shadow's steps */
    uint64_t shadow_loads;   /* loads taken from Max Work's shadow (sched_switches: those while schedule
                              * entries were left) */
    uint64_t shadow_steps;   /* Max Work's fetches of the frame, as the shadow found them; 0: none */
    int shadow_broken;       /* a packet the shadow could not place: no bound for the frame's rest */
    uint64_t shadow_ops;     /* DSP operations of the shadow (mw_shadow.h) */
    uint64_t node_count_ops; /* DSP operations counting each node's rays (c5_board_out.node_rays) */
    double start_overlap;    /* the start queues' overlap with the previous frame's; -1: not compared */
    uint32_t tree_nodes, tree_slots; /* the Cell Tree: nodes, slots with extension slots */
    int tree_overflow;       /* the tree outgrew the DSP RAM (the frame is still right) */
    int tree_sdram;          /* the tree was in the DSP's SDRAM (opts.sdram_tree): its reads and
                              * writes are SDRAM node and directory accesses */
    uint64_t tree_sdram_bytes; /* of its region in use */
    uint32_t tree_cell_nodes_max; /* the most nodes of one cell: packet indices run below it */
    /* The tree the frame's dependencies need, with unbounded RAM (tree_demand.h): nodes, and
     * slots with five children a slot (the node layout) and with six (Figure 8's); 0 when
     * the host ran out of memory for it. */
    uint64_t tree_demand_nodes, tree_demand_slots, tree_demand_slots6;
    uint64_t tree_demand_sum_maxgen; /* the frame's proven lower bound on any order of loads from
                                      * that tree (c5_demand_sum_maxgen); 0: no memory for it */
    uint64_t tree_tags, tree_reads, tree_writes; /* DSP work building it: packets, node accesses */
    double tree_wall_s;      /* host time of building it (opts.time_tree; else 0) */
    c5_board_stages stages;
    int cells;               /* cells in the split */
    double wall_s;           /* host time of the model */
    uint64_t helper_runs;    /* ray runs the host's helper threads did and the board's thread
                              * replayed (opts.threads): host work, no part of the board's */
    uint64_t helper_wakes;   /* visits at whose start the helpers slept and were woken (not
                              * found spinning): host work too */
    /* With opts.link: packets sent to and received from other boards, the exchanges taken
     * part in, the processor cycles of the replicated eye-ray set-up that finds which board
     * owns each pixel (in cycles_process). */
    uint64_t link_sent, link_received, link_rounds, cycles_eye_owner;
    /* Asynchronous boards: cycles waiting for packets with every queue empty (the frame's
     * time is its clock: process + fetch + idle), loads of the cell still in RDRAM (no fetch),
     * and when its last load ended. */
    uint64_t cycles_idle, resident_loads, last_end;
} c5_board_stats;

/* Renders frame `frame` of the scene into out (allocated here). 0, or -1 with a message
 * (a scene beyond the model's formats, docs/bit-layouts.md, is refused, not approximated). */
int c5_board_render(const c5_scene *s, const c5_supervol *sv, int frame, const c5_board_opts *opts,
                    c5_image *out, c5_board_stats *stats, c5_err *err);
/* The same, keeping what `keep` gives room for. */
int c5_board_render_keep(const c5_scene *s, const c5_supervol *sv, int frame, const c5_board_opts *opts,
                         const c5_board_out *keep, c5_image *out, c5_board_stats *stats, c5_err *err);

#endif
