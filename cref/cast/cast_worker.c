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

/* Sample j's position (voxel units, clamped into the volume): its brick, the offset of its
 * cell inside the brick, the fractions; bc receives the brick's coordinates. */
static inline size_t locate(const ray_f *r, int32_t j, float f[3], int *off, int bc[3])
{
    float t = (float)j * r->step;
    int lc[3];
    for (int a = 0; a < 3; a++) {
        float x = r->o[a] + t * r->d[a];
        x = x < 0 ? 0 : x;
        x = x > r->hi[a] ? r->hi[a] : x;
        int i = (int)x;
        i = i > r->last[a] ? r->last[a] : i;
        f[a] = x - (float)i;
        bc[a] = (unsigned)i / C5_CAST_BRICK;
        lc[a] = (unsigned)i % C5_CAST_BRICK;
    }
    *off = lc[0] + DY * lc[1] + DZ * lc[2];
    return (size_t)bc[2] * r->nb01 + (size_t)bc[1] * r->nb0 + (size_t)bc[0];
}

static void march(const c5_cast_view *vw, int px, int py, const c5_cast_seg *seg, int nseg, const uint64_t *hash,
                  float out[3], c5_cast_counts *cnt)
{
    const c5_cast_volume *v = vw->v;
    const float(*rgba)[4] = vw->tf->rgba;
    const uint8_t *bricks = v->bricks;
    const uint16_t *normals = v->normals;
    const float(*shade)[2] = vw->shade;
    out[0] = out[1] = out[2] = 0;
    if (!bricks)
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
    if (!c5_cast_slab(o, dv, inv, lo, vw->box_hi, &tin, &tout))
        return;
    double jd_in = ceil(tin / vw->step), jd_out = floor(tout / vw->step);
    if (jd_out > C5_CAST_J_MAX)
        jd_out = C5_CAST_J_MAX;
    if (jd_in > jd_out)
        return;
    int32_t jin = (int32_t)jd_in, jout = (int32_t)jd_out;
    const int prefetch = vw->prefetch, shading = vw->shading, early = vw->early, lookahead = vw->lookahead;
    float C0 = 0, C1 = 0, C2 = 0, A = 0;
    uint64_t n_samples = 0, n_zero = 0, n_hashed = 0;
    size_t last = (size_t)-1;
    int skip = 0;
    for (int s = 0; s < nseg; s++) {
        int32_t j0 = seg[s].j0 > jin ? seg[s].j0 : jin, j1 = seg[s].j1 < jout ? seg[s].j1 : jout;
        for (int32_t j = j0; j <= j1; j++) {
            float f[3];
            int off, bc[3];
            size_t bi = locate(&r, j, f, &off, bc);
            if (bi != last) {
                last = bi;
                if (hash) {
                    uint32_t key = c5_cast_hash_key(vw, bc[0], bc[1], bc[2]);
                    skip = !(hash[key / 64] >> (key % 64) & 1);
                }
                if (prefetch) {
                    float g[3];
                    int o2, bc2[3];
                    size_t nb = locate(&r, j + lookahead < jout ? j + lookahead : jout, g, &o2, bc2);
                    if (nb != bi)
                        prefetch_brick(vw, nb);
                }
            }
            if (skip) {
                n_hashed++;
                continue;
            }
            n_samples++;
            const uint8_t *b = bricks + bi * C5_CAST_BSTRIDE + off;
            float fx = f[0], fy = f[1], fz = f[2];
            float x00 = lerp(b[0], b[DX], fx), x10 = lerp(b[DY], b[DY + DX], fx);
            float x01 = lerp(b[DZ], b[DZ + DX], fx), x11 = lerp(b[DZ + DY], b[DZ + DY + DX], fx);
            float sv = lerp(lerp(x00, x10, fy), lerp(x01, x11, fy), fz);
            const float *e = rgba[(int)(sv * C5_CAST_TF_SCALE + 0.5f)];
            float a = e[3];
            /* no branch on a == 0: it is unpredictable, and compositing a zero sample adds +0 */
            n_zero += a == 0;
            float c0 = e[0], c1 = e[1], c2 = e[2];
            if (shading && a != 0) {
                const uint16_t *n = normals + bi * C5_CAST_BSTRIDE + off;
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
                goto done;
            }
        }
    }
done:
    cnt->samples += n_samples, cnt->zero += n_zero, cnt->hashed += n_hashed;
    out[0] = C0, out[1] = C1, out[2] = C2;
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
