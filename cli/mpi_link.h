/* The boards' transport over MPI (docs/multi-board.md): the only place cube5 calls MPI.
 * Built with MPI when the Makefile finds Open MPI (pkg-config ompi-c; C5_HAVE_MPI), without
 * otherwise: then one board works and more say how to get MPI. */
#ifndef C5_MPI_LINK_H
#define C5_MPI_LINK_H

#include "multi_board.h"

/* Joins the MPI job as one of `boards` boards (boards > 1; MPI_Init): 0 with the transport,
 * or -1 with a message (no MPI in this build, not started by mpirun with that many ranks):
 * an input error (exit 2). */
int c5_mpi_begin(int boards, c5_mb_transport *t, c5_err *err);

/* After c5_mpi_begin: a failure on this board ends every board (MPI_Abort with `code`)
 * after printing "cube5: error: board R: MSG"; never returns. */
void c5_mpi_fail(const c5_mb_transport *t, const char *msg, int code);

/* After c5_mpi_begin: MPI_Finalize. */
void c5_mpi_end(void);

#endif
