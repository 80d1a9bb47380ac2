/* An out-of-core grid's cells on disk as the RDRAM holds them (cell_store.h). */
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "atomic_file.h"
#include "cache_dir.h"
#include "cell_store.h"
#include "voxsrc.h"
#include "worker_pool.h"

#define PAGE 4096
#define MAGIC "cube5 cells 1\n"
#define BATCH 8 /* cells read at once at most (a buffer each) */

struct c5_cell_store {
    uint8_t *base;
    size_t len;
    size_t *off;     /* [count + 1]: each cell's first byte; off[count] the file's size */
    int count, cached;
};

static size_t round_page(size_t n) { return (n + PAGE - 1) & ~(size_t)(PAGE - 1); }

static void header(const c5_supervol *sv, const c5_cells *c, char *out, size_t n)
{
    snprintf(out, n, MAGIC "%s\nsplit %d %d %d ghost %d\n", sv->grid_id, c->n[0], c->n[1], c->n[2], C5_GHOST);
}

/* A batch of cells read at once, one a worker: each into its own buffer, as c5_rdram_load
 * reads it but without dropping the planes after each cell (build drops a layer's). */
typedef struct {
    const c5_supervol *sv;
    const c5_cells *c;
    int first;
    c5_rdram m[BATCH];
    int rc[BATCH];
    c5_err err[BATCH];
} batch;

static void read_cell(void *ctx, size_t i, int worker)
{
    (void)worker;
    batch *b = ctx;
    c5_rdram *m = &b->m[i];
    if ((b->rc[i] = c5_rdram_place(m, b->c, b->first + (int)i, &b->err[i]) != 0))
        return;
    long lo[3] = {m->org[0], m->org[1], m->org[2]};
    long hi[3] = {lo[0] + m->ext[0], lo[1] + m->ext[1], lo[2] + m->ext[2]};
    b->rc[i] = c5_supervol_read_box(b->sv, lo, hi, m->v, &b->err[i]) != 0;
}

/* Writes every cell, in cell order, read as c5_rdram_load reads it: the host's cores read a
 * batch of cells at once (a generated volume's voxels are made then), the file gets them in
 * order, so its bytes do not depend on the threads. 0, -1 with err (a read of the grid
 * failed), or 1 (the cache file could not be written). */
static int build(const c5_supervol *sv, const c5_cells *c, const char *path, const char *head, const size_t *off,
                 c5_err *err)
{
    c5_afile a;
    c5_err werr;
    if (c5_afile_open(&a, path, &werr) != 0)
        return 1;
    static const uint8_t zeros[PAGE];
    size_t hl = strlen(head);
    c5_afile_write(&a, head, hl);
    c5_afile_write(&a, zeros, off[0] - hl);
    int threads = c5_pool_cpus() < BATCH ? c5_pool_cpus() : BATCH;
    c5_pool *pool = c5_pool_new(threads);
    batch *b = calloc(1, sizeof *b);
    int rc = pool && b ? 0 : (c5_fail(err, "out of memory for the cell store"), -1);
    for (int i = 0; b && i < BATCH; i++)
        b->m[i].cell = -1;
    if (b)
        b->sv = sv, b->c = c;
    int layer = c->n[0] * c->n[1], per = c5_pool_threads(pool);
    for (int first = 0; first < c->count && rc == 0; first += per) {
        int n = c->count - first < per ? c->count - first : per;
        b->first = first;
        c5_pool_run(pool, (size_t)n, 1, read_cell, b);
        for (int i = 0; i < n && rc == 0; i++) {
            int cell = first + i;
            if (b->rc[i]) {
                *err = b->err[i];
                rc = -1;
                break;
            }
            size_t bytes = c5_cell_bytes(c, cell);
            c5_afile_write(&a, b->m[i].v, bytes);
            c5_afile_write(&a, zeros, off[cell + 1] - off[cell] - bytes);
            /* a layer of cells shares its planes: they leave the process after its last
             * cell, not after each (a mapped file's pages; c5_supervol_done_reading) */
            if ((cell + 1) % layer == 0) {
                int lo[3], hi[3];
                c5_cell_box(c, cell, lo, hi);
                long blo[3] = {0, 0, lo[2] - C5_GHOST}, bhi[3] = {c->dims[0], c->dims[1], hi[2] + C5_GHOST};
                c5_supervol_done_reading(sv, blo, bhi);
            }
        }
    }
    for (int i = 0; b && i < BATCH; i++)
        c5_rdram_free(&b->m[i]);
    free(b);
    c5_pool_free(pool);
    if (rc != 0) {
        c5_afile_abort(&a);
        return rc;
    }
    return c5_afile_commit(&a, &werr) == 0 ? 0 : 1;
}

/* The file mapped if it is this grid's and split's, whole. */
static int map_existing(const char *path, const char *head, size_t total, c5_cell_store *s)
{
    int fd = open(path, O_RDONLY);
    if (fd < 0)
        return -1;
    struct stat st;
    size_t hl = strlen(head);
    char *got = malloc(hl);
    int ok = got && fstat(fd, &st) == 0 && (size_t)st.st_size == total && pread(fd, got, hl, 0) == (ssize_t)hl &&
             !memcmp(got, head, hl);
    free(got);
    void *p = ok ? mmap(NULL, total, PROT_READ, MAP_PRIVATE, fd, 0) : MAP_FAILED;
    close(fd);
    if (p == MAP_FAILED)
        return -1;
    c5_map_guard(path);
    s->base = p;
    s->len = total;
    return 0;
}

int c5_cell_store_open(const c5_supervol *sv, const c5_cells *c, c5_cell_store **out, c5_err *err)
{
    *out = NULL;
    char dir[3072], path[3200], head[C5_MAX_VOLUMES * 340 + 200];
    if (sv->v || !sv->store || !sv->grid_id[0] || c5_cache_dir(dir, sizeof dir) != 0)
        return 0;
    header(sv, c, head, sizeof head);
    c5_cell_store *s = calloc(1, sizeof *s);
    if (!s || !(s->off = malloc(((size_t)c->count + 1) * sizeof *s->off))) {
        free(s);
        return 0;
    }
    s->count = c->count;
    s->off[0] = round_page(strlen(head));
    for (int i = 0; i < c->count; i++)
        s->off[i + 1] = round_page(s->off[i] + c5_cell_bytes(c, i));
    snprintf(path, sizeof path, "%s/cells-%016llx.bin", dir, (unsigned long long)c5_cache_hash(head));
    if (map_existing(path, head, s->off[c->count], s) == 0) {
        s->cached = 1;
        c5_cache_touch(path);
    } else {
        int rc = c5_cache_make_room(dir, s->off[c->count]) != 0 ? 1 : build(sv, c, path, head, s->off, err);
        if (rc != 0 || map_existing(path, head, s->off[c->count], s) != 0) {
            c5_cell_store_close(s);
            return rc < 0 ? -1 : 0;
        }
    }
    *out = s;
    return 0;
}

void c5_cell_store_prefetch(c5_cell_store *s, int cell)
{
    if (cell >= 0 && cell < s->count)
        madvise(s->base + s->off[cell], s->off[cell + 1] - s->off[cell], MADV_WILLNEED);
}

const uint8_t *c5_cell_store_cell(c5_cell_store *s, int cell)
{
    c5_cell_store_prefetch(s, cell);
    return s->base + s->off[cell];
}

void c5_cell_store_release(c5_cell_store *s, int cell)
{
    madvise(s->base + s->off[cell], s->off[cell + 1] - s->off[cell], MADV_DONTNEED);
}

int c5_cell_store_was_cached(const c5_cell_store *s) { return s->cached; }

void c5_cell_store_close(c5_cell_store *s)
{
    if (!s)
        return;
    if (s->base)
        munmap(s->base, s->len);
    free(s->off);
    free(s);
}
