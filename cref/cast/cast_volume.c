/* The caster's volume: bricks with a one-voxel apron (every cell's 8 corners in one brick,
 * so a sample never looks outside its brick), the min/max octree over the bricks, and the
 * encoded per-voxel normals for shading. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cast_internal.h"

static size_t vidx(const c5_cast_volume *v, size_t i, size_t j, size_t k)
{
    return (k * v->dims[1] + j) * v->dims[0] + i;
}

static size_t clampz(long i, size_t n) { return i < 0 ? 0 : (size_t)i >= n ? n - 1 : (size_t)i; }

/* Copies brick (bx, by, bz) from the linear voxels into dst[C5_CAST_BSTRIDE], apron included;
 * positions past the volume repeat its last voxel (they are never sampled: a cell's corners
 * are within the volume). */
static void fill_brick(const c5_cast_volume *v, int bx, int by, int bz, uint8_t *dst)
{
    for (int z = 0; z < C5_CAST_BSIDE; z++)
        for (int y = 0; y < C5_CAST_BSIDE; y++)
            for (int x = 0; x < C5_CAST_BSIDE; x++) {
                size_t i = clampz(bx * C5_CAST_BRICK + x, v->dims[0]);
                size_t j = clampz(by * C5_CAST_BRICK + y, v->dims[1]);
                size_t k = clampz(bz * C5_CAST_BRICK + z, v->dims[2]);
                dst[(z * C5_CAST_BSIDE + y) * C5_CAST_BSIDE + x] = v->vox[vidx(v, i, j, k)];
            }
}

/* Min and max of the voxels that the n^3 cells from voxel (i0, j0, k0) reach: voxel indices
 * i0 .. i0+n per axis, within dims. */
static void box_minmax(const c5_cast_volume *v, size_t i0, size_t j0, size_t k0, int n, uint8_t mm[2])
{
    unsigned lo = 255, hi = 0;
    size_t i1 = clampz((long)i0 + n, v->dims[0]), j1 = clampz((long)j0 + n, v->dims[1]);
    size_t k1 = clampz((long)k0 + n, v->dims[2]);
    for (size_t k = clampz((long)k0, v->dims[2]); k <= k1; k++)
        for (size_t j = clampz((long)j0, v->dims[1]); j <= j1; j++)
            for (size_t i = clampz((long)i0, v->dims[0]); i <= i1; i++) {
                unsigned s = v->vox[vidx(v, i, j, k)];
                lo = s < lo ? s : lo;
                hi = s > hi ? s : hi;
            }
    mm[0] = (uint8_t)lo, mm[1] = (uint8_t)hi;
}

static int build_octree(c5_cast_volume *v, c5_err *err)
{
    for (int a = 0; a < 3; a++)
        v->ln[0][a] = v->nb[a];
    size_t n0 = (size_t)v->nb[0] * (size_t)v->nb[1] * (size_t)v->nb[2];
    if (!(v->minmax[0] = malloc(2 * n0)) || !(v->sub_minmax = malloc(2 * C5_CAST_SUBS * n0)))
        return c5_fail(err, "cast: out of memory for the octree");
    for (int bz = 0; bz < v->nb[2]; bz++)
        for (int by = 0; by < v->nb[1]; by++)
            for (int bx = 0; bx < v->nb[0]; bx++) {
                size_t b = c5_cast_brick_index(v, bx, by, bz), i0 = (size_t)bx * C5_CAST_BRICK;
                size_t j0 = (size_t)by * C5_CAST_BRICK, k0 = (size_t)bz * C5_CAST_BRICK;
                uint8_t *sm = v->sub_minmax + 2 * C5_CAST_SUBS * b, *mm = v->minmax[0] + 2 * b;
                mm[0] = 255, mm[1] = 0;
                /* the octants' voxel ranges together are exactly the brick's */
                for (int s = 0; s < C5_CAST_SUBS; s++, sm += 2) {
                    box_minmax(v, i0 + (s & 1) * C5_CAST_SUB, j0 + (s >> 1 & 1) * C5_CAST_SUB,
                               k0 + (s >> 2) * C5_CAST_SUB, C5_CAST_SUB, sm);
                    mm[0] = sm[0] < mm[0] ? sm[0] : mm[0];
                    mm[1] = sm[1] > mm[1] ? sm[1] : mm[1];
                }
            }
    int l = 0;
    while (v->ln[l][0] > 1 || v->ln[l][1] > 1 || v->ln[l][2] > 1) {
        const int *c = v->ln[l];
        int *p = v->ln[l + 1];
        for (int a = 0; a < 3; a++)
            p[a] = (c[a] + 1) / 2;
        if (!(v->minmax[l + 1] = malloc(2 * (size_t)p[0] * (size_t)p[1] * (size_t)p[2])))
            return c5_fail(err, "cast: out of memory for the octree");
        for (int z = 0; z < p[2]; z++)
            for (int y = 0; y < p[1]; y++)
                for (int x = 0; x < p[0]; x++) {
                    unsigned lo = 255, hi = 0;
                    for (int cz = 2 * z; cz < 2 * z + 2 && cz < c[2]; cz++)
                        for (int cy = 2 * y; cy < 2 * y + 2 && cy < c[1]; cy++)
                            for (int cx = 2 * x; cx < 2 * x + 2 && cx < c[0]; cx++) {
                                const uint8_t *m = v->minmax[l] + 2 * (((size_t)cz * c[1] + cy) * c[0] + cx);
                                lo = m[0] < lo ? m[0] : lo;
                                hi = m[1] > hi ? m[1] : hi;
                            }
                    uint8_t *m = v->minmax[l + 1] + 2 * (((size_t)z * p[1] + y) * p[0] + x);
                    m[0] = (uint8_t)lo, m[1] = (uint8_t)hi;
                }
        l++;
    }
    v->levels = l + 1;
    return 0;
}

int c5_cast_volume_make(const uint8_t *vox, const size_t dims[3], const double spacing[3], c5_cast_volume **out,
                        c5_err *err)
{
    *out = NULL;
    size_t count = 1;
    for (int a = 0; a < 3; a++) {
        if (dims[a] < 1 || dims[a] > 65535)
            return c5_fail(err, "cast: volume dims must be 1..65535 per axis (got %zu)", dims[a]);
        if (!(spacing[a] > 0) || !isfinite(spacing[a]))
            return c5_fail(err, "cast: volume spacing must be finite and > 0 (got %g)", spacing[a]);
        count *= dims[a];
    }
    c5_cast_volume *v = calloc(1, sizeof *v);
    if (!v)
        goto oom;
    pthread_mutex_init(&v->classified.mu, NULL);
    if (!(v->vox = malloc(count)))
        goto oom;
    memcpy(v->vox, vox, count);
    memcpy(v->dims, dims, sizeof v->dims);
    memcpy(v->spacing, spacing, sizeof v->spacing);
    int flat = 0;
    for (int a = 0; a < 3; a++) {
        v->cells[a] = (int)dims[a] - 1;
        v->nb[a] = (v->cells[a] + C5_CAST_BRICK - 1) / C5_CAST_BRICK;
        flat |= v->cells[a] == 0;
    }
    if (flat) { /* no thickness: the sample box is empty, every ray misses (VTK bounds) */
        v->nb[0] = v->nb[1] = v->nb[2] = 0;
        *out = v;
        return 0;
    }
    size_t nbricks = (size_t)v->nb[0] * (size_t)v->nb[1] * (size_t)v->nb[2];
    if (!(v->bricks = aligned_alloc(64, nbricks * C5_CAST_BSTRIDE)))
        goto oom;
    for (int bz = 0; bz < v->nb[2]; bz++)
        for (int by = 0; by < v->nb[1]; by++)
            for (int bx = 0; bx < v->nb[0]; bx++) {
                uint8_t *b = v->bricks + c5_cast_brick_index(v, bx, by, bz) * C5_CAST_BSTRIDE;
                fill_brick(v, bx, by, bz, b);
                memset(b + C5_CAST_BVOX, 0, C5_CAST_BSTRIDE - C5_CAST_BVOX);
            }
    if (build_octree(v, err)) {
        c5_cast_volume_free(v);
        return -1;
    }
    *out = v;
    return 0;
oom:
    c5_cast_volume_free(v);
    return c5_fail(err, "cast: out of memory for a %zux%zux%zu volume", dims[0], dims[1], dims[2]);
}

void c5_cast_volume_free(c5_cast_volume *v)
{
    if (!v)
        return;
    for (int l = 0; l < C5_CAST_MAX_LEVELS; l++) {
        free(v->minmax[l]);
        free(v->classified.cls[l]);
        free(v->classified.kids[l]);
    }
    free(v->classified.sub_mask);
    pthread_mutex_destroy(&v->classified.mu);
    free(v->sub_minmax);
    free(v->bricks);
    free(v->normals);
    free(v->vox);
    free(v);
}

/* ---- normals ------------------------------------------------------------------------- */

uint16_t c5_cast_normal_encode(double x, double y, double z)
{
    double s = fabs(x) + fabs(y) + fabs(z);
    if (!(s > 0))
        return C5_CAST_NZERO;
    double ox = x / s, oy = y / s;
    if (z < 0) { /* fold the lower half of the octahedron over the upper */
        double fx = (1 - fabs(oy)) * (ox < 0 ? -1 : 1), fy = (1 - fabs(ox)) * (oy < 0 ? -1 : 1);
        ox = fx, oy = fy;
    }
    const int q = 1 << C5_CAST_NBITS;
    int u = (int)floor((ox + 1) * 0.5 * q), w = (int)floor((oy + 1) * 0.5 * q);
    u = u < 0 ? 0 : u >= q ? q - 1 : u;
    w = w < 0 ? 0 : w >= q ? q - 1 : w;
    return (uint16_t)(u * q + w);
}

void c5_cast_normal_decode(uint16_t code, double n[3])
{
    if (code >= C5_CAST_NZERO) {
        n[0] = n[1] = n[2] = 0;
        return;
    }
    const int q = 1 << C5_CAST_NBITS;
    double ox = ((code / q) + 0.5) / q * 2 - 1, oy = ((code % q) + 0.5) / q * 2 - 1;
    double z = 1 - fabs(ox) - fabs(oy);
    if (z < 0) {
        double fx = (1 - fabs(oy)) * (ox < 0 ? -1 : 1), fy = (1 - fabs(ox)) * (oy < 0 ? -1 : 1);
        ox = fx, oy = fy;
    }
    double len = sqrt(ox * ox + oy * oy + z * z);
    n[0] = ox / len, n[1] = oy / len, n[2] = z / len;
}

/* VTK's gradient (peer README): central differences v[i-1] - v[i+1] per axis (one-sided at
 * the border, indices clamped), divided by spacing / mean spacing. */
static uint16_t voxel_normal(const c5_cast_volume *v, size_t i, size_t j, size_t k)
{
    double mean = (v->spacing[0] + v->spacing[1] + v->spacing[2]) / 3;
    size_t ix[2] = {i ? i - 1 : 0, i + 1 < v->dims[0] ? i + 1 : i};
    size_t jy[2] = {j ? j - 1 : 0, j + 1 < v->dims[1] ? j + 1 : j};
    size_t kz[2] = {k ? k - 1 : 0, k + 1 < v->dims[2] ? k + 1 : k};
    double gx = ((double)v->vox[vidx(v, ix[0], j, k)] - v->vox[vidx(v, ix[1], j, k)]) / (v->spacing[0] / mean);
    double gy = ((double)v->vox[vidx(v, i, jy[0], k)] - v->vox[vidx(v, i, jy[1], k)]) / (v->spacing[1] / mean);
    double gz = ((double)v->vox[vidx(v, i, j, kz[0])] - v->vox[vidx(v, i, j, kz[1])]) / (v->spacing[2] / mean);
    return c5_cast_normal_encode(gx, gy, gz);
}

int c5_cast_volume_normals(c5_cast_volume *v, c5_err *err)
{
    if (v->normals || !v->bricks)
        return 0;
    size_t nbricks = (size_t)v->nb[0] * (size_t)v->nb[1] * (size_t)v->nb[2];
    uint16_t *n = aligned_alloc(64, nbricks * C5_CAST_BSTRIDE * sizeof *n);
    if (!n)
        return c5_fail(err, "cast: out of memory for the normals");
    for (int bz = 0; bz < v->nb[2]; bz++)
        for (int by = 0; by < v->nb[1]; by++)
            for (int bx = 0; bx < v->nb[0]; bx++) {
                uint16_t *b = n + c5_cast_brick_index(v, bx, by, bz) * C5_CAST_BSTRIDE;
                for (int z = 0; z < C5_CAST_BSIDE; z++)
                    for (int y = 0; y < C5_CAST_BSIDE; y++)
                        for (int x = 0; x < C5_CAST_BSIDE; x++)
                            b[(z * C5_CAST_BSIDE + y) * C5_CAST_BSIDE + x] =
                                voxel_normal(v, clampz(bx * C5_CAST_BRICK + x, v->dims[0]),
                                             clampz(by * C5_CAST_BRICK + y, v->dims[1]),
                                             clampz(bz * C5_CAST_BRICK + z, v->dims[2]));
                for (int i = C5_CAST_BVOX; i < C5_CAST_BSTRIDE; i++)
                    b[i] = C5_CAST_NZERO;
            }
    v->normals = n;
    return 0;
}
