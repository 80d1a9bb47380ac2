/* cref's frame loop: eye rays through pixel centres (spec sec. 2), 16x16 tiles handed to
 * threads. Each pixel is traced whole by one thread in a fixed order, so the image bits
 * and the statistics do not depend on the thread count. Compiled twice (cref/real.h): in
 * double, c5_cref_render, and in long double, c5_cref_render_long. */
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "camera.h"
#include "trace.h"
#include "clock.h"
#include "worker_pool.h"

#include <tgmath.h>

#define TILE 16

#ifdef C5_CREF_LONG
/* The long double build computes again, in long double, what cref takes from common/ in
 * double: the eye rays (camera.c's formulas; keep them in step) and the table's step
 * correction (tf.c's c5_tf_build; the piecewise-linear control points stay c5_tf_eval's,
 * the definition of each entry to one rounding). */
typedef struct {
    c5_rvec3 eye, f, right, up;
    c5_real tan_half, aspect;
    int w, h;
} eye_basis;

static void eye_basis_make(const c5_camera *cam, const c5_camera_basis *b, eye_basis *e)
{
    c5_rvec3 up = rv3_of(cam->up);
    e->eye = rv3_of(cam->eye);
    e->f = rv3_norm(rv3_sub(rv3_of(cam->target), e->eye));
    e->right = rv3_norm(rv3_cross(e->f, up));
    e->up = rv3_cross(e->right, e->f);
    e->tan_half = tan((c5_real)cam->fov_deg * C5_REAL_PI / 360);
    e->aspect = (c5_real)b->w / b->h;
    e->w = b->w;
    e->h = b->h;
}

static c5_rvec3 eye_dir(const eye_basis *b, int px, int py)
{
    c5_real sx = (2 * (px + (c5_real)0.5) / b->w - 1) * b->tan_half * b->aspect;
    c5_real sy = (1 - 2 * (py + (c5_real)0.5) / b->h) * b->tan_half;
    return rv3_norm(rv3_add(b->f, rv3_add(rv3_scale(b->right, sx), rv3_scale(b->up, sy))));
}

static void tf_build(const c5_tf_desc *tf, c5_real step, c5_real unit, c5_rtf_table *out)
{
    c5_real ratio = step / unit;
    for (int s = 0; s < 256; s++) {
        for (int c = 0; c < 3; c++)
            out->rgba[s][c] = c5_tf_eval(&tf->color[0][0], tf->n_color, 4, c + 1, s);
        c5_real a = c5_tf_eval(&tf->opacity[0][0], tf->n_opacity, 2, 1, s);
        out->rgba[s][3] = a >= 1 ? 1 : a <= 0 ? 0 : 1 - pow(1 - a, ratio);
    }
}
#else
typedef c5_camera_basis eye_basis;

static void eye_basis_make(const c5_camera *cam, const c5_camera_basis *b, eye_basis *e)
{
    (void)cam;
    *e = *b;
}

static c5_rvec3 eye_dir(const eye_basis *b, int px, int py) { return c5_camera_pixel_dir(b, px, py); }

static void tf_build(const c5_tf_desc *tf, c5_real step, c5_real unit, c5_rtf_table *out)
{
    c5_tf_build(tf, step, unit, out);
}
#endif

typedef struct {
    const c5_trace_ctx *ctx;
    const eye_basis *cam;
    c5_image *img;
    double *raw; /* NULL, or w*h*3: each pixel's sum before the float rounding */
    int tiles_x, n_tiles;
    int next_tile; /* shared, taken under `lock` */
    pthread_mutex_t lock;
    void (*progress)(void *ctx, int tiles_done, int tiles);
    void *progress_ctx;
} job;

typedef struct {
    job *j;
    c5_cref_stats st;
} worker;

static void *work(void *arg)
{
    worker *wk = arg;
    job *j = wk->j;
    c5_ray_stack stk = {0};
    for (;;) {
        pthread_mutex_lock(&j->lock);
        int t = j->next_tile++;
        if (j->progress && t < j->n_tiles)
            j->progress(j->progress_ctx, t, j->n_tiles);
        pthread_mutex_unlock(&j->lock);
        if (t >= j->n_tiles)
            break;
        int x0 = (t % j->tiles_x) * TILE, y0 = (t / j->tiles_x) * TILE;
        for (int py = y0; py < y0 + TILE && py < j->cam->h; py++)
            for (int px = x0; px < x0 + TILE && px < j->cam->w; px++) {
                c5_ray eye = {j->cam->eye, eye_dir(j->cam, px, py), rv3(1, 1, 1), INFINITY, C5_RAY_EYE, 0};
                c5_real rgb[3] = {0, 0, 0};
                C5R(trace_pixel)(j->ctx, &eye, rgb, &wk->st, &stk);
                size_t at = 3 * ((size_t)py * j->cam->w + px);
                float *o = j->img->rgb + at;
                o[0] = (float)rgb[0];
                o[1] = (float)rgb[1];
                o[2] = (float)rgb[2];
                if (j->raw)
                    for (int c = 0; c < 3; c++)
                        j->raw[at + c] = (double)rgb[c];
            }
    }
    free(stk.rays);
    return NULL;
}

int C5R(cref_render_into)(const c5_scene *s, const c5_supervol *sv, int frame, const c5_cref_opts *opts,
                          c5_image *out, double *raw, c5_cref_stats *stats, c5_err *err)
{
    double start = c5_now_s();
    memset(stats, 0, sizeof *stats);
    if (c5_image_alloc(out, s->render.width, s->render.height, err) != 0)
        return -1;

    c5_trace_ctx *ctx = calloc(1, sizeof *ctx);
    if (!ctx) {
        c5_image_free(out);
        return c5_fail(err, "out of memory");
    }
    ctx->s = s;
    ctx->sv = sv;
    ctx->field = opts ? opts->field : NULL;
    ctx->has_volume = !c5_supervol_empty(sv);
    ctx->shade = ctx->has_volume && s->render.shading && s->n_lights > 0;
    c5_real diag = 1;
    if (ctx->has_volume) {
        c5_rvec3 h = rv3_of(sv->spacing);
        ctx->step = c5_render_step(s, sv);
        tf_build(&s->tf, ctx->step, c5_render_unit(s, sv), &ctx->tf);
        ctx->box_lo = rv3_of(sv->origin);
        ctx->box_hi = rv3_add(ctx->box_lo, rv3(sv->dims[0] * h.x, sv->dims[1] * h.y, sv->dims[2] * h.z));
        diag = fmax(1, rv3_len(rv3_sub(ctx->box_hi, ctx->box_lo)));
        ctx->fade_g2 = (c5_real)1 / 16 / ((c5_real)c5_supervol_min_spacing(sv) * (c5_real)c5_supervol_min_spacing(sv));
    }
    ctx->eps = 1e-6 * diag;

    c5_camera cam = c5_scene_camera_at(s, frame);
    c5_camera_basis basis;
    if (c5_camera_basis_make(&cam, s->render.width, s->render.height, frame, &basis, err) != 0) {
        free(ctx);
        c5_image_free(out);
        return -1;
    }
    eye_basis eb;
    eye_basis_make(&cam, &basis, &eb);
    job j = {.ctx = ctx, .cam = &eb, .img = out, .raw = raw, .progress = opts ? opts->progress : NULL,
             .progress_ctx = opts ? opts->progress_ctx : NULL};
    j.tiles_x = (basis.w + TILE - 1) / TILE;
    j.n_tiles = j.tiles_x * ((basis.h + TILE - 1) / TILE);
    pthread_mutex_init(&j.lock, NULL);

    int n = c5_cref_thread_count(opts ? opts->threads : 0);
    worker *wk = calloc((size_t)n, sizeof *wk);
    pthread_t *th = calloc((size_t)n, sizeof *th);
    int started = 0, rc = 0;
    if (!wk || !th) {
        rc = c5_fail(err, "out of memory");
    } else {
        for (int i = 0; i < n; i++) {
            wk[i].j = &j;
            if (i > 0 && pthread_create(&th[i], NULL, work, &wk[i]) != 0)
                break; /* fewer threads: same bits, only slower */
            started = i + 1;
        }
        work(&wk[0]);
        for (int i = 1; i < started; i++)
            pthread_join(th[i], NULL);
        for (int i = 0; i < started; i++) {
            for (int t = 0; t < C5_RAY_TYPES; t++)
                stats->rays[t] += wk[i].st.rays[t];
            for (int e = 0; e < C5_END_KINDS; e++)
                stats->ends[e] += wk[i].st.ends[e];
            stats->samples += wk[i].st.samples;
        }
    }
    pthread_mutex_destroy(&j.lock);
    free(wk);
    free(th);
    free(ctx);
    if (rc != 0)
        c5_image_free(out);
    stats->wall_s = c5_now_s() - start;
    return rc;
}

int C5_CREF_RENDER(const c5_scene *s, const c5_supervol *sv, int frame, const c5_cref_opts *opts, c5_image *out,
                   c5_cref_stats *stats, c5_err *err)
{
    return C5R(cref_render_into)(s, sv, frame, opts, out, NULL, stats, err);
}

#ifndef C5_CREF_LONG /* what does not depend on the precision: once, in the double build */
int c5_cref_render_raw(const c5_scene *s, const c5_supervol *sv, int frame, const c5_cref_opts *opts,
                       int long_double, c5_image *out, double *raw, c5_cref_stats *stats, c5_err *err)
{
    return (long_double ? c5l_cref_render_into : c5_cref_render_into)(s, sv, frame, opts, out, raw, stats, err);
}

int c5_cref_thread_count(int requested)
{
    return requested > 256 ? 256 : requested > 0 ? requested : c5_cpus_usable();
}

double c5_render_step(const c5_scene *s, const c5_supervol *sv)
{
    return s->render.step > 0 ? s->render.step : c5_supervol_min_spacing(sv);
}

double c5_render_unit(const c5_scene *s, const c5_supervol *sv)
{
    return s->tf.unit_distance > 0 ? s->tf.unit_distance : c5_supervol_min_spacing(sv);
}

const char *c5_ray_type_name(c5_ray_type t)
{
    static const char *n[] = {"eye", "shadow", "reflect", "refract"};
    return (unsigned)t < C5_RAY_TYPES ? n[t] : "?";
}

const char *c5_end_kind_name(c5_end_kind k)
{
    static const char *n[] = {"opacity", "left_scene", "surface", "light_reached", "shadow_blocked",
                              "bounce_limit", "weight_cutoff"};
    return (unsigned)k < C5_END_KINDS ? n[k] : "?";
}
#endif
