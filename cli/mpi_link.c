/* MPI collectives for rtl_model/multi_board.h: the packets with MPI_Alltoall (counts) and
 * MPI_Alltoallv (the 32-byte packets, ordered by sender), the round figures with
 * MPI_Allgather, the frame buffers with MPI_Allreduce. MPI_COMM_WORLD keeps MPI's default
 * handler, MPI_ERRORS_ARE_FATAL: a failed call ends the job; a rank that dies makes mpirun
 * end the others (docs/multi-board.md, "Failures"). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "mpi_link.h"

#ifdef C5_HAVE_MPI
#include <mpi.h>
#include <signal.h>

typedef struct {
    int size, rank;
    int *scount, *sdispl, *rcount, *rdispl;
    uint8_t (*sbuf)[C5_PACKET_BYTES], (*rbuf)[C5_PACKET_BYTES];
    size_t scap, rcap;
    long kill_at;      /* C5_MPI_TEST_KILL: the exchange at which this rank kills itself, -1: never */
    long fail_at;      /* C5_MPI_TEST_FAIL: the exchange at which this rank reports an error, -1: never */
    long exchanges;
} mpi_ctx;

static mpi_ctx ctx;

static int grow(uint8_t (**buf)[C5_PACKET_BYTES], size_t *cap, size_t n, c5_err *err)
{
    if (n <= *cap)
        return 0;
    void *p = realloc(*buf, n * C5_PACKET_BYTES);
    if (!p)
        return c5_fail(err, "out of memory for %zu packets", n);
    *buf = p;
    *cap = n;
    return 0;
}

static int alltoall(void *vc, const uint8_t (*out)[C5_PACKET_BYTES], const uint16_t *dest, size_t n_out,
                    const uint8_t (**in)[C5_PACKET_BYTES], size_t *n_in, c5_err *err)
{
    mpi_ctx *c = vc;
    /* The failure test (tests/mpi_test.sh): this rank dies mid-frame, the others must end. */
    if (c->kill_at >= 0 && c->exchanges == c->kill_at)
        raise(SIGKILL);
    if (c->fail_at >= 0 && c->exchanges == c->fail_at)
        return c5_fail(err, "a failure on purpose at exchange %ld (C5_MPI_TEST_FAIL)", c->exchanges);
    c->exchanges++;
    memset(c->scount, 0, (size_t)c->size * sizeof *c->scount);
    for (size_t i = 0; i < n_out; i++)
        c->scount[dest[i]]++;
    if (grow(&c->sbuf, &c->scap, n_out, err) != 0)
        return -1;
    int at = 0;
    for (int k = 0; k < c->size; k++) {
        c->sdispl[k] = at;
        at += c->scount[k];
    }
    for (size_t i = 0; i < n_out; i++) /* by receiver, each receiver's in the board's order */
        memcpy(c->sbuf[c->sdispl[dest[i]]++], out[i], C5_PACKET_BYTES);
    MPI_Alltoall(c->scount, 1, MPI_INT, c->rcount, 1, MPI_INT, MPI_COMM_WORLD);
    long long total = 0;
    for (int k = 0; k < c->size; k++) {
        if ((long long)c->scount[k] * C5_PACKET_BYTES > 0x7fffffff || (long long)c->rcount[k] * C5_PACKET_BYTES > 0x7fffffff)
            return c5_fail(err, "more than 2 GB of packets between two boards in one round");
        c->rdispl[k] = (int)(total * C5_PACKET_BYTES);
        total += c->rcount[k];
        c->scount[k] *= C5_PACKET_BYTES;
        c->rcount[k] *= C5_PACKET_BYTES;
        c->sdispl[k] -= c->scount[k] / C5_PACKET_BYTES;
        c->sdispl[k] *= C5_PACKET_BYTES;
    }
    if (total * C5_PACKET_BYTES > 0x7fffffff)
        return c5_fail(err, "more than 2 GB of packets for one board in one round");
    if (grow(&c->rbuf, &c->rcap, (size_t)total, err) != 0)
        return -1;
    MPI_Alltoallv(c->sbuf, c->scount, c->sdispl, MPI_BYTE, c->rbuf, c->rcount, c->rdispl, MPI_BYTE, MPI_COMM_WORLD);
    *in = (const uint8_t (*)[C5_PACKET_BYTES])c->rbuf;
    *n_in = (size_t)total;
    return 0;
}

static int allgather(void *vc, const void *mine, size_t bytes, void *all, c5_err *err)
{
    (void)vc;
    if (bytes > 0x7fffffff)
        return c5_fail(err, "allgather of %zu bytes", bytes);
    MPI_Allgather(mine, (int)bytes, MPI_BYTE, all, (int)bytes, MPI_BYTE, MPI_COMM_WORLD);
    return 0;
}

static int sum_u64(void *vc, uint64_t *v, size_t n, c5_err *err)
{
    (void)vc;
    (void)err;
    for (size_t at = 0; at < n;) { /* counts are ints */
        int part = n - at > (1u << 30) ? 1 << 30 : (int)(n - at);
        MPI_Allreduce(MPI_IN_PLACE, v + at, part, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
        at += (size_t)part;
    }
    return 0;
}

int c5_mpi_begin(int boards, c5_mb_transport *t, c5_err *err)
{
    const char *env = getenv("OMPI_COMM_WORLD_SIZE");
    if (!env || atoi(env) != boards)
        return c5_fail(err, "--boards %d: run cube5 as %d MPI ranks, e.g. 'mpirun -np %d cube5 ... --boards %d' "
                       "(%s; docs/multi-board.md)", boards, boards, boards, boards,
                       env ? "mpirun started a different number of ranks" : "not started by mpirun");
    MPI_Init(NULL, NULL);
    MPI_Comm_size(MPI_COMM_WORLD, &ctx.size);
    MPI_Comm_rank(MPI_COMM_WORLD, &ctx.rank);
    size_t n = (size_t)ctx.size;
    ctx.scount = calloc(n, sizeof(int));
    ctx.sdispl = calloc(n, sizeof(int));
    ctx.rcount = calloc(n, sizeof(int));
    ctx.rdispl = calloc(n, sizeof(int));
    if (!ctx.scount || !ctx.sdispl || !ctx.rcount || !ctx.rdispl)
        return c5_fail(err, "out of memory");
    const char *kill = getenv("C5_MPI_TEST_KILL"); /* "RANK:EXCHANGE" */
    int kr = -1;
    long ke = 0;
    ctx.kill_at = kill && sscanf(kill, "%d:%ld", &kr, &ke) == 2 && kr == ctx.rank ? ke : -1;
    const char *fail = getenv("C5_MPI_TEST_FAIL"); /* "RANK:EXCHANGE": the error path */
    ctx.fail_at = fail && sscanf(fail, "%d:%ld", &kr, &ke) == 2 && kr == ctx.rank ? ke : -1;
    *t = (c5_mb_transport){&ctx, ctx.rank, ctx.size, alltoall, allgather, sum_u64};
    return 0;
}

void c5_mpi_fail(const c5_mb_transport *t, const char *msg, int code)
{
    fprintf(stderr, "cube5: error: board %d: %s\n", t->rank, msg);
    fflush(stderr);
    MPI_Abort(MPI_COMM_WORLD, code);
    exit(code);
}

void c5_mpi_end(void)
{
    free(ctx.scount), free(ctx.sdispl), free(ctx.rcount), free(ctx.rdispl), free(ctx.sbuf), free(ctx.rbuf);
    MPI_Finalize();
}

#else

int c5_mpi_begin(int boards, c5_mb_transport *t, c5_err *err)
{
    (void)t;
    return c5_fail(err, "--boards %d: this cube5 was built without MPI, which several boards need: install Open MPI "
                   "(bash scripts/setup-deps.sh demo, or apt-get install libopenmpi-dev openmpi-bin), rebuild "
                   "(make), and run 'mpirun -np %d cube5 ... --boards %d' (docs/multi-board.md)", boards, boards, boards);
}

void c5_mpi_fail(const c5_mb_transport *t, const char *msg, int code)
{
    (void)t;
    fprintf(stderr, "cube5: error: %s\n", msg);
    exit(code);
}

void c5_mpi_end(void) {}

#endif
