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

/* One of several boards sharing the super volume (rtl_model/multi_board.h,
 * docs/multi-board.md): each board owns some cells; a ray leaving for a cell another board
 * owns goes to it as its 32-byte packet, exchanged in rounds. */
typedef struct {
    void *ctx;
    int self, boards;      /* this board's number, 0..boards-1 */
    const uint16_t *owner; /* [cells of the split]: the board owning each cell */
    /* Called when this board's queues are empty: hands over the packets for other boards
     * (out[i] goes to board dest[i]) with the board's counters so far (cycles filled in),
     * and receives the packets the other boards sent this board (*in, *n_in: the link's
     * memory, valid until the next call). 1: rays are queued somewhere (go on), 0: every
     * board is idle and no packet is in flight (the frame is over), -1 with a message. */
    int (*exchange)(void *ctx, const uint8_t (*out)[C5_PACKET_BYTES], const uint16_t *dest, size_t n_out,
                    const struct c5_board_stats *so_far, const uint8_t (**in)[C5_PACKET_BYTES], size_t *n_in,
                    c5_err *err);
} c5_board_link;

/* Why the board stopped following a schedule (c5_board_stats.switch_reason). */
typedef enum {
    C5_SWITCH_NONE = 0,
    C5_SWITCH_START = 1,   /* the queues after the set-up differ from the previous frame's */
    C5_SWITCH_ORPHANS = 2, /* rays wait in cells the rest of the schedule never visits */
    C5_SWITCH_SKIPS = 3,   /* scheduled cells found empty too often */
    C5_SWITCH_NO_GAIN = 4, /* on the previous tree the schedule makes no fewer loads than Max Work */
    C5_SWITCH_SURPRISE = 5, /* loads the replay did not expect have eaten the expected saving */
    C5_SWITCH_LAG = 6,     /* a one-frame-old schedule, replayed on the previous frame, saved too little */
    C5_SWITCH_LEDGER = 7,  /* the expected saving does not cover the frame's risk and the path's deficit */
} c5_switch_reason;

/* The detection's thresholds (docs/cell-tree.md, "Stale schedules": measured). */
#define C5_STALE_START_OVERLAP 0.95 /* switch at load 0 below this overlap of the start queues */
#define C5_STALE_ORPHAN_FRAC 0.10   /* switch when orphan rays are this part of the queued rays */
#define C5_STALE_SKIP_FRAC 0.50     /* switch when skipped entries are this part of those passed */
#define C5_STALE_SKIP_MIN 4         /* ... and at least this many */
#define C5_STALE_GAIN_MARGIN 0.0    /* follow only a schedule the replay finds this part shorter than Max Work */
#define C5_STALE_GAIN_MIN_LOADS 2   /* ... and at least this many loads shorter */
#define C5_STALE_LAG_GAIN 0.03      /* ... and a one-frame-old schedule saved this part of Max Work's loads */
#define C5_STALE_SURPRISE 0.5       /* switch when unexpected loads and orphan cells reach this part of the saving */
#define C5_STALE_FIRST_RISK 3       /* with less than one frame's allowance banked, follow only an expected
                                     * saving of this many allowances */
typedef struct {
    double start_overlap, orphan_frac, skip_frac;
    int skip_min;
    double gain_margin;  /* follow only when the replayed schedule saves more than this part of Max Work's loads */
    double lag_gain;     /* follow only when the previous frame's schedule, replayed on the frame after, saved this part */
    double surprise;     /* switch when unexpected loads reach this part of the expected saving */
    int first_risk;      /* allowances of expected saving needed while the bank holds less than one
                          * allowance; < 0: the ledger is off */
} c5_stale_thresholds;

typedef struct {
    int cells[3];            /* split of the grid into cells per axis; < 1: the fewest cells of at most 256 voxels (c5_model_auto_split) */
    c5_queue_key key;        /* 0: C5_KEY_MORTON */
    c5_sched_kind sched;     /* 0: C5_SCHED_MAXWORK */
    const int *schedule;     /* C5_SCHED_EXTERNAL: cell ids in load order (the Cell Tree's), or
                              * group ids with tree_group */
    int schedule_len;
    int *fetch_log;          /* if not NULL: the cells fetched, in order (the first fetch_log_cap);
                              * a frame's fetches are a schedule of its own tree, which the window
                              * rule starts from (docs/cell-tree.md) */
    int fetch_log_cap;
    c5_ctree *tree;          /* the DSP's Cell Tree of this frame, filled here after the caller's
                              * c5_ctree_init (which sets its capacity); NULL: built and dropped */
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
    const c5_widths *widths; /* datapath fraction widths, NULL: shipped (widths.h; issue 8 sweep) */
    /* Called after every cell visit, for a progress line in long frames; NULL: none. */
    void (*progress)(void *ctx, const struct c5_board_progress *p);
    void *progress_ctx;
    /* Stale-schedule detection while following an external schedule of cells (the DSP's, at
     * the cost of its queue counters; docs/cell-tree.md, "Stale schedules"): when a signal
     * fires, Max Work chooses the rest of the frame. The image never depends on it. */
    int stale_check;         /* 0: on (default); -1: off, the schedule is followed to its end */
    const uint32_t *prev_start; /* rays each cell's queue held when the previous frame's set-up
                                 * ended (c5_board_stats.start_counts of that frame), or NULL */
    int prev_start_len;      /* entries of prev_start: the split's cells */
    uint32_t *start_counts;  /* out, or NULL: this frame's, [cells] */
    c5_stale_thresholds stale; /* 0 fields: the defaults (C5_STALE_*) */
    /* The DSP's replay of the previous frame's tree (stale_plan.h), or NULL: what following
     * the schedule and Max Work cost there, and per entry the rays it expects. */
    const c5_stale_plan *plan;
    uint32_t *node_rays;     /* out, or NULL: packets tagged with each node slot, [C5_TREE_SLOTS] */
    /* Several boards (rtl_model/multi_board.h): NULL: this board owns every cell. With a
     * link the board generates only the eye rays of its pixels (those whose first queued ray
     * is for a cell it owns; pixels with none: pixel index mod boards), and taps must be NULL. */
    const c5_board_link *link;
    uint64_t *frame_acc;     /* out, or NULL: the frame buffer's integer sums before the clamp,
                              * [width x height x 3] (what several boards add up) */
    uint32_t *moves;         /* out, or NULL: [cells x cells] rays handed on from the active cell
                              * (row) to another cell (column); rays the eye-ray set-up queues
                              * count on their cell's diagonal (the --assign tree rule's input) */
} c5_board_opts;

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
    uint64_t sched_switches; /* 1 when the frame stopped following a stale schedule */
    int64_t switched_at_load;  /* the fetch index (0-based) of the first Max Work load after the
                                * switch; -1: no switch */
    c5_switch_reason switch_reason;
    double switch_value;     /* the signal's value at the switch (overlap, fraction) */
    uint64_t stale_ops;      /* DSP operations of the detection: counters read and compared */
    uint64_t node_count_ops; /* DSP operations counting each node's rays (opts.node_rays) */
    double start_overlap;    /* the start queues' overlap with the previous frame's; -1: not compared */
    uint32_t tree_nodes, tree_slots; /* the Cell Tree: nodes, slots with extension slots */
    int tree_overflow;       /* the tree outgrew the DSP RAM (the frame is still right) */
    /* The tree the frame's dependencies need, with unbounded RAM (tree_demand.h): nodes, and
     * slots with five children a slot (the node layout) and with six (Figure 8's); 0 when
     * the host ran out of memory for it. */
    uint64_t tree_demand_nodes, tree_demand_slots, tree_demand_slots6;
    uint64_t tree_tags, tree_reads, tree_writes; /* DSP work building it: packets, node accesses */
    double tree_wall_s;      /* host time of building it */
    c5_board_stages stages;
    int cells;               /* cells in the split */
    double wall_s;           /* host time of the model */
    /* With opts.link: packets sent to and received from other boards, the exchanges taken
     * part in, the processor cycles of the replicated eye-ray set-up that finds which board
     * owns each pixel (in cycles_process). */
    uint64_t link_sent, link_received, link_rounds, cycles_eye_owner;
} c5_board_stats;

/* Renders frame `frame` of the scene into out (allocated here). 0, or -1 with a message
 * (a scene beyond the model's formats, docs/bit-layouts.md, is refused, not approximated). */
int c5_board_render(const c5_scene *s, const c5_supervol *sv, int frame, const c5_board_opts *opts,
                    c5_image *out, c5_board_stats *stats, c5_err *err);

#endif
