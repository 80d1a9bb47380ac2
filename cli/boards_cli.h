/* The several-boards options shared by render, compare and schedule (--boards, --assign,
 * --link-bw, --link-latency) and the per-board report (text and JSON). */
#ifndef C5_BOARDS_CLI_H
#define C5_BOARDS_CLI_H

#include <jansson.h>

#include "mpi_link.h"
#include "opt_table.h"
#include "multi_board.h"

typedef struct {
    long boards;          /* --boards, 1 when not given */
    c5_mb_opts mo;
    int given;            /* any of the options given */
    int loopback;         /* --loopback: the boards are threads of this process */
    const c5_link_preset *link; /* --link NAME, or NULL; --link-bw and --link-latency win over it */
    int mpi;              /* c5_mpi_begin succeeded: t is the transport */
    c5_mb_transport t;
    c5_mb_history hist;   /* --assign tree: the previous frame's traffic */
    c5_mb_history *hist_lb; /* --loopback: each board's */
} c5_boards_args;

/* --boards, --assign, --link-bw, --link-latency: fields of a c5_boards_args. */
extern const c5_opt c5_boards_opts[];
/* After parsing: with N > 1 joins the MPI job (an input error when it cannot). */
int c5_boards_begin(c5_boards_args *b, c5_err *err);
/* Frame f on the boards (MPI ranks, --loopback threads, or the only board); keep: this
 * board's (board 0's with --loopback). 0, or -1 with a message. */
int c5_boards_render(const c5_boards_args *b, const c5_scene *s, const c5_supervol *sv, int f, const c5_board_opts *o,
                     const c5_board_out *keep, c5_image *img, c5_mb_stats *ms, c5_err *err);
/* 1 on the board that prints and writes files (board 0, or the only one). */
int c5_boards_leader(const c5_boards_args *b);
void c5_boards_end(c5_boards_args *b);

json_t *c5_cli_mb_json(const c5_mb_stats *ms);
void c5_cli_mb_print(const c5_mb_stats *ms);

#endif
