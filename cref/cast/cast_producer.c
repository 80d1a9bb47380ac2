/* The producer (the paper's PPE, sec. 5.1): per tile, rays walk the min/max octree front to
 * back and keep the bricks the transfer function leaves non-empty, as segments (R, L) of the
 * ray, here already turned into ranges of sample indices.
 *
 * Approximation (sec. 5.2): only the rays through the corners of k x k subtiles are walked,
 * and each subtile takes the union of its 4 corners' lists. The paper's Figure 7 shows what
 * that misses: a brick that some pixel's ray crosses between the corner rays. So every box is
 * dilated by how far a pixel's ray can stray from its nearest corner ray before leaving the
 * volume (docs/caster.md): a pixel p and its nearest corner c (at most k/sqrt2 pixels apart)
 * have directions that differ by at most theta = (k/sqrt2) * 2 tan_half / h (the image plane
 * at distance 1 is flat, so the chord bounds the angle), so at distance t the two rays are at
 * most theta * t apart, and t never exceeds the far corner of the volume. A brick p crosses at
 * t is therefore crossed by c's dilated walk at the same t, and every mode stays exact.
 * Refining: each corner ray also sets the hash bits of the bricks it keeps. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cast_internal.h"

typedef struct {
    double o[3], inv[3];
    double sg_delta[3];       /* dilation per axis (voxel units), signed as the ray runs */
    int mask;                 /* child order: bit a set when the ray runs towards -a */
    double *t0, *t1;
    int n, cap;
    uint64_t *hash;
    int overflow;
    const c5_cast_view *vw;
} walk;

/* The walk is parametric: a node gets from its parent, per axis, the t at which the ray
 * enters and leaves its dilated slab, and splits them for its children with two planes per
 * axis (the mid plane moved by +-delta: dilated children overlap). Axes the ray runs parallel
 * to carry -inf/+inf (inside) or +inf/-inf (outside). Boxes are not clipped to the volume at
 * its far faces (a superset; the workers clip every ray to the volume). */
static void visit(walk *w, int l, int x, int y, int z, const double en[3], const double ex[3], double tn, double tf)
{
    const c5_cast_volume *v = w->vw->v;
    size_t node = ((size_t)z * v->ln[l][1] + y) * v->ln[l][0] + x;
    int cls = w->vw->cls[l][node];
    if (l == 0 || cls == C5_CAST_SOLID) {
        /* every brick below is non-empty: the union of their dilated boxes is this one's */
        if (w->n == w->cap) {
            w->overflow = 1;
            return;
        }
        w->t0[w->n] = tn, w->t1[w->n] = tf;
        w->n++;
        if (w->hash && l == 0) {
            uint32_t key = c5_cast_hash_key(w->vw, x, y, z);
            w->hash[key / 64] |= (uint64_t)1 << (key % 64);
        } else if (w->hash)
            for (int i = 0; i < C5_CAST_HASH_WORDS; i++)
                w->hash[i] |= w->vw->node_hash[l][node][i];
        return;
    }
    int side = C5_CAST_BRICK << l, idx[3] = {x, y, z};
    double near_ex[3], far_en[3];
    for (int a = 0; a < 3; a++) {
        double m = (double)idx[a] * side + side / 2;
        if (w->inv[a] != 0) {
            near_ex[a] = (m + w->sg_delta[a] - w->o[a]) * w->inv[a];
            far_en[a] = (m - w->sg_delta[a] - w->o[a]) * w->inv[a];
        } else {
            near_ex[a] = w->o[a] <= m + w->sg_delta[a] ? INFINITY : -INFINITY;
            far_en[a] = w->o[a] >= m - w->sg_delta[a] ? -INFINITY : INFINITY;
        }
    }
    /* Children in the ray's front-to-back order i (child o = i ^ mask): the non-empty ones,
     * less those whose near or far slab on some axis misses [tn, tf] (a cheap pre-test that
     * leaves about half; the full test below decides). */
    unsigned cand = w->vw->kids[l][node];
    if (w->mask & 1)
        cand = (cand & 0x55u) << 1 | (cand >> 1 & 0x55u);
    if (w->mask & 2)
        cand = (cand & 0x33u) << 2 | (cand >> 2 & 0x33u);
    if (w->mask & 4)
        cand = (cand & 0x0fu) << 4 | cand >> 4;
    static const unsigned near_kids[3] = {0x55, 0x33, 0x0f};
    double sel_en[3][2], sel_ex[3][2];
    for (int a = 0; a < 3; a++) {
        sel_en[a][0] = en[a], sel_ex[a][0] = near_ex[a];
        sel_en[a][1] = far_en[a], sel_ex[a][1] = ex[a];
        unsigned keep = 0;
        if ((en[a] > tn ? en[a] : tn) <= (near_ex[a] < tf ? near_ex[a] : tf))
            keep |= near_kids[a];
        if ((far_en[a] > tn ? far_en[a] : tn) <= (ex[a] < tf ? ex[a] : tf))
            keep |= ~near_kids[a] & 0xffu;
        cand &= keep;
    }
    while (cand && !w->overflow) {
        int i = __builtin_ctz(cand);
        cand &= cand - 1;
        int o = i ^ w->mask;
        double cen[3], cex[3], a0 = tn, b0 = tf;
        for (int a = 0; a < 3; a++) {
            int far = i >> a & 1;
            cen[a] = sel_en[a][far];
            cex[a] = sel_ex[a][far];
            a0 = cen[a] > a0 ? cen[a] : a0;
            b0 = cex[a] < b0 ? cex[a] : b0;
        }
        if (a0 <= b0)
            visit(w, l - 1, 2 * x + (o & 1), 2 * y + (o >> 1 & 1), 2 * z + (o >> 2 & 1), cen, cex, a0, b0);
    }
}

/* Sorts the intervals by start (they arrive nearly in order) and merges overlapping ones. */
static int merge_intervals(double *t0, double *t1, int n)
{
    for (int i = 1; i < n; i++) {
        double a = t0[i], b = t1[i];
        int j = i - 1;
        for (; j >= 0 && t0[j] > a; j--)
            t0[j + 1] = t0[j], t1[j + 1] = t1[j];
        t0[j + 1] = a, t1[j + 1] = b;
    }
    int m = 0;
    for (int i = 0; i < n; i++) {
        if (m && t0[i] <= t1[m - 1]) {
            if (t1[i] > t1[m - 1])
                t1[m - 1] = t1[i];
            continue;
        }
        t0[m] = t0[i], t1[m] = t1[i];
        m++;
    }
    return m;
}

int c5_cast_ray_segments(const c5_cast_view *vw, const double d[3], const double delta_v[3], double *t0, double *t1,
                         int cap, uint64_t *hash)
{
    const c5_cast_volume *v = vw->v;
    walk w = {.t0 = t0, .t1 = t1, .cap = cap, .hash = hash, .vw = vw};
    if (!v->bricks)
        return 0;
    int top = v->levels - 1;
    double side = C5_CAST_BRICK << top, en[3], ex[3], tn = 0, tf = INFINITY;
    for (int a = 0; a < 3; a++) {
        double da = d[a] / v->spacing[a];
        w.o[a] = vw->eye_v[a];
        w.inv[a] = da != 0 ? 1 / da : 0;
        w.mask |= (da < 0) << a;
        w.sg_delta[a] = da < 0 ? -delta_v[a] : delta_v[a];
        double lo = -delta_v[a], hi = side + delta_v[a];
        if (da != 0) {
            double s0 = (lo - w.o[a]) * w.inv[a], s1 = (hi - w.o[a]) * w.inv[a];
            en[a] = da < 0 ? s1 : s0, ex[a] = da < 0 ? s0 : s1;
        } else {
            int in = w.o[a] >= lo && w.o[a] <= hi;
            en[a] = in ? -INFINITY : INFINITY, ex[a] = in ? INFINITY : -INFINITY;
        }
        tn = en[a] > tn ? en[a] : tn;
        tf = ex[a] < tf ? ex[a] : tf;
    }
    if (tn <= tf && vw->cls[top][0] != C5_CAST_EMPTY)
        visit(&w, top, 0, 0, 0, en, ex, tn, tf);
    return w.overflow ? -1 : merge_intervals(t0, t1, w.n);
}

static size_t level_nodes(const c5_cast_volume *v, int l)
{
    return (size_t)v->ln[l][0] * (size_t)v->ln[l][1] * (size_t)v->ln[l][2];
}

/* A classification (per level its classes and child masks, the sub-brick masks) from one set of
 * arrays into another. */
static void copy_classes(const c5_cast_volume *v, size_t nsub, uint8_t *const cls[], uint8_t *const kids[],
                         const uint8_t *sub, uint8_t *const to_cls[], uint8_t *const to_kids[], uint8_t *to_sub)
{
    for (int l = 0; l < v->levels; l++) {
        memcpy(to_cls[l], cls[l], level_nodes(v, l));
        if (l > 0)
            memcpy(to_kids[l], kids[l], level_nodes(v, l));
    }
    memcpy(to_sub, sub, nsub);
}

/* The volume's kept classification into vw, when it was made for vw's table: 1, else 0. */
static int classified_take(c5_cast_volume *v, c5_cast_view *vw, size_t nsub)
{
    pthread_mutex_lock(&v->classified.mu);
    int hit = v->classified.valid && !memcmp(v->classified.nonzero, vw->tf->nonzero, sizeof v->classified.nonzero);
    if (hit)
        copy_classes(v, nsub, v->classified.cls, v->classified.kids, v->classified.sub_mask, vw->cls, vw->kids,
                     vw->sub_mask);
    pthread_mutex_unlock(&v->classified.mu);
    return hit;
}

/* Keeps vw's classification in the volume for the next frame (not when memory is short). */
static void classified_keep(c5_cast_volume *v, const c5_cast_view *vw, size_t nsub)
{
    pthread_mutex_lock(&v->classified.mu);
    int ok = v->classified.sub_mask || (v->classified.sub_mask = malloc(nsub));
    for (int l = 0; ok && l < v->levels; l++)
        ok = (v->classified.cls[l] || (v->classified.cls[l] = malloc(level_nodes(v, l)))) &&
             (l == 0 || v->classified.kids[l] || (v->classified.kids[l] = malloc(level_nodes(v, l))));
    v->classified.valid = ok;
    if (ok) {
        memcpy(v->classified.nonzero, vw->tf->nonzero, sizeof v->classified.nonzero);
        copy_classes(v, nsub, vw->cls, vw->kids, vw->sub_mask, v->classified.cls, v->classified.kids,
                     v->classified.sub_mask);
    }
    pthread_mutex_unlock(&v->classified.mu);
}

/* Bottom-up classification; see cast_internal.h. Without hashes, a frame whose table has the
 * non-zero entries of the volume's last classified frame copies that classification instead
 * (about half a millisecond of serial work a frame on a 256^3 volume, before the workers start). */
int c5_cast_view_classify(c5_cast_view *vw, int hashes)
{
    c5_cast_volume *v = (c5_cast_volume *)vw->v; /* only its kept classification changes */
    if (!v->bricks)
        return 0;
    /* 3 bytes more: cast_wide.c reads each brick's mask with a 32-bit gather */
    size_t nsub = (size_t)v->nb[0] * (size_t)v->nb[1] * (size_t)v->nb[2] + 3;
    if (!(vw->sub_mask = calloc(nsub, 1)))
        return -1;
    for (int l = 0; l < v->levels; l++)
        if (!(vw->cls[l] = malloc(level_nodes(v, l))) || (l > 0 && !(vw->kids[l] = malloc(level_nodes(v, l)))))
            return -1;
    if (!hashes && classified_take(v, vw, nsub))
        return 0;
    for (int l = 0; l < v->levels; l++) {
        size_t n = level_nodes(v, l);
        if (hashes && l > 0 && !(vw->node_hash[l] = calloc(n, sizeof *vw->node_hash[l])))
            return -1;
        for (int z = 0; z < v->ln[l][2]; z++)
            for (int y = 0; y < v->ln[l][1]; y++)
                for (int x = 0; x < v->ln[l][0]; x++) {
                    size_t node = ((size_t)z * v->ln[l][1] + y) * v->ln[l][0] + x;
                    if (l == 0) {
                        const uint8_t *mm = v->minmax[0] + 2 * node;
                        vw->cls[0][node] = c5_cast_tf_empty(vw->tf, mm[0], mm[1]) ? C5_CAST_EMPTY : C5_CAST_SOLID;
                        unsigned bits = 0;
                        for (int s = 0; s < C5_CAST_SUBS; s++) {
                            const uint8_t *sm = v->sub_minmax + 2 * (C5_CAST_SUBS * node + s);
                            bits |= (unsigned)!c5_cast_tf_empty(vw->tf, sm[0], sm[1]) << s;
                        }
                        vw->sub_mask[node] = (uint8_t)bits;
                        continue;
                    }
                    const int *c = v->ln[l - 1];
                    int all = 1;
                    unsigned kids = 0;
                    for (int i = 0; i < 8; i++) {
                        int cx = 2 * x + (i & 1), cy = 2 * y + (i >> 1 & 1), cz = 2 * z + (i >> 2 & 1);
                        if (cx >= c[0] || cy >= c[1] || cz >= c[2])
                            continue;
                        size_t ch = ((size_t)cz * c[1] + cy) * c[0] + cx;
                        int k = vw->cls[l - 1][ch];
                        kids |= (unsigned)(k != C5_CAST_EMPTY) << i, all &= k == C5_CAST_SOLID;
                        if (!hashes || k == C5_CAST_EMPTY)
                            continue;
                        uint64_t *h = vw->node_hash[l][node];
                        if (l == 1) {
                            uint32_t key = c5_cast_hash_key(vw, cx, cy, cz);
                            h[key / 64] |= (uint64_t)1 << (key % 64);
                        } else
                            for (int wd = 0; wd < C5_CAST_HASH_WORDS; wd++)
                                h[wd] |= vw->node_hash[l - 1][ch][wd];
                    }
                    vw->cls[l][node] = !kids ? C5_CAST_EMPTY : all ? C5_CAST_SOLID : C5_CAST_MIXED;
                    vw->kids[l][node] = (uint8_t)kids;
                }
    }
    if (!hashes)
        classified_keep(v, vw, nsub);
    return 0;
}

void c5_cast_view_release(c5_cast_view *vw)
{
    for (int l = 0; l < C5_CAST_MAX_LEVELS; l++) {
        free(vw->cls[l]);
        free(vw->kids[l]);
        free(vw->node_hash[l]);
        vw->cls[l] = NULL, vw->kids[l] = NULL, vw->node_hash[l] = NULL;
    }
    free(vw->shade);
    free(vw->sub_mask);
    c5_cast_corners_free(vw->corners);
    vw->shade = NULL, vw->sub_mask = NULL, vw->corners = NULL;
}

void c5_cast_ray_dir(const c5_cast_view *vw, double u, double v, double d[3])
{
    const c5_cast_camera *c = vw->cam;
    /* the peer's formula with its divisions hoisted: 2/w and 2/h per frame, one 1/len per ray */
    double su = (u * vw->two_over_w - 1) * c->tan_half, sv = (1 - v * vw->two_over_h) * c->tan_half;
    double q[3], len = 0;
    for (int a = 0; a < 3; a++) {
        q[a] = c->f[a] + su * c->right[a] + sv * c->up[a];
        len += q[a] * q[a];
    }
    double inv = 1 / sqrt(len);
    for (int a = 0; a < 3; a++)
        d[a] = q[a] * inv;
}

/* Room for n more segments in the task. */
static int reserve(c5_cast_task *t, uint32_t used, uint32_t n)
{
    if (used + n <= t->seg_cap)
        return 0;
    uint32_t cap = t->seg_cap ? t->seg_cap : 4096;
    while (cap < used + n)
        cap *= 2;
    c5_cast_seg *s = realloc(t->seg, cap * sizeof *s);
    if (!s)
        return -1;
    t->seg = s, t->seg_cap = cap;
    return 0;
}

/* Sample index range of [a, b] widened by the margin, as inclusive j0..j1 (j1 < j0: none). */
static c5_cast_seg to_indices(const c5_cast_view *vw, double a, double b)
{
    double j0 = ceil((a - vw->margin_t) / vw->step), j1 = floor((b + vw->margin_t) / vw->step);
    j0 = j0 < 0 ? 0 : j0 > C5_CAST_J_MAX ? C5_CAST_J_MAX : j0;
    j1 = j1 > C5_CAST_J_MAX ? C5_CAST_J_MAX : j1 < j0 - 1 ? j0 - 1 : j1;
    return (c5_cast_seg){(int32_t)j0, (int32_t)j1};
}

static const c5_cast_seg EVERYTHING = {0, C5_CAST_J_MAX};

/* One ray's segments as index ranges into out[0..C5_CAST_CORNER_MAX) and the hash bits of
 * its bricks. A ray with more intervals than the scratch holds keeps one segment over the
 * whole ray and sets every hash bit: slower, never wrong. */
static int ray_list(const c5_cast_view *vw, c5_cast_scratch *rs, double u, double v, c5_cast_seg *out,
                    uint64_t *hash)
{
    double d[3];
    c5_cast_ray_dir(vw, u, v, d);
    int n = 0;
    if (hash)
        memset(hash, 0, C5_CAST_HASH_WORDS * sizeof *hash);
    int m = c5_cast_ray_segments(vw, d, vw->delta_v, rs->t0, rs->t1, C5_CAST_RAY_MAX, hash);
    for (int i = 0; i < m && n >= 0; i++) {
        c5_cast_seg s = to_indices(vw, rs->t0[i], rs->t1[i]);
        if (s.j1 < s.j0)
            continue;
        if (n && s.j0 <= out[n - 1].j1 + 1) { /* no sample between: one segment */
            if (s.j1 > out[n - 1].j1)
                out[n - 1].j1 = s.j1;
        } else if (n == C5_CAST_CORNER_MAX)
            n = -1;
        else
            out[n++] = s;
    }
    if (m < 0 || n < 0) {
        out[0] = EVERYTHING;
        if (hash)
            memset(hash, 0xff, C5_CAST_HASH_WORDS * sizeof *hash);
        return 1;
    }
    return n;
}

/* Union of sorted, disjoint lists a and b into out (sorted, merged). */
static int union_lists(const c5_cast_seg *a, int na, const c5_cast_seg *b, int nb, c5_cast_seg *out)
{
    int i = 0, j = 0, n = 0;
    while (i < na || j < nb) {
        c5_cast_seg s = (j >= nb || (i < na && a[i].j0 <= b[j].j0)) ? a[i++] : b[j++];
        if (n && s.j0 <= out[n - 1].j1 + 1) {
            if (s.j1 > out[n - 1].j1)
                out[n - 1].j1 = s.j1;
        } else
            out[n++] = s;
    }
    return n;
}

c5_cast_scratch *c5_cast_scratch_new(void) { return malloc(sizeof(c5_cast_scratch)); }
void c5_cast_scratch_free(c5_cast_scratch *s) { free(s); }

/* plain: one segment per pixel over the whole ray (the worker clips it to the volume). */
static int produce_plain(c5_cast_task *t)
{
    int n = t->units_x * t->units_y;
    if (reserve(t, 0, (uint32_t)n))
        return -1;
    for (int u = 0; u < n; u++) {
        t->first[u] = (uint32_t)u;
        t->seg[u] = EVERYTHING;
    }
    t->first[n] = (uint32_t)n;
    return 0;
}

/* ess: every pixel's own ray through its centre, boxes undilated (margin only). */
static int produce_ess(const c5_cast_view *vw, c5_cast_scratch *rs, c5_cast_task *t)
{
    uint32_t used = 0;
    int u = 0;
    for (int y = 0; y < t->units_y; y++)
        for (int x = 0; x < t->units_x; x++, u++) {
            t->first[u] = used;
            if (reserve(t, used, C5_CAST_CORNER_MAX))
                return -1;
            used += (uint32_t)ray_list(vw, rs, t->x0 + x + 0.5, t->y0 + y + 0.5, t->seg + used, NULL);
            t->rays++;
        }
    t->first[u] = used;
    return 0;
}

/* Corner (a, b) of the frame's grid (pixel (a k, b k)): its list into out and its hash bits,
 * from the shared entry when the corner is on a tile border and another tile walked it. */
static int corner_list(const c5_cast_view *vw, c5_cast_scratch *rs, c5_cast_task *t, int a, int b, c5_cast_seg *out,
                       uint64_t *hash)
{
    int k = t->unit;
    long e = vw->corners ? c5_cast_corners_at(vw->corners, a, b) : -1;
    int got = e >= 0 ? c5_cast_corner_take(vw->corners, e, out, hash) : C5_CAST_CORNER_WALK_AGAIN;
    if (got >= 0)
        return got;
    int n = ray_list(vw, rs, a * k, b * k, out, hash);
    t->rays++;
    if (got == C5_CAST_CORNER_WALK)
        c5_cast_corner_put(vw->corners, e, out, n, hash);
    return n;
}

/* approx (+ refine): rays through the subtile grid's corners (pixel edges, not centres), one
 * row of corners at a time; each subtile the union of its 4 corners' lists and hashes. */
static int produce_approx(const c5_cast_view *vw, c5_cast_scratch *rs, c5_cast_task *t, int refine)
{
    int k = t->unit, cx = t->units_x + 1, cy = t->units_y + 1, a0 = t->x0 / k, b0 = t->y0 / k;
    uint32_t used = 0;
    int u = 0;
    for (int b = 0; b < cy; b++) {
        int r = b & 1, p = r ^ 1;
        for (int a = 0; a < cx; a++)
            rs->row_n[r][a] = corner_list(vw, rs, t, a0 + a, b0 + b, rs->row[r][a], refine ? rs->hash[r][a] : NULL);
        for (int a = 0; b > 0 && a < cx - 1; a++, u++) {
            t->first[u] = used;
            if (reserve(t, used, 4 * C5_CAST_CORNER_MAX))
                return -1;
            int n1 = union_lists(rs->row[p][a], rs->row_n[p][a], rs->row[p][a + 1], rs->row_n[p][a + 1], rs->tmp[0]);
            int n2 = union_lists(rs->row[r][a], rs->row_n[r][a], rs->row[r][a + 1], rs->row_n[r][a + 1], rs->tmp[1]);
            used += (uint32_t)union_lists(rs->tmp[0], n1, rs->tmp[1], n2, t->seg + used);
            for (int i = 0; refine && i < C5_CAST_HASH_WORDS; i++)
                t->hash[u][i] = rs->hash[p][a][i] | rs->hash[p][a + 1][i] | rs->hash[r][a][i] | rs->hash[r][a + 1][i];
        }
    }
    t->first[u] = used;
    return 0;
}

int c5_cast_produce(const c5_cast_view *vw, c5_cast_scratch *rs, int x0, int y0, c5_cast_task *t)
{
    int unit = vw->mode == C5_CAST_APPROX || vw->mode == C5_CAST_APPROX_REFINE ? vw->k : 1;
    t->x0 = x0, t->y0 = y0, t->unit = unit, t->rays = 0;
    int wpx = vw->w - x0 < C5_CAST_TILE ? vw->w - x0 : C5_CAST_TILE;
    int hpx = vw->h - y0 < C5_CAST_TILE ? vw->h - y0 : C5_CAST_TILE;
    t->units_x = (wpx + unit - 1) / unit, t->units_y = (hpx + unit - 1) / unit;
    switch (vw->mode) {
    case C5_CAST_PLAIN:
        return produce_plain(t);
    case C5_CAST_ESS:
        return produce_ess(vw, rs, t);
    default:
        return produce_approx(vw, rs, t, vw->mode == C5_CAST_APPROX_REFINE);
    }
}
