/* The several-boards options shared by render, compare and schedule (--boards, --assign,
 * --link-bw, --link-latency) and the per-board report (text and JSON). */
#ifndef C5_BOARDS_CLI_H
#define C5_BOARDS_CLI_H

#include <jansson.h>

#include "mpi_link.h"
#include "multi_board.h"

typedef struct {
    long boards;          /* --boards, 1 when not given */
    c5_mb_opts mo;
    int given;            /* any of the options given */
    int mpi;              /* c5_mpi_begin succeeded: t is the transport */
    c5_mb_transport t;
    c5_mb_history hist;   /* --assign tree: the previous frame's traffic */
} c5_boards_args;

#define C5_BOARDS_HELP                                                                              \
    "  --boards N        rtl only: N boards share the super volume, one MPI rank each: run as\n"      \
    "                    'mpirun -np N cube5 ... --boards N' (docs/multi-board.md); the image is\n"   \
    "                    the same bits for any N\n"                                                    \
    "  --assign R        how cells go to boards: kd (default, a k-d split), slab, mod (scattered),\n" \
    "                    or tree (from the previous frame's rays between cells; kd in frame 0)\n"  \
    "  --link-bw MB/S    inter-board link bandwidth each way per board (default 125: Gigabit\n"      \
    "                    Ethernet)\n"                                                                 \
    "  --link-latency US inter-board latency per exchange round in us (default 50)\n"

/* 1: argv[*i] was one of the options (its value consumed), 0: not one, -1: a bad value. */
int c5_boards_option(int argc, char **argv, int *i, c5_boards_args *b, c5_err *err);
/* After parsing: with N > 1 joins the MPI job (an input error when it cannot). */
int c5_boards_begin(c5_boards_args *b, c5_err *err);
/* 1 on the board that prints and writes files (board 0, or the only one). */
int c5_boards_leader(const c5_boards_args *b);
void c5_boards_end(c5_boards_args *b);

json_t *c5_cli_mb_json(const c5_mb_stats *ms);
void c5_cli_mb_print(const c5_mb_stats *ms);

#endif
