/* One frame of the streaming model (the paper's Figures 2, 3 and 5): the calling thread is
 * the producer; it walks the 16x16 tiles in Z-order and hands tile i to worker i mod W
 * through that worker's bounded buffer (a ring of queue_depth task entries, the paper's
 * 4-entry mailbox), blocking while the ring is full. Each worker renders its tiles into
 * disjoint pixels, so the image has the same bits for any worker count. */
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cast_internal.h"
#include "cast_sample.h"
#include "rng.h"
#include "clock.h"
#include "worker_pool.h"

static const char *const MODE_NAMES[C5_CAST_MODES] = {"plain", "ess", "approx", "approx+refine"};

const char *c5_cast_mode_name(c5_cast_mode m) { return m >= 0 && m < C5_CAST_MODES ? MODE_NAMES[m] : "?"; }

/* The index of s in names[0..n), or -1. */
static int name_index(const char *s, const char *const *names, int n)
{
    for (int i = 0; i < n; i++)
        if (!strcmp(s, names[i]))
            return i;
    return -1;
}

int c5_cast_mode_parse(const char *s, c5_cast_mode *m)
{
    int i = name_index(s, MODE_NAMES, C5_CAST_MODES);
    if (i >= 0)
        *m = (c5_cast_mode)i;
    return i < 0 ? -1 : 0;
}

static const char *const PREFETCH_NAMES[C5_CAST_PREFETCHES] = {"off", "cells", "bricks"};

const char *c5_cast_prefetch_name(c5_cast_prefetch p)
{
    return p >= 0 && p < C5_CAST_PREFETCHES ? PREFETCH_NAMES[p] : "?";
}

int c5_cast_prefetch_parse(const char *s, c5_cast_prefetch *p)
{
    int i = name_index(s, PREFETCH_NAMES, C5_CAST_PREFETCHES);
    if (i >= 0)
        *p = (c5_cast_prefetch)i;
    return i < 0 ? -1 : 0;
}

void c5_cast_opts_default(c5_cast_opts *o)
{
    *o = (c5_cast_opts){.mode = C5_CAST_APPROX, .k = 0, .workers = 2, .producer = -1, .shading = 0,
                        .prefetch = C5_CAST_PREFETCH_CELLS,
                        .sub_bricks = 1, .self_produce = 1, .early_termination = 1, .step = 0, .queue_depth = 4,
                        .wide = -1};
}

static double min_spacing(const c5_cast_volume *v) { return fmin(v->spacing[0], fmin(v->spacing[1], v->spacing[2])); }

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* Farthest distance from p to a corner of the volume's world box, and the farthest signed
 * distance along f from p. */
static void far_corner(const c5_cast_volume *v, const double p[3], const double f[3], double *dist, double *along)
{
    *dist = 0, *along = -INFINITY;
    for (int c = 0; c < 8; c++) {
        double q[3], d2 = 0;
        for (int a = 0; a < 3; a++) {
            q[a] = (c >> a & 1 ? v->cells[a] * v->spacing[a] : 0) - p[a];
            d2 += q[a] * q[a];
        }
        *dist = fmax(*dist, sqrt(d2));
        *along = fmax(*along, dot3(q, f));
    }
}

int c5_cast_prop1_k(const c5_cast_volume *v, const c5_cast_camera *cam, int w, int h)
{
    double e[3], dist_e, dist_v, unused;
    for (int a = 0; a < 3; a++)
        e[a] = cam->focal[a] - cam->eye[a];
    dist_e = dot3(e, cam->f); /* eye to the image plane through the focal point */
    far_corner(v, cam->focal, cam->f, &unused, &dist_v);
    if (!(dist_e > dist_v))
        return 1;
    double pitch = 2 * dist_e * cam->tan_half / (w > h ? w : h);
    double half_brick = C5_CAST_BRICK * min_spacing(v) / 2;
    int k = C5_CAST_TILE;
    while (k > 1 && k * pitch > half_brick)
        k /= 2;
    return k;
}

int c5_cast_default_k(const c5_cast_volume *v, const c5_cast_camera *cam, int w, int h)
{
    int k = c5_cast_prop1_k(v, cam, w, h);
    return k < C5_CAST_K_LOW ? C5_CAST_K_LOW : k > C5_CAST_K_HIGH ? C5_CAST_K_HIGH : k;
}

double c5_cast_load_imbalance(const c5_cast_stats *st)
{
    if (st->workers < 2)
        return 0;
    double m = 0, s = 0;
    for (int i = 0; i < st->workers; i++)
        m += st->worker_s[i];
    m /= st->workers;
    for (int i = 0; i < st->workers; i++)
        s += (st->worker_s[i] - m) * (st->worker_s[i] - m);
    return m > 0 ? 100 * sqrt(s / st->workers) / m : 0;
}

/* The frame's constants: step, eye in voxel units, k, the producer's dilation (docs/caster.md),
 * the hash factors and, when shading, the headlight's factors per normal code. */
int c5_cast_view_setup(c5_cast_view *vw, const c5_cast_volume *v, const c5_cast_tf *tf, const c5_cast_camera *cam, int w,
                       int h, const c5_cast_opts *o, c5_err *err)
{
    memset(vw, 0, sizeof *vw);
    vw->v = v, vw->tf = tf, vw->cam = cam, vw->w = w, vw->h = h, vw->mode = o->mode;
    vw->two_over_w = 2.0 / w, vw->two_over_h = 2.0 / h;
    vw->shading = o->shading, vw->prefetch = o->prefetch, vw->early = o->early_termination;
    vw->sub_skip = o->sub_bricks && o->mode != C5_CAST_PLAIN; /* plain marches every sample */
    vw->wide = o->wide != 0 && o->mode != C5_CAST_APPROX_REFINE && o->prefetch != C5_CAST_PREFETCH_BRICKS &&
               c5_cast_wide_usable(v);
    double ms = min_spacing(v);
    vw->step = o->step > 0 ? o->step : ms;
    int approx = o->mode == C5_CAST_APPROX || o->mode == C5_CAST_APPROX_REFINE;
    vw->k = !approx ? 1 : o->k > 0 ? o->k : c5_cast_default_k(v, cam, w, h);
    double t_far, unused, eye_len = sqrt(dot3(cam->eye, cam->eye));
    far_corner(v, cam->eye, cam->f, &t_far, &unused);
    /* a pixel's ray is at most k/2 pixels from its nearest corner ray along each image axis */
    double du = approx ? vw->k / 2.0 * 2 * cam->tan_half / w : 0, dv = approx ? vw->k / 2.0 * 2 * cam->tan_half / h : 0;
    double theta = sqrt(du * du + dv * dv);
    /* float positions of the workers stray from the exact rays by a few ulps of their size */
    double eps = 1e-3 * ms + 1e-5 * (eye_len + t_far);
    for (int a = 0; a < 3; a++) {
        vw->eye_v[a] = cam->eye[a] / v->spacing[a];
        vw->box_hi[a] = v->cells[a];
        vw->clamp_hi[a] = c5_cast_clamp_hi(v->cells[a]);
        vw->delta_v[a] = (theta * t_far + eps) / v->spacing[a];
    }
    vw->margin_t = eps;
    vw->lookahead = (int)ceil(C5_CAST_BRICK * ms / vw->step);
    uint64_t st = 0xC5CA57ull;
    for (int a = 0; a < 3; a++)
        vw->hash_r[a] = 1 + c5_splitmix64(&st) % (C5_CAST_HASH_PR - 1);
    if (c5_cast_view_classify(vw, o->mode == C5_CAST_APPROX_REFINE))
        return c5_fail(err, "cast: out of memory for the octree's classification");
    if (approx && !(vw->corners = c5_cast_corners_new(w, h, vw->k)))
        return c5_fail(err, "cast: out of memory for the corner rays");
    if (!o->shading)
        return 0;
    if (v->bricks && !v->normals)
        return c5_fail(err, "cast: shading needs the volume's normals (c5_cast_volume_normals)");
    if (!(vw->shade = malloc(sizeof *vw->shade * C5_CAST_NCODES)))
        return c5_fail(err, "cast: out of memory for the shading table");
    for (int c = 0; c < C5_CAST_NCODES; c++) {
        double n[3];
        c5_cast_normal_decode((uint16_t)c, n);
        /* two-sided headlight: L = H = towards the eye = -f; no gradient: ambient only */
        double ndl = fabs(dot3(n, cam->f));
        vw->shade[c][0] = (float)(tf->ambient + tf->diffuse * ndl);
        vw->shade[c][1] = ndl > 0 ? (float)(tf->specular * pow(ndl, tf->specular_power)) : 0.0f;
    }
    return 0;
}

/* ---- the bounded buffers ---------------------------------------------------------------- */

/* Worker w's buffer and its share of the tiles (global tiles w, w + W, w + 2W, ...): `next`
 * counts those claimed for production, `pending` those the producer claimed but has not
 * published yet. All under mu. */
typedef struct {
    pthread_mutex_t mu;
    pthread_cond_t cv;
    c5_cast_task *slot;
    int depth, head, count;
    int next, n, pending;
} ring;

typedef struct {
    const c5_cast_view *vw;
    ring *r;
    int index, workers, self_produce;
    const int *tiles;
    float *rgb;
    c5_cast_counts cnt;
    c5_cast_task own;        /* a tile this worker produces itself */
    c5_cast_scratch *rs;
    uint64_t rays, segments, tiles_own;
    double busy_s, wait_s, produce_s;
    int failed;
} worker;

/* Production of one tile into t, counted into the given totals. */
static int produce(const c5_cast_view *vw, c5_cast_scratch *rs, const int *tiles, int i, c5_cast_task *t,
                   uint64_t *rays, uint64_t *segments)
{
    if (c5_cast_produce(vw, rs, tiles[2 * i], tiles[2 * i + 1], t))
        return -1;
    *rays += t->rays;
    *segments += t->first[t->units_x * t->units_y];
    return 0;
}

/* A worker renders the tasks of its buffer. When the buffer is empty and some of its tiles
 * are still unclaimed, it produces the next one itself instead of waiting (self_produce):
 * with more threads than cores the producer thread often sits in the run queue while the
 * workers starve. Tiles stay statically assigned, so the image is the same either way. */
static void *worker_main(void *arg)
{
    worker *wk = arg;
    ring *r = wk->r;
    double t0 = c5_now_s();
    pthread_mutex_lock(&r->mu);
    for (;;) {
        if (!r->count) {
            if (wk->self_produce && r->next < r->n && !wk->failed) {
                int i = wk->index + r->next++ * wk->workers;
                pthread_mutex_unlock(&r->mu);
                double p0 = c5_now_s();
                wk->failed = produce(wk->vw, wk->rs, wk->tiles, i, &wk->own, &wk->rays, &wk->segments);
                wk->produce_s += c5_now_s() - p0;
                if (!wk->failed) {
                    c5_cast_work(wk->vw, &wk->own, wk->rgb, &wk->cnt);
                    wk->tiles_own++;
                }
                pthread_mutex_lock(&r->mu);
                continue;
            }
            if (r->next == r->n && !r->pending)
                break;
            double w0 = c5_now_s();
            pthread_cond_wait(&r->cv, &r->mu);
            wk->wait_s += c5_now_s() - w0;
            continue;
        }
        c5_cast_task *t = &r->slot[r->head];
        pthread_mutex_unlock(&r->mu);
        c5_cast_work(wk->vw, t, wk->rgb, &wk->cnt);
        pthread_mutex_lock(&r->mu);
        r->head = (r->head + 1) % r->depth;
        r->count--;
        pthread_cond_broadcast(&r->cv);
    }
    pthread_mutex_unlock(&r->mu);
    wk->busy_s = c5_now_s() - t0 - wk->wait_s - wk->produce_s;
    return NULL;
}

/* The producer's side: claims the worker's next tile (-1 when the worker claimed them all)
 * and the free entry it goes to, blocking while the buffer is full. */
static c5_cast_task *ring_claim(ring *r, int *k, double *wait_s)
{
    pthread_mutex_lock(&r->mu);
    if (r->next == r->n) {
        pthread_mutex_unlock(&r->mu);
        return NULL;
    }
    *k = r->next++;
    r->pending++;
    double w0 = c5_now_s();
    while (r->count == r->depth)
        pthread_cond_wait(&r->cv, &r->mu);
    *wait_s += c5_now_s() - w0;
    c5_cast_task *t = &r->slot[(r->head + r->count) % r->depth];
    pthread_mutex_unlock(&r->mu);
    return t;
}

/* Publishes the claimed entry (or, when production failed, just drops the claim). */
static void ring_publish(ring *r, int filled)
{
    pthread_mutex_lock(&r->mu);
    r->count += filled;
    r->pending--;
    pthread_cond_broadcast(&r->cv);
    pthread_mutex_unlock(&r->mu);
}

/* Tile origins in Z-order (Morton order of the tile grid). */
static int *zorder_tiles(int ntx, int nty, int *n)
{
    int side = 1;
    while (side < ntx || side < nty)
        side *= 2;
    int *out = malloc(sizeof *out * 2 * (size_t)ntx * (size_t)nty);
    if (!out)
        return NULL;
    *n = 0;
    for (long m = 0; m < (long)side * side; m++) {
        int x = 0, y = 0;
        for (int b = 0; b < 16; b++) {
            x |= (int)((m >> (2 * b)) & 1) << b;
            y |= (int)((m >> (2 * b + 1)) & 1) << b;
        }
        if (x < ntx && y < nty) {
            out[2 * *n] = x * C5_CAST_TILE, out[2 * *n + 1] = y * C5_CAST_TILE;
            (*n)++;
        }
    }
    return out;
}

static int check_args(const c5_cast_volume *v, const c5_cast_camera *cam, int w, int h, const c5_cast_opts *o,
                      const c5_image *out, c5_err *err)
{
    if (w < 1 || h < 1 || w > 16384 || h > 16384)
        return c5_fail(err, "cast: image size must be 1..16384 per side (got %dx%d)", w, h);
    if (o->workers < 1 || o->workers > C5_CAST_MAX_WORKERS)
        return c5_fail(err, "cast: workers must be 1..%d (got %d)", C5_CAST_MAX_WORKERS, o->workers);
    if (o->k && o->k != 1 && o->k != 2 && o->k != 4 && o->k != 8 && o->k != 16)
        return c5_fail(err, "cast: k must be 1, 2, 4, 8 or 16 (got %d)", o->k);
    if (o->producer < -1 || o->producer > 1)
        return c5_fail(err, "cast: producer must be -1 (auto), 0 or 1 (got %d)", o->producer);
    if (o->producer == 0 && !o->self_produce)
        return c5_fail(err, "cast: with no producer thread (producer 0) the workers must produce their own tiles "
                            "(self_produce 1)");
    if (o->queue_depth < 0 || o->queue_depth > 1024)
        return c5_fail(err, "cast: queue depth must be 0..1024 (got %d)", o->queue_depth);
    if (o->mode < 0 || o->mode >= C5_CAST_MODES)
        return c5_fail(err, "cast: unknown mode %d", (int)o->mode);
    if (o->prefetch < 0 || o->prefetch >= C5_CAST_PREFETCHES)
        return c5_fail(err, "cast: unknown prefetch %d", (int)o->prefetch);
    if (o->wide < -1 || o->wide > 1)
        return c5_fail(err, "cast: wide must be -1 (auto), 0 or 1 (got %d)", o->wide);
    if (o->wide == 1 && !c5_cast_wide_usable(v))
        return c5_fail(err, "cast: eight samples at a time (wide 1) needs an x86-64 build, a CPU with AVX2 and "
                            "under 2 GiB of bricks");
    if (!(o->step >= 0) || !isfinite(o->step))
        return c5_fail(err, "cast: step must be finite and >= 0 (got %g)", o->step);
    if (!(cam->tan_half > 0) || !isfinite(cam->tan_half))
        return c5_fail(err, "cast: the camera's view angle must be in (0, 180) degrees");
    for (int a = 0; a < 3; a++)
        if (!isfinite(cam->eye[a]) || !isfinite(cam->f[a]) || !isfinite(cam->right[a]) || !isfinite(cam->up[a]))
            return c5_fail(err, "cast: the camera has a non-finite component");
    if (out->rgb && (out->w != w || out->h != h))
        return c5_fail(err, "cast: the output image is %dx%d, not %dx%d", out->w, out->h, w, h);
    return 0;
}

int c5_cast_render(const c5_cast_volume *v, const c5_cast_tf *tf, const c5_cast_camera *cam, int w, int h,
                   const c5_cast_opts *o, c5_image *out, c5_cast_stats *st, c5_err *err)
{
    double t_start = c5_now_s();
    memset(st, 0, sizeof *st);
    if (check_args(v, cam, w, h, o, out, err))
        return -1;
    c5_cast_view vw;
    if (c5_cast_view_setup(&vw, v, tf, cam, w, h, o, err)) {
        c5_cast_view_release(&vw);
        return -1;
    }
    int nw = o->workers, depth = o->queue_depth ? o->queue_depth : 4, ntiles = 0, rc = -1, allocated = 0;
    int *tiles = zorder_tiles((w + C5_CAST_TILE - 1) / C5_CAST_TILE, (h + C5_CAST_TILE - 1) / C5_CAST_TILE, &ntiles);
    ring *rings = calloc((size_t)nw, sizeof *rings);
    worker *wk = calloc((size_t)nw, sizeof *wk);
    pthread_t *th = calloc((size_t)nw, sizeof *th);
    c5_cast_task *slots = calloc((size_t)nw * (size_t)depth, sizeof *slots);
    c5_cast_scratch *rs = c5_cast_scratch_new();
    int started = 0, failed = 0;
    if (!tiles || !rings || !wk || !th || !slots || !rs)
        goto oom;
    int refine = o->mode == C5_CAST_APPROX_REFINE;
    for (int i = 0; i < nw * depth && refine; i++)
        if (!(slots[i].hash = malloc(sizeof *slots[i].hash * C5_CAST_TILE * C5_CAST_TILE)))
            goto oom;
    for (int i = 0; i < nw && o->self_produce; i++)
        if (!(wk[i].rs = c5_cast_scratch_new()) ||
            (refine && !(wk[i].own.hash = malloc(sizeof *wk[i].own.hash * C5_CAST_TILE * C5_CAST_TILE))))
            goto oom;
    if (!out->rgb) {
        if (c5_image_alloc(out, w, h, err))
            goto done;
        allocated = 1;
    }
    for (started = 0; started < nw; started++) {
        ring *r = &rings[started];
        pthread_mutex_init(&r->mu, NULL);
        pthread_cond_init(&r->cv, NULL);
        r->slot = slots + (size_t)started * depth, r->depth = depth;
        r->n = (ntiles - started + nw - 1) / nw;
        worker *k = &wk[started];
        k->vw = &vw, k->r = r, k->index = started, k->workers = nw, k->self_produce = o->self_produce;
        k->tiles = tiles, k->rgb = out->rgb;
        if (pthread_create(&th[started], NULL, worker_main, k)) {
            pthread_mutex_destroy(&r->mu);
            pthread_cond_destroy(&r->cv);
            failed = 1;
            break;
        }
    }
    /* auto: a producer thread beside as many workers as there are CPUs only takes CPU time
     * from them (docs/caster.md, "The producer thread"); the workers then produce every tile */
    int producer = o->producer >= 0 ? o->producer : !o->self_produce || nw < c5_cpus_usable();
    double t0 = c5_now_s();
    for (int i = 0; producer && i < ntiles && !failed; i++) {
        ring *r = &rings[i % nw];
        int k;
        c5_cast_task *t = ring_claim(r, &k, &st->producer_wait_s);
        if (!t)
            continue; /* the worker produced the rest of its tiles itself */
        int bad = produce(&vw, rs, tiles, i % nw + k * nw, t, &st->producer_rays, &st->segments);
        ring_publish(r, !bad);
        failed |= bad;
        st->tiles += !bad;
    }
    for (int i = 0; producer && i < started; i++) { /* nothing more will be claimed: lets the workers finish */
        pthread_mutex_lock(&rings[i].mu);
        rings[i].n = rings[i].next;
        pthread_cond_broadcast(&rings[i].cv);
        pthread_mutex_unlock(&rings[i].mu);
    }
    st->producer_s = c5_now_s() - t0 - st->producer_wait_s;
    for (int i = 0; i < started; i++) {
        pthread_join(th[i], NULL);
        pthread_mutex_destroy(&rings[i].mu);
        pthread_cond_destroy(&rings[i].cv);
        st->worker_s[i] = wk[i].busy_s, st->worker_wait_s[i] = wk[i].wait_s;
        st->producer_s += wk[i].produce_s, st->producer_rays += wk[i].rays, st->segments += wk[i].segments;
        st->tiles += wk[i].tiles_own, st->tiles_self += wk[i].tiles_own;
        st->samples += wk[i].cnt.samples, st->samples_zero += wk[i].cnt.zero;
        st->samples_hashed += wk[i].cnt.hashed, st->rays_terminated += wk[i].cnt.terminated;
        st->samples_sub += wk[i].cnt.sub;
        failed |= wk[i].failed;
    }
    st->workers = started, st->k = vw.k, st->producer = producer, st->wide = vw.wide;
    if (failed) {
        c5_fail(err, started < nw ? "cast: could not start worker thread %d" : "cast: out of memory in the producer",
                started);
        if (allocated)
            c5_image_free(out);
        goto done;
    }
    rc = 0;
    goto done;
oom:
    c5_fail(err, "cast: out of memory for a %dx%d frame", w, h);
done:
    for (int i = 0; slots && i < nw * depth; i++) {
        free(slots[i].seg);
        free(slots[i].hash);
    }
    for (int i = 0; wk && i < nw; i++) {
        c5_cast_scratch_free(wk[i].rs);
        free(wk[i].own.seg);
        free(wk[i].own.hash);
    }
    c5_cast_scratch_free(rs);
    free(slots);
    free(th);
    free(wk);
    free(rings);
    free(tiles);
    c5_cast_view_release(&vw);
    st->frame_s = c5_now_s() - t_start;
    return rc;
}
