/* Several boards in one process: the multi-board layer (multi_board.h) over threads and a
 * barrier, one thread a board (the loopback transport). The boards' figures are the model's,
 * so they are the same as over MPI (cli/mpi_link.c) for the same options. */
#ifndef C5_MB_LOOPBACK_H
#define C5_MB_LOOPBACK_H

#include "multi_board.h"

/* Renders frame `frame` on `boards` boards, one thread each; board 0's image and statistics
 * into out and ms (keep: board 0's, or NULL; the other boards keep nothing and report no
 * progress). hist: each board's own history for the tree rule, hist[boards], kept by the
 * caller from frame to frame as each MPI rank keeps its own; NULL: kd for the tree rule.
 * Checks that every board ended with the same image and figures. 0, or -1 with a message. */
int c5_mb_render_loopback(const c5_scene *s, const c5_supervol *sv, int frame, const c5_board_opts *base,
                          const c5_board_out *keep, const c5_mb_opts *mo, int boards, c5_mb_history *hist,
                          c5_image *out, c5_mb_stats *ms, c5_err *err);

#endif
