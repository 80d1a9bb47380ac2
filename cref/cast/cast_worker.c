/* The workers (the paper's SPEs, sec. 5.1): march the producer's segments of each pixel's
 * ray, reconstruct trilinearly inside one brick, classify, shade, composite front to back
 * with early ray termination, and prefetch the brick the ray is heading for.
 *
 * Exactness across modes: sample j of a ray sits at t = j * step from the eye, computed from
 * j alone; a skipped sample has opacity exactly 0, and compositing such a sample adds +0 to
 * colour and opacity. So any mode that skips only such samples draws the same bits. */
#include <math.h>
#include <string.h>

#include "cast_internal.h"

static inline float lerp(float a, float b, float t) { return a + t * (b - a); }

static inline float tri(const float c[8], float fx, float fy, float fz)
{
    float x00 = lerp(c[0], c[1], fx), x10 = lerp(c[2], c[3], fx);
    float x01 = lerp(c[4], c[5], fx), x11 = lerp(c[6], c[7], fx);
    return lerp(lerp(x00, x10, fy), lerp(x01, x11, fy), fz);
}

/* Offsets of a cell's 8 corners inside a brick: x, then y, then z. */
enum { DX = 1, DY = C5_CAST_BSIDE, DZ = C5_CAST_BSIDE * C5_CAST_BSIDE };
static const int CORNER[8] = {0, DX, DY, DX + DY, DZ, DZ + DX, DZ + DY, DZ + DX + DY};

static inline void prefetch_brick(const c5_cast_view *vw, size_t bi)
{
    const char *b = (const char *)(vw->v->bricks + bi * C5_CAST_BSTRIDE);
    for (int i = 0; i < C5_CAST_BSTRIDE; i += 64)
        __builtin_prefetch(b + i);
    if (vw->shading) {
        const char *n = (const char *)(vw->v->normals + bi * C5_CAST_BSTRIDE);
        for (int i = 0; i < C5_CAST_BSTRIDE * 2; i += 64)
            __builtin_prefetch(n + i);
    }
}

/* One ray in the workers' float arithmetic: origin and direction in voxel units. */
typedef struct {
    float o[3], d[3], hi[3], step;
    int last[3];            /* last cell index per axis */
    size_t nb0, nb01;       /* brick strides */
} ray_f;

/* Sample position x = o + t d on one axis, clamped into [0, hi]: its cell (at most `last`)
 * and the fraction inside it. Every sample's position comes from this alone. */
static inline int cell(float o, float d, float hi, int last, float t, float *f)
{
    float x = o + t * d;
    x = x < 0 ? 0 : x;
    x = x > hi ? hi : x;
    int i = (int)x;
    i = i > last ? last : i;
    *f = x - (float)i;
    return i;
}

static inline size_t brick_of(const ray_f *r, int ix, int iy, int iz)
{
    return (size_t)((unsigned)iz / C5_CAST_BRICK) * r->nb01 + (size_t)((unsigned)iy / C5_CAST_BRICK) * r->nb0 +
           (size_t)((unsigned)ix / C5_CAST_BRICK);
}

/* Brick coordinates packed into one word: a change of brick is one compare. */
static inline uint64_t brick_key(int ix, int iy, int iz)
{
    return (uint64_t)((unsigned)ix / C5_CAST_BRICK) | (uint64_t)((unsigned)iy / C5_CAST_BRICK) << 21 |
           (uint64_t)((unsigned)iz / C5_CAST_BRICK) << 42;
}

/* The brick holding sample j (for the prefetch). */
static size_t brick_at(const ray_f *r, int32_t j)
{
    float t = (float)j * r->step, f;
    int ix = cell(r->o[0], r->d[0], r->hi[0], r->last[0], t, &f);
    int iy = cell(r->o[1], r->d[1], r->hi[1], r->last[1], t, &f);
    int iz = cell(r->o[2], r->d[2], r->hi[2], r->last[2], t, &f);
    return brick_of(r, ix, iy, iz);
}

/* The brick a ray is in, carried across its segments. */
typedef struct {
    uint64_t key;
    const uint8_t *b;
    const uint16_t *n;
    int skip;
    unsigned sub;           /* the brick's non-empty sub-bricks (all when not skipping) */
} brick_state;

/* Marches samples j0..j1 of one ray, compositing into acc (C0, C1, C2, A). Returns 1 when the
 * ray terminated early. Inlined with constant `shading` and `hash` (NULL or not), so each
 * variant's loop has no test it does not need. */
static inline int march_span(const c5_cast_view *vw, const ray_f *r, int32_t j0, int32_t j1, int32_t jout,
                             const uint64_t *hash, const int shading, float acc[4], brick_state *bs,
                             c5_cast_counts *cnt)
{
    const float(*rgba)[4] = vw->tf->rgba;
    const float(*shade)[2] = vw->shade;
    const int prefetch = vw->prefetch, early = vw->early, lookahead = vw->lookahead;
    const float o0 = r->o[0], o1 = r->o[1], o2 = r->o[2], d0 = r->d[0], d1 = r->d[1], d2 = r->d[2];
    const float h0 = r->hi[0], h1 = r->hi[1], h2 = r->hi[2], step = r->step;
    const int l0 = r->last[0], l1 = r->last[1], l2 = r->last[2];
    float C0 = acc[0], C1 = acc[1], C2 = acc[2], A = acc[3];
    uint64_t n_samples = 0, n_zero = 0, n_hashed = 0, n_sub = 0;
    int done = 0;
    for (int32_t j = j0; j <= j1; j++) {
        float t = (float)j * step, fx, fy, fz;
        int ix = cell(o0, d0, h0, l0, t, &fx), iy = cell(o1, d1, h1, l1, t, &fy), iz = cell(o2, d2, h2, l2, t, &fz);
        uint64_t key = brick_key(ix, iy, iz);
        if (key != bs->key) {
            bs->key = key;
            size_t bi = brick_of(r, ix, iy, iz);
            bs->b = vw->v->bricks + bi * C5_CAST_BSTRIDE;
            if (shading)
                bs->n = vw->v->normals + bi * C5_CAST_BSTRIDE;
            bs->sub = vw->sub_skip ? vw->sub_mask[bi] : 0xffu;
            if (hash) {
                uint32_t hk = c5_cast_hash_key(vw, ix / C5_CAST_BRICK, iy / C5_CAST_BRICK, iz / C5_CAST_BRICK);
                bs->skip = !(hash[hk / 64] >> (hk % 64) & 1);
            }
            if (prefetch) {
                size_t nb = brick_at(r, j + lookahead < jout ? j + lookahead : jout);
                if (nb != bi)
                    prefetch_brick(vw, nb);
            }
        }
        if (hash && bs->skip) {
            n_hashed++;
            continue;
        }
        unsigned sb = ((unsigned)ix / C5_CAST_SUB & 1) | ((unsigned)iy / C5_CAST_SUB & 1) << 1 |
                      ((unsigned)iz / C5_CAST_SUB & 1) << 2;
        if (!(bs->sub >> sb & 1)) { /* the TF is zero over the sub-brick's range: opacity 0 */
            n_sub++;
            continue;
        }
        n_samples++;
        int off = (int)((unsigned)ix % C5_CAST_BRICK + DY * ((unsigned)iy % C5_CAST_BRICK) +
                        DZ * ((unsigned)iz % C5_CAST_BRICK));
        const uint8_t *b = bs->b + off;
        float x00 = lerp(b[0], b[DX], fx), x10 = lerp(b[DY], b[DY + DX], fx);
        float x01 = lerp(b[DZ], b[DZ + DX], fx), x11 = lerp(b[DZ + DY], b[DZ + DY + DX], fx);
        float sv = lerp(lerp(x00, x10, fy), lerp(x01, x11, fy), fz);
        const float *e = rgba[(int)(sv * C5_CAST_TF_SCALE + 0.5f)];
        float a = e[3];
        /* no branch on a == 0: it is unpredictable, and compositing a zero sample adds +0 */
        n_zero += a == 0;
        float c0 = e[0], c1 = e[1], c2 = e[2];
        if (shading && a != 0) {
            const uint16_t *n = bs->n + off;
            float df[8], sp[8];
            for (int i = 0; i < 8; i++) {
                df[i] = shade[n[CORNER[i]]][0];
                sp[i] = shade[n[CORNER[i]]][1];
            }
            float kd = tri(df, fx, fy, fz), ks = a * tri(sp, fx, fy, fz);
            c0 = c0 * kd + ks, c1 = c1 * kd + ks, c2 = c2 * kd + ks;
        }
        float T = 1 - A;
        C0 += T * c0, C1 += T * c1, C2 += T * c2;
        A += T * a;
        if (early && A > C5_CAST_OPAQUE) {
            cnt->terminated++;
            done = 1;
            break;
        }
    }
    acc[0] = C0, acc[1] = C1, acc[2] = C2, acc[3] = A;
    cnt->samples += n_samples, cnt->zero += n_zero, cnt->hashed += n_hashed, cnt->sub += n_sub;
    return done;
}

/* The ray o + t d (voxel units per world t; inv[a] = 1/d[a], unused where d[a] == 0) against
 * the box [lo, hi]: 1 and its entry and exit t (entry clamped to t >= 0), or 0 on a miss. */
static int slab(const double o[3], const double d[3], const double inv[3], const double lo[3],
                               const double hi[3], double *tn, double *tf)
{
    double a = 0, b = 1.0 / 0.0;
    for (int i = 0; i < 3; i++) {
        if (d[i] == 0) {
            if (o[i] < lo[i] || o[i] > hi[i])
                return 0;
            continue;
        }
        double s0 = (lo[i] - o[i]) * inv[i], s1 = (hi[i] - o[i]) * inv[i];
        if (s0 > s1) {
            double s = s0;
            s0 = s1, s1 = s;
        }
        a = s0 > a ? s0 : a;
        b = s1 < b ? s1 : b;
    }
    *tn = a, *tf = b;
    return a <= b;
}

static void march(const c5_cast_view *vw, int px, int py, const c5_cast_seg *seg, int nseg, const uint64_t *hash,
                  float out[3], c5_cast_counts *cnt)
{
    const c5_cast_volume *v = vw->v;
    out[0] = out[1] = out[2] = 0;
    if (!v->bricks)
        return;
    double d[3], o[3], dv[3], inv[3], tin, tout, lo[3] = {0, 0, 0};
    c5_cast_ray_dir(vw, px + 0.5, py + 0.5, d);
    ray_f r;
    for (int a = 0; a < 3; a++) {
        o[a] = vw->eye_v[a];
        dv[a] = d[a] / v->spacing[a];
        inv[a] = dv[a] != 0 ? 1 / dv[a] : 0;
        r.o[a] = (float)o[a], r.d[a] = (float)dv[a], r.hi[a] = (float)vw->box_hi[a], r.last[a] = v->cells[a] - 1;
    }
    r.step = (float)vw->step;
    r.nb0 = (size_t)v->nb[0], r.nb01 = (size_t)v->nb[0] * (size_t)v->nb[1];
    if (!slab(o, dv, inv, lo, vw->box_hi, &tin, &tout))
        return;
    double jd_in = ceil(tin / vw->step), jd_out = floor(tout / vw->step);
    if (jd_out > C5_CAST_J_MAX)
        jd_out = C5_CAST_J_MAX;
    if (jd_in > jd_out)
        return;
    int32_t jin = (int32_t)jd_in, jout = (int32_t)jd_out;
    float acc[4] = {0, 0, 0, 0};
    brick_state bs = {UINT64_MAX, NULL, NULL, 0, 0xffu};
    for (int s = 0; s < nseg; s++) {
        int32_t j0 = seg[s].j0 > jin ? seg[s].j0 : jin, j1 = seg[s].j1 < jout ? seg[s].j1 : jout;
        int stop;
        if (vw->shading)
            stop = hash ? march_span(vw, &r, j0, j1, jout, hash, 1, acc, &bs, cnt)
                        : march_span(vw, &r, j0, j1, jout, NULL, 1, acc, &bs, cnt);
        else
            stop = hash ? march_span(vw, &r, j0, j1, jout, hash, 0, acc, &bs, cnt)
                        : march_span(vw, &r, j0, j1, jout, NULL, 0, acc, &bs, cnt);
        if (stop)
            break;
    }
    out[0] = acc[0], out[1] = acc[1], out[2] = acc[2];
}

void c5_cast_work(const c5_cast_view *vw, const c5_cast_task *t, float *rgb, c5_cast_counts *cnt)
{
    int u = 0;
    for (int uy = 0; uy < t->units_y; uy++)
        for (int ux = 0; ux < t->units_x; ux++, u++) {
            const c5_cast_seg *seg = t->seg + t->first[u];
            int nseg = (int)(t->first[u + 1] - t->first[u]);
            const uint64_t *hash = vw->mode == C5_CAST_APPROX_REFINE ? t->hash[u] : NULL;
            int px0 = t->x0 + ux * t->unit, py0 = t->y0 + uy * t->unit;
            for (int py = py0; py < py0 + t->unit && py < vw->h; py++)
                for (int px = px0; px < px0 + t->unit && px < vw->w && px < t->x0 + C5_CAST_TILE; px++)
                    march(vw, px, py, seg, nseg, hash, rgb + 3 * ((size_t)py * vw->w + px), cnt);
        }
}
