/* Several boards in one process (rtl_model/multi_board.h over threads and a barrier): the
 * transport the unit tests use to check the multi-board layer without MPI. */
#ifndef C5_TEST_MB_LOOPBACK_H
#define C5_TEST_MB_LOOPBACK_H

#include "multi_board.h"

/* Renders the frame on `boards` boards, one thread each; board 0's image and statistics into
 * out and ms. Also checks that every board ended with the same image and figures (-1 and a
 * message if not). 0, or -1 after printing the error. */
int c5t_mb_render(const c5_scene *s, const c5_supervol *sv, int frame, const c5_board_opts *base,
                  const c5_mb_opts *mo, int boards, c5_image *out, c5_mb_stats *ms);
/* The same with each board's own history for the tree rule: hist[boards], kept by the caller
 * from frame to frame (as each MPI rank keeps its own). */
int c5t_mb_render_hist(const c5_scene *s, const c5_supervol *sv, int frame, const c5_board_opts *base,
                       const c5_mb_opts *mo, int boards, c5_mb_history *hist, c5_image *out, c5_mb_stats *ms);

#endif
