/* Several boards on one super volume (docs/multi-board.md): each board is a whole board model
 * (DSP, RDRAM, ray queues, Cell Tree) owning a part of the cells; a ray leaving for a cell
 * another board owns travels there as its 32-byte packet. By default each board runs on its
 * own clock and a packet travels as soon as it is handed on (mb_async.h); in rounds, each
 * board works off its queues, then all exchange the packets for each other and learn how
 * many moved, and a round in which no packet moved ends the frame. The frame buffers'
 * integer sums are added, so the image is the same bits as one board's for any number of
 * boards, any assignment and either exchange.
 *
 * This layer is independent of the transport: c5_mb_transport carries the collectives
 * (cli/mpi_link.c over MPI; mb_loopback.c over threads in one process). It also holds the
 * modelled cost of the inter-board link and each board's time. */
#ifndef C5_MULTI_BOARD_H
#define C5_MULTI_BOARD_H

#include <stdint.h>

#include "board.h"

#define C5_MB_MAX_BOARDS C5_LINK_MAX_BOARDS
#define C5_MB_CLOCK_HZ 100e6      /* the board clock: modelled times are counted in its cycles */
/* The inter-board link's defaults (docs/multi-board.md, "Link model"): one full-duplex
 * Gigabit Ethernet port a board into a switch (IEEE 802.3ab, 1000BASE-T: 1 Gbit/s =
 * 125 MB/s of line rate) and 50 us a message exchange, the order of small-message MPI
 * latency over TCP on Gigabit Ethernet (an assumption, not measured here). */
#define C5_LINK_BW_DEFAULT 125e6
#define C5_LINK_LATENCY_DEFAULT 50e-6

/* Named links (cube5 --link; docs/multi-board.md, "Link model"): the line rate each way, and a
 * latency of the order published for small messages on such a link (assumptions, not
 * measured here). */
typedef struct {
    const char *name;
    double bw, latency_s;
} c5_link_preset;

/* Its entry, or NULL. c5_link_presets: the list, ended by a NULL name. */
const c5_link_preset *c5_link_preset_find(const char *name);
extern const c5_link_preset c5_link_presets[];

/* How cells are assigned to boards (c5_mb_assign). */
typedef enum {
    C5_ASSIGN_SLAB = 1, /* contiguous runs of cells in order, the axis with the most cells slowest: slabs */
    C5_ASSIGN_KD = 2,   /* recursive bisection of the grid of cells, longest axis first (a k-d split) */
    C5_ASSIGN_MOD = 3,  /* cell id mod boards: scattered (a worst case; tests "any assignment") */
    C5_ASSIGN_TREE = 4, /* from the previous frame's ray traffic between cells: a k-d split balancing
                         * the rays each cell received, then cells moved to the board they trade
                         * most rays with (the paper's proposal); kd in a run's first frame */
    C5_ASSIGN_LOAD = 5, /* from what the boards measured in the previous frame: a k-d split
                         * balancing each cell's board cycles (its loads' fetches and processing),
                         * the dynamic load balance of the paper's future work; kd in a run's
                         * first frame */
} c5_assign_rule;

/* How rays move between boards. */
typedef enum {
    C5_MB_ASYNC = 1,  /* each board on its own clock; a packet travels when it is handed on, and
                       * the frame ends by credit recovery (mb_async.h; the default) */
    C5_MB_ROUNDS = 2, /* bulk-synchronous: each board works off its queues, then all exchange;
                       * a round that moves nothing ends the frame */
} c5_mb_mode;

const char *c5_mb_mode_name(c5_mb_mode m);
/* "async", "rounds" -> the mode; 0: unknown. */
c5_mb_mode c5_mb_mode_parse(const char *s);

/* The tree rule works on a cells x cells table: up to this many cells (else kd). */
#define C5_MB_TREE_MAX_CELLS 1024

/* What the tree rule carries from frame to frame: the caller's, zeroed before the first
 * frame, c5_mb_history_free after the last. */
typedef struct {
    int cells;          /* the split's cells the tables are for, 0: none yet */
    uint64_t *moves;    /* tree rule: [cells x cells] the last frame's rays handed from cell (row)
                         * to cell (column) on all boards; set-up rays on their cell's diagonal */
    uint64_t *cost;     /* load rule: [cells] the last frame's board cycles of each cell */
} c5_mb_history;

void c5_mb_history_free(c5_mb_history *h);

/* The collectives the boards need; every board calls each one the same number of times in
 * the same order. 0, or -1 with a message. */
typedef struct {
    void *ctx;
    int rank, size; /* this board, the number of boards */
    /* Packets to other boards: out[i] to board dest[i]; receives those sent to this board,
     * ordered by sender then by the sender's order, into the transport's memory (valid until
     * the next call). */
    int (*alltoall)(void *ctx, const uint8_t (*out)[C5_PACKET_BYTES], const uint16_t *dest, size_t n_out,
                    const uint8_t (**in)[C5_PACKET_BYTES], size_t *n_in, c5_err *err);
    /* Every board's `bytes` bytes into all[size * bytes], by board. */
    int (*allgather)(void *ctx, const void *mine, size_t bytes, void *all, c5_err *err);
    /* v[0..n) summed element by element over the boards, the sum on every board. */
    int (*sum_u64)(void *ctx, uint64_t *v, size_t n, c5_err *err);
} c5_mb_transport;

typedef struct {
    c5_mb_mode mode;        /* 0: C5_MB_ASYNC */
    c5_assign_rule assign;  /* 0: C5_ASSIGN_KD */
    double link_bw;         /* bytes/s a board's port moves each way, 0: C5_LINK_BW_DEFAULT */
    double link_latency_s;  /* per exchange, 0: C5_LINK_LATENCY_DEFAULT, < 0: none */
    c5_mb_history *history; /* C5_ASSIGN_TREE: read and then updated each frame; NULL: kd */
} c5_mb_opts;

/* One board's share of a frame. */
typedef struct {
    int cells;                 /* cells it owns */
    uint64_t busy_cycles;      /* its board cycles (process + fetch stalls, eye-owner set-up included) */
    uint64_t link_cycles;      /* rounds: its port's time in the exchanges (latency + max(sent, received) /
                                * bandwidth); async: the time its busier port direction moved packets,
                                * beside the board's work */
    uint64_t idle_cycles;      /* rounds: frame_cycles - busy - link, async: frame_cycles - busy: waiting */
    uint64_t resident_loads;   /* async: loads of the cell still in RDRAM, not fetched */
    uint64_t packets_sent, packets_received;
    uint64_t fetches, fetch_bytes;
    uint64_t rays_processed;   /* rays taken from its eDRAM sorter */
} c5_mb_board;

typedef struct {
    int boards;
    c5_mb_mode mode;
    c5_assign_rule assign;
    double link_bw, link_latency_s; /* the link model used */
    uint64_t rounds;                /* rounds: exchanges (the last moves nothing: the termination round) */
    uint64_t exchanges;             /* async: the simulation's exchanges (no modelled time) */
    uint64_t frame_cycles;          /* rounds: sum over rounds of the slowest board's work and the slowest
                                     * port; async: the last board's last load's end, and two
                                     * latencies for the end to be detected and announced */
    double frame_s;                 /* frame_cycles at 100 MHz */
    uint64_t link_packets, link_bytes; /* between boards, all boards together */
    double balance;                 /* mean busy cycles / the largest: 1 is perfectly balanced */
    c5_mb_board board[C5_MB_MAX_BOARDS];
    c5_board_stats sum;             /* counters added over the boards; cycles and board_s: the frame's */
} c5_mb_stats;

const char *c5_assign_name(c5_assign_rule r);
/* "slab", "kd", "mod" -> the rule; 0: unknown. */
c5_assign_rule c5_assign_parse(const char *s);

/* The owner of each cell of an n[0] x n[1] x n[2] split (cell id x + n0 (y + n1 z)) among
 * `boards` boards: owner[count]. Every board owns at least one cell when there are as many
 * cells as boards. 0, or -1 with a message (boards outside 1..C5_MB_MAX_BOARDS). */
int c5_mb_assign(c5_assign_rule rule, const int n[3], int boards, uint16_t *owner, c5_err *err);

/* The tree rule on a traffic table (c5_mb_history.moves of this split): each cell's weight is
 * the rays it received (its column's sum, + 1); a k-d split cuts where the weights balance
 * (each side at least as many cells as boards), then passes move a cell to the board it
 * trades most rays with while no board's weight grows beyond the largest after the split and
 * 10 %, or the mean and the heaviest cell.
 * 0, or -1 with a message. */
int c5_mb_assign_tree(const int n[3], int boards, const uint64_t *moves, uint16_t *owner, c5_err *err);

/* The load rule on the board cycles each cell took (c5_mb_history.cost of this split): a k-d
 * split cut where the cycles balance, each side keeping at least a cell a board. 0, or -1 with
 * a message. */
int c5_mb_assign_load(const int n[3], int boards, const uint64_t *cost, uint16_t *owner, c5_err *err);

/* The cell split c5_board_render uses for these options and grid (the automatic one for
 * cells < 1). */
void c5_mb_split(const c5_board_opts *o, const c5_supervol *sv, int cells[3]);

/* Renders frame `frame` as board t->rank of t->size (base: the board options every board
 * uses, the link set here; keep: what this board keeps of its frame, or NULL; its frame_acc
 * and moves are set here). Every board gets the summed image in out and the frame's
 * statistics of every board in ms. With one board: c5_board_render unchanged (no link). 0,
 * or -1 with a message; after -1 on one board the others may wait in a collective: the
 * transport must end them (MPI_Abort). */
int c5_mb_render(const c5_scene *s, const c5_supervol *sv, int frame, const c5_board_opts *base,
                 const c5_board_out *keep, const c5_mb_opts *mo, const c5_mb_transport *t, c5_image *out,
                 c5_mb_stats *ms, c5_err *err);

/* Adds frame f's figures into a run's totals (counters and cycles add; balance is recomputed
 * from the summed busy cycles). */
void c5_mb_add(c5_mb_stats *sum, const c5_mb_stats *f);

/* The board statistics' counters added (a + b into a); queue_max and the tree sizes: the larger. */
void c5_board_stats_add(c5_board_stats *a, const c5_board_stats *b);

#endif
