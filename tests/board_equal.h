/* Two renders of the board model compared bit for bit: every counter and cycle count of
 * c5_board_stats (host times aside) and the image. For the tests of the model's host-speed
 * paths, which must change no bit (test_rq_heap.c, test_board_fast.c). */
#ifndef C5_TEST_BOARD_EQUAL_H
#define C5_TEST_BOARD_EQUAL_H

#include "board.h"

/* 0, or -1 after reporting the first field that differs (what: which render). */
int c5t_board_stats_equal(const char *what, const c5_board_stats *a, const c5_board_stats *b);
/* 1 when both images have the same size and the same float bits. */
int c5t_same_image(const c5_image *a, const c5_image *b);

#endif
