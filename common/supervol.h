/* The super volume: the scene's one 8-bit grid (the volume the board splits into cells).
 * Voxel (i,j,k) is centred at origin + (i+0.5, j+0.5, k+0.5) * spacing; the grid fills the
 * box [origin, origin + dims * spacing). */
#ifndef C5_SUPERVOL_H
#define C5_SUPERVOL_H

#include <stddef.h>
#include <stdint.h>

#include "err.h"
#include "scene.h"

struct c5_svstore;

typedef struct {
    size_t dims[3];
    c5_vec3 origin, spacing;
    uint8_t *v;           /* resident: dims[0]*dims[1]*dims[2], x fastest; NULL when the scene has
                             no volume (dims 0), when the grid is out of core (store), or a shell */
    /* what was placed, for summaries */
    int n_sources;
    char source_label[C5_MAX_VOLUMES][160];
    /* where the spacing came from (docs/scene-format.md, "Spacing"): "scene" (grid.spacing),
     * "file NAME" (a volume file's own spacing) or "default" (1, 1, 1); before grid.size */
    char spacing_source[180];
    /* Out of core (docs/out-of-core.md): the grid is above the memory budget, so its voxels
     * stay in their sources (files read at an offset, generators evaluated per voxel), read
     * box by box and through a brick cache of the budget's size; NULL when resident. */
    struct c5_svstore *store;
    /* A resident grid that is one uint8 file's voxels is that file mapped read-only (v points
     * into the mapping; never written): no copy, and only the pages a frame reads are read. */
    void *map_base;
    size_t map_len;
    /* The grid is one file's voxels, at offset 0 and of the grid's dims: the file's identity
     * (c5_voxsrc_identity), by which what is derived from the voxels is cached; "" otherwise. */
    char file_id[320];
    /* Every source's identity with its offset, the fill and the dims: the grid's, for caches
     * of an out-of-core grid (rtl_model/mem/cell_store.h); "" when a source has none. */
    char grid_id[C5_MAX_VOLUMES * 340 + 64];
    /* The value range of every 8^3 block, computed on first use (block_range.h), or NULL. */
    struct c5_block_range *ranges;
} c5_supervol;

/* The memory budget, bytes: a grid of at most this many voxels is held whole (resident);
 * a larger one is out of core behind a brick cache of this many bytes. */
#define C5_MEM_BUDGET_DEFAULT ((size_t)1 << 30)
/* The least C5_MEM_BUDGET taken: one set of the brick cache, 8 bricks of 32^3 voxels
 * (256 KiB): a trilinear sample's 2x2x2 voxels may lie in 8 bricks, and a cache of fewer
 * evicts within one sample. */
#define C5_MEM_BUDGET_MIN (((size_t)8) << 15)
/* C5_MEM_BUDGET from the environment (a byte count, with an optional suffix K, M, G or T,
 * powers of 1024), else C5_MEM_BUDGET_DEFAULT; -1 with err when set but not such a size. */
int c5_mem_budget(size_t *out, c5_err *err);
/* A byte count from environment variable `name` (digits, an optional K, M, G or T, powers of
 * 1024, and an optional B or iB), else dflt; -1 with "NAME: ..." when set but not such a
 * count, or zero. */
int c5_env_bytes(const char *name, size_t dflt, size_t *out, c5_err *err);
/* The brick cache's bricks: C5_BRICK^3 voxels, aligned to the grid. */
#define C5_BRICK_LOG2 5
#define C5_BRICK (1 << C5_BRICK_LOG2)

/* Loads or generates every volume of the scene, maps uint16 through its window, places
 * each at its offset and resolves the grid's dims, spacing and origin (grid.center). The
 * spacing is the scene's grid.spacing when it gives one, else the files' own spacing (they
 * must agree), else (1, 1, 1); grid.size then scales it. A scene without volumes gives an
 * empty super volume (v == NULL). */
int c5_supervol_build(const c5_scene *s, c5_supervol *out, c5_err *err);
/* The same with the budget given (c5_supervol_build takes c5_mem_budget's). */
int c5_supervol_build_budget(const c5_scene *s, size_t budget, c5_supervol *out, c5_err *err);
void c5_supervol_free(c5_supervol *sv);
/* The grid's voxels where they lie in the host's address space, x fastest (voxel (x, y, z) at
 * [(z Y + y) X + x]): the resident grid, or the read-only mapping of the one uint8 file an
 * out-of-core grid is (its pages the kernel's, read from the file on demand); NULL: neither
 * (out of core from other sources: read boxes). */
const uint8_t *c5_supervol_data(const c5_supervol *sv);
/* A reader of an out-of-core grid (c5_supervol_data, or large boxes of one mapped file) is
 * about to read voxels [lo, hi) (the kernel starts reading their pages now, plane by plane),
 * or is done with them (the process's pages of the span are dropped, so host memory stays
 * bounded; they are read again when needed). No-ops for a resident grid. */
void c5_supervol_will_read(const c5_supervol *sv, const long lo[3], const long hi[3]);
void c5_supervol_done_reading(const c5_supervol *sv, const long lo[3], const long hi[3]);
/* The resident voxels handed to the caller as a malloc'd array (a mapping copied), sv freed
 * after; NULL: out of memory (sv freed too). */
uint8_t *c5_supervol_detach(c5_supervol *sv);

/* Voxels [lo, hi) of the grid (clamp-to-edge outside it) into out, x fastest, (hi - lo)
 * per axis: voxel (x, y, z) at out[((z - lo[2]) (hi[1] - lo[1]) + y - lo[1]) (hi[0] - lo[0])
 * + x - lo[0]] = c5_supervol_at(sv, x, y, z). Out of core, small boxes go through the brick
 * cache and large ones (C5_SV_DIRECT_VOXELS and up) straight to the sources; either way the
 * bits are the grid's. Thread-safe. 0, or -1 with err (a file that fails to read). */
#define C5_SV_DIRECT_VOXELS ((size_t)4 << (3 * C5_BRICK_LOG2))
int c5_supervol_read_box(const c5_supervol *sv, const long lo[3], const long hi[3], uint8_t *out, c5_err *err);
/* The same where no error can be passed on (a renderer's inner loop): on a read failure it
 * prints "cube5: error: MSG" and exits with C5_EXIT_INPUT. */
void c5_supervol_read_box_or_exit(const c5_supervol *sv, const long lo[3], const long hi[3], uint8_t *out);
/* Out of core: the brick cache's counters and capacity (all 0 when resident). */
typedef struct {
    unsigned long long hits, misses;
    size_t bricks, bytes;
} c5_supervol_cache_stats;
void c5_supervol_cache_stats_get(const c5_supervol *sv, c5_supervol_cache_stats *st);
/* The caster (cube5 cast, sweep --knob k) holds its volume whole: its refusal of an
 * out-of-core grid, "WHAT: the grid of XxYxZ voxels is above the memory budget ...", -1. */
int c5_supervol_cast_refusal(const c5_supervol *sv, const char *what, c5_err *err);
unsigned c5_supervol_at_store(const c5_supervol *sv, long i, long j, long k);

/* The analytic Marschner-Lobb signal (f_m, alpha) that the marschner_lobb generator samples
 * when it fills this whole grid, at world point p: value in 0..255 and its gradient per world
 * unit. The generator maps voxel centre (i + 0.5) / n onto [-1, 1] (generators.c), so the
 * signal at p is rho(2 (p - origin) / extent - 1). The analytic reference of tests and sweeps. */
void c5_supervol_marschner_lobb(const c5_supervol *sv, double f_m, double alpha, c5_vec3 p, double *value,
                                c5_vec3 *grad);

/* No volume: the scene is surfaces only. A grid with dims but v == NULL is a shell: its
 * geometry without its voxels, as the emulated board knows it (the voxels stay in the host's
 * memory and arrive cell by cell, c5_board_host). */
static inline int c5_supervol_empty(const c5_supervol *sv) { return !sv->dims[0] || !sv->dims[1] || !sv->dims[2]; }
static inline double c5_supervol_min_spacing(const c5_supervol *sv)
{
    return fmin(sv->spacing.x, fmin(sv->spacing.y, sv->spacing.z));
}
/* c5_supervol_at of a resident grid (v != NULL), without the test. */
static inline unsigned c5_supervol_at_resident(const c5_supervol *sv, long i, long j, long k)
{
    long nx = (long)sv->dims[0], ny = (long)sv->dims[1], nz = (long)sv->dims[2];
    i = i < 0 ? 0 : i >= nx ? nx - 1 : i;
    j = j < 0 ? 0 : j >= ny ? ny - 1 : j;
    k = k < 0 ? 0 : k >= nz ? nz - 1 : k;
    return sv->v[((size_t)k * (size_t)ny + (size_t)j) * (size_t)nx + (size_t)i];
}
/* Voxel value with indices clamped to the grid (clamp-to-edge); out of core through the
 * brick cache (c5_supervol_read_box_or_exit). */
static inline unsigned c5_supervol_at(const c5_supervol *sv, long i, long j, long k)
{
    long nx = (long)sv->dims[0], ny = (long)sv->dims[1], nz = (long)sv->dims[2];
    i = i < 0 ? 0 : i >= nx ? nx - 1 : i;
    j = j < 0 ? 0 : j >= ny ? ny - 1 : j;
    k = k < 0 ? 0 : k >= nz ? nz - 1 : k;
    if (__builtin_expect(!sv->v, 0))
        return c5_supervol_at_store(sv, i, j, k);
    return sv->v[((size_t)k * (size_t)ny + (size_t)j) * (size_t)nx + (size_t)i];
}

#endif
