/* cref's frame loop: eye rays through pixel centres (spec sec. 2), 16x16 tiles handed to
 * threads. Each pixel is traced whole by one thread in a fixed order, so the image bits
 * and the statistics do not depend on the thread count. */
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "camera.h"
#include "trace.h"
#include "clock.h"

#define TILE 16

double c5_render_step(const c5_scene *s, const c5_supervol *sv)
{
    return s->render.step > 0 ? s->render.step : c5_supervol_min_spacing(sv);
}

double c5_render_unit(const c5_scene *s, const c5_supervol *sv)
{
    return s->tf.unit_distance > 0 ? s->tf.unit_distance : c5_supervol_min_spacing(sv);
}

typedef struct {
    const c5_trace_ctx *ctx;
    const c5_camera_basis *cam;
    c5_image *img;
    int tiles_x, n_tiles;
    int next_tile; /* shared, taken under `lock` */
    pthread_mutex_t lock;
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
        pthread_mutex_unlock(&j->lock);
        if (t >= j->n_tiles)
            break;
        int x0 = (t % j->tiles_x) * TILE, y0 = (t / j->tiles_x) * TILE;
        for (int py = y0; py < y0 + TILE && py < j->cam->h; py++)
            for (int px = x0; px < x0 + TILE && px < j->cam->w; px++) {
                c5_ray eye = {j->cam->eye, c5_camera_pixel_dir(j->cam, px, py), v3(1, 1, 1), INFINITY, C5_RAY_EYE, 0};
                double rgb[3] = {0, 0, 0};
                c5_trace_pixel(j->ctx, &eye, rgb, &wk->st, &stk);
                float *o = j->img->rgb + 3 * ((size_t)py * j->cam->w + px);
                o[0] = (float)rgb[0];
                o[1] = (float)rgb[1];
                o[2] = (float)rgb[2];
            }
    }
    free(stk.rays);
    return NULL;
}

int c5_cref_thread_count(int requested)
{
    long n = requested > 0 ? requested : sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : n > 256 ? 256 : (int)n;
}

int c5_cref_render(const c5_scene *s, const c5_supervol *sv, int frame, const c5_cref_opts *opts, c5_image *out,
                   c5_cref_stats *stats, c5_err *err)
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
    double diag = 1;
    if (ctx->has_volume) {
        ctx->step = c5_render_step(s, sv);
        c5_tf_build(&s->tf, ctx->step, c5_render_unit(s, sv), &ctx->tf);
        ctx->box_lo = sv->origin;
        ctx->box_hi = v3_add(sv->origin, v3(sv->dims[0] * sv->spacing.x, sv->dims[1] * sv->spacing.y,
                                            sv->dims[2] * sv->spacing.z));
        diag = fmax(1, v3_len(v3_sub(ctx->box_hi, ctx->box_lo)));
        ctx->grad_eps = 1.0 / 16 / c5_supervol_min_spacing(sv);
    }
    ctx->eps = 1e-6 * diag;

    c5_camera cam = c5_scene_camera_at(s, frame);
    c5_camera_basis basis;
    if (c5_camera_basis_make(&cam, s->render.width, s->render.height, frame, &basis, err) != 0) {
        free(ctx);
        c5_image_free(out);
        return -1;
    }
    job j = {.ctx = ctx, .cam = &basis, .img = out};
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
