/* The error/time sweep (sweep.h, docs/sweep.md). */
#include "sweep.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "board.h"
#include "camera.h"
#include "clock.h"
#include "generators.h"

/* ---- knobs ---------------------------------------------------------------------------- */

static int parse_value(const c5_sweep_knob *k, const char *tok, double *out, c5_err *err)
{
    char *end;
    errno = 0;
    double v = strtod(tok, &end);
    int num = *tok && !*end && !errno && isfinite(v);
    switch (k->kind) {
    case C5_KNOB_STEP:
        if (!num || !(v > 0) || !(v < C5_SWEEP_MAX_STEP))
            return c5_fail(err, "--knob %s: expected a step in voxels in (0, %g) (the model's step_vec), got '%s'",
                           k->name, C5_SWEEP_MAX_STEP, tok);
        break;
    case C5_KNOB_ET:
        if (!num || !(v > 0) || v > 1)
            return c5_fail(err, "--knob %s: expected an opacity in (0, 1], got '%s'", k->name, tok);
        break;
    case C5_KNOB_BOUNCES:
        if (!num || v != floor(v) || v < 0 || v > C5_SWEEP_MAX_BOUNCES)
            return c5_fail(err,
                           "--knob %s: expected a whole number 0..%d (the model's 4-bit generation), got '%s'",
                           k->name, C5_SWEEP_MAX_BOUNCES, tok);
        break;
    case C5_KNOB_WIDTH: {
        if (!num || v != floor(v) || fabs(v) > 1e6)
            return c5_fail(err, "--knob %s: expected a whole number of fraction bits, got '%s'", k->name, tok);
        c5_widths w = c5_widths_shipped();
        c5_err e;
        if (c5_widths_set(&w, c5_width_name(k->width), (int)v, &e) != 0)
            return c5_fail(err, "--knob %s: %s", k->name, e.msg);
        break;
    }
    case C5_KNOB_K:
        if (!num || !(v == 1 || v == 2 || v == 4 || v == 8 || v == 16))
            return c5_fail(err, "--knob %s: expected 1, 2, 4, 8 or 16, got '%s'", k->name, tok);
        break;
    }
    *out = v;
    return 0;
}

int c5_sweep_knob_parse(const char *spec, c5_sweep_knob *out, c5_err *err)
{
    memset(out, 0, sizeof *out);
    const char *eq = strchr(spec, '=');
    if (!eq || eq == spec)
        return c5_fail(err, "--knob: expected NAME=V1,V2,... (step, et, bounces, width.NAME, k), got '%s'", spec);
    size_t len = (size_t)(eq - spec);
    if (len >= sizeof out->name)
        return c5_fail(err, "--knob: unknown knob '%.*s' (step, et, bounces, width.NAME, k)", (int)len, spec);
    memcpy(out->name, spec, len);
    out->name[len] = 0;
    if (!strcmp(out->name, "step"))
        out->kind = C5_KNOB_STEP;
    else if (!strcmp(out->name, "et"))
        out->kind = C5_KNOB_ET;
    else if (!strcmp(out->name, "bounces"))
        out->kind = C5_KNOB_BOUNCES;
    else if (!strcmp(out->name, "k"))
        out->kind = C5_KNOB_K;
    else if (!strncmp(out->name, "width.", 6)) {
        out->kind = C5_KNOB_WIDTH;
        int id = -1;
        for (int i = 0; i < C5_W_COUNT; i++)
            if (!strcmp(out->name + 6, c5_width_name((c5_width_id)i)))
                id = i;
        if (id < 0) {
            c5_widths w = c5_widths_shipped();
            c5_err e;
            c5_widths_set(&w, out->name + 6, 1, &e); /* fails: its message lists the known names */
            return c5_fail(err, "--knob %s: %s", out->name, e.msg);
        }
        out->width = (c5_width_id)id;
    } else
        return c5_fail(err, "--knob: unknown knob '%s' (step, et, bounces, width.NAME, k)", out->name);
    const char *p = eq + 1;
    if (!*p)
        return c5_fail(err, "--knob %s: no values (expected %s=V1,V2,...)", out->name, out->name);
    for (;;) {
        const char *comma = strchr(p, ',');
        size_t n = comma ? (size_t)(comma - p) : strlen(p);
        char tok[64];
        if (n == 0)
            return c5_fail(err, "--knob %s: empty value in '%s'", out->name, spec);
        if (n >= sizeof tok)
            return c5_fail(err, "--knob %s: value too long in '%s'", out->name, spec);
        memcpy(tok, p, n);
        tok[n] = 0;
        if (out->n == C5_SWEEP_MAX_VALUES)
            return c5_fail(err, "--knob %s: at most %d values", out->name, C5_SWEEP_MAX_VALUES);
        double v = 0;
        if (parse_value(out, tok, &v, err) != 0)
            return -1;
        for (int i = 0; i < out->n; i++)
            if (out->v[i] == v)
                return c5_fail(err, "--knob %s: value '%s' given twice", out->name, tok);
        out->v[out->n++] = v;
        if (!comma)
            break;
        p = comma + 1;
    }
    return 0;
}

c5_sweep_point c5_sweep_point_with(const c5_sweep_point *base, const c5_sweep_knob *kn, double v)
{
    c5_sweep_point p = *base;
    switch (kn->kind) {
    case C5_KNOB_STEP: p.step = v; break;
    case C5_KNOB_ET: p.et = v; break;
    case C5_KNOB_BOUNCES: p.bounces = (int)v; break;
    case C5_KNOB_WIDTH: p.widths.frac[kn->width] = (int)v; break;
    case C5_KNOB_K: p.k = (int)v; break;
    }
    return p;
}

int c5_sweep_is_default(const c5_sweep_point *base, const c5_sweep_knob *kn, double v)
{
    switch (kn->kind) {
    case C5_KNOB_STEP: return fabs(v - base->step) <= 1e-9 * base->step;
    case C5_KNOB_ET: return v == base->et;
    case C5_KNOB_BOUNCES: return (int)v == base->bounces;
    case C5_KNOB_WIDTH: return (int)v == c5_width_shipped(kn->width);
    case C5_KNOB_K: return (int)v == base->k;
    }
    return 0;
}

int c5_sweep_knob_renderers(const c5_sweep_knob *kn, c5_sweep_renderer r[2])
{
    switch (kn->kind) {
    case C5_KNOB_WIDTH: r[0] = C5_SW_MODEL; return 1;
    case C5_KNOB_K: r[0] = C5_SW_CAST; return 1;
    default: r[0] = C5_SW_CREF, r[1] = C5_SW_MODEL; return 2;
    }
}

const char *c5_sweep_renderer_name(c5_sweep_renderer r)
{
    return r == C5_SW_CREF ? "cref" : r == C5_SW_MODEL ? "model" : "cast";
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* Sorted, without repeats. */
static void knob_values(c5_sweep_knob *k, const double *v, int n)
{
    k->n = 0;
    for (int i = 0; i < n; i++) {
        int seen = 0;
        for (int j = 0; j < k->n; j++)
            seen |= k->v[j] == v[i];
        if (!seen && k->n < C5_SWEEP_MAX_VALUES)
            k->v[k->n++] = v[i];
    }
    qsort(k->v, (size_t)k->n, sizeof k->v[0], cmp_double);
}

int c5_sweep_default_knobs(const c5_sweep_point *base, int has_volume, c5_sweep_knob *out)
{
    int n = 0;
    double v[8];
    int m;
    if (has_volume) {
        c5_sweep_knob *k = &out[n++];
        *k = (c5_sweep_knob){.name = "step", .kind = C5_KNOB_STEP};
        m = 0;
        const double f[] = {0.5, 1, 2, 4};
        for (int i = 0; i < 4; i++)
            if (base->step * f[i] < C5_SWEEP_MAX_STEP)
                v[m++] = base->step * f[i];
        knob_values(k, v, m);
    }
    c5_sweep_knob *k = &out[n++];
    *k = (c5_sweep_knob){.name = "et", .kind = C5_KNOB_ET};
    double et[] = {0.8, 0.9, 0.99, 1, base->et};
    knob_values(k, et, 5);
    k = &out[n++];
    *k = (c5_sweep_knob){.name = "bounces", .kind = C5_KNOB_BOUNCES};
    const int b[] = {0, 1, base->bounces, base->bounces + 2};
    m = 0;
    for (int i = 0; i < 4; i++)
        if (b[i] <= C5_SWEEP_MAX_BOUNCES)
            v[m++] = b[i];
    knob_values(k, v, m);
    for (int w = 0; w < C5_W_COUNT; w++) {
        k = &out[n++];
        *k = (c5_sweep_knob){.kind = C5_KNOB_WIDTH, .width = (c5_width_id)w};
        snprintf(k->name, sizeof k->name, "width.%s", c5_width_name((c5_width_id)w));
        int s = c5_width_shipped((c5_width_id)w);
        m = 0;
        const int d[] = {6, 3, 0};
        for (int i = 0; i < 3; i++)
            if (s - d[i] >= 1)
                v[m++] = s - d[i];
        knob_values(k, v, m);
    }
    if (has_volume) {
        k = &out[n++];
        *k = (c5_sweep_knob){.name = "k", .kind = C5_KNOB_K};
        const double kv[] = {1, 2, 4, 8, 16};
        knob_values(k, kv, 5);
    }
    return n;
}

void c5_sweep_pareto(const double *t, const double *e, int n, int *on)
{
    for (int i = 0; i < n; i++) {
        on[i] = !isnan(t[i]) && !isnan(e[i]);
        for (int j = 0; j < n && on[i]; j++) {
            if (j == i || isnan(t[j]) || isnan(e[j]))
                continue;
            if (t[j] <= t[i] && e[j] <= e[i] && (t[j] < t[i] || e[j] < e[i]))
                on[i] = 0;
        }
    }
}

/* ---- the Marschner-Lobb truth ------------------------------------------------------------ */

int c5_sweep_is_marschner_lobb(const c5_scene *s, const c5_supervol *sv)
{
    if (s->n_volumes != 1 || c5_supervol_empty(sv))
        return 0;
    const c5_volume_desc *d = &s->volumes[0];
    if (d->kind != C5_SRC_GENERATOR || d->generator != C5_GEN_MARSCHNER_LOBB)
        return 0;
    for (int a = 0; a < 3; a++)
        if (d->offset[a] != 0 || d->gen_dims[a] != sv->dims[a])
            return 0;
    return 1;
}

static void ml_sample(const c5_field *f, c5_vec3 p, double *value, c5_vec3 *grad)
{
    const c5_sweep_ctx *c = f->ctx;
    c5_supervol_marschner_lobb(c->sv, c->ml_f_m, c->ml_alpha, p, value, grad);
}

/* ---- context -------------------------------------------------------------------------- */

static int cast_setup(c5_sweep_ctx *c, c5_err *err)
{
    const c5_scene *s = c->scene;
    const c5_supervol *sv = c->sv;
    if (!c->has_volume)
        return c5_fail(err, "--knob k: the scene has no volume to cast");
    double sp[3] = {sv->spacing.x, sv->spacing.y, sv->spacing.z};
    if (!sv->v)
        return c5_supervol_cast_refusal(sv, "--knob k", err);
    if (c5_cast_volume_make(sv->v, sv->dims, sp, &c->cv, err) != 0)
        return -1;
    /* The caster puts voxel (i,j,k) at (i sx, j sy, k sz) (VTK's point positions), cref at the
     * voxel's centre origin + (i + 1/2) s: the scene's camera moved by that offset sees the
     * same voxels in the same pixels. */
    c5_camera cam = c5_scene_camera_at(s, 0);
    c5_camera_basis b;
    if (c5_camera_basis_make(&cam, s->render.width, s->render.height, 0, &b, err) != 0)
        return -1;
    double shift[3] = {sv->origin.x + 0.5 * sp[0], sv->origin.y + 0.5 * sp[1], sv->origin.z + 0.5 * sp[2]};
    double eye[3] = {b.eye.x, b.eye.y, b.eye.z}, tgt[3] = {cam.target.x, cam.target.y, cam.target.z};
    double f[3] = {b.f.x, b.f.y, b.f.z}, r[3] = {b.right.x, b.right.y, b.right.z}, u[3] = {b.up.x, b.up.y, b.up.z};
    for (int a = 0; a < 3; a++) {
        c->cam.eye[a] = eye[a] - shift[a];
        c->cam.focal[a] = tgt[a] - shift[a];
        c->cam.f[a] = f[a];
        c->cam.right[a] = r[a];
        c->cam.up[a] = u[a];
    }
    c->cam.tan_half = b.tan_half;
    c->cast_shading = s->n_lights > 0 && s->render.shading;
    if (c->cast_shading && c5_cast_volume_normals(c->cv, err) != 0)
        return -1;
    c->cast_tf = s->tf;
    if (!(c->cast_tf.unit_distance > 0))
        c->cast_tf.unit_distance = c->voxel;
    c->base.k = c5_cast_default_k(c->cv, &c->cam, s->render.width, s->render.height);
    c->cast_ready = 1;
    return 0;
}

int c5_sweep_init(c5_sweep_ctx *c, const c5_scene *s, const c5_supervol *sv, int threads, int need_cast,
                  c5_err *err)
{
    memset(c, 0, sizeof *c);
    c->scene = s;
    c->sv = sv;
    c->threads = threads;
    c->has_volume = !c5_supervol_empty(sv);
    c->voxel = c->has_volume ? c5_supervol_min_spacing(sv) : 1;
    c->base.step = c->has_volume ? c5_render_step(s, sv) / c->voxel : (s->render.step > 0 ? s->render.step : 1);
    c->base.et = s->render.max_opacity;
    c->base.bounces = s->render.max_bounces;
    c->base.widths = c5_widths_shipped();
    c->analytic = c5_sweep_is_marschner_lobb(s, sv);
    if (c->analytic) {
        c->ml_f_m = s->volumes[0].f_m;
        c->ml_alpha = s->volumes[0].alpha;
    }
    if (need_cast && cast_setup(c, err) != 0) {
        c5_sweep_free(c);
        return -1;
    }
    return 0;
}

void c5_sweep_free(c5_sweep_ctx *c)
{
    c5_image_free(&c->ref);
    c5_image_free(&c->cast_ref);
    c5_image_free(&c->cast_plain);
    c5_cast_volume_free(c->cv);
    c->cv = NULL;
    c->cast_ready = 0;
}

/* ---- rendering ------------------------------------------------------------------------- */

static c5_scene *scene_at(const c5_sweep_ctx *c, double step, double et, int bounces, c5_err *err)
{
    c5_scene *s = malloc(sizeof *s);
    if (!s) {
        c5_fail(err, "out of memory");
        return NULL;
    }
    *s = *c->scene;
    s->render.step = step * c->voxel;
    s->render.max_opacity = et;
    s->render.max_bounces = bounces;
    return s;
}

static int cref_at(const c5_sweep_ctx *c, double step, double et, int bounces, int analytic, c5_image *out,
                   c5_cref_stats *st, double *host_s, c5_err *err)
{
    c5_scene *s = scene_at(c, step, et, bounces, err);
    if (!s)
        return -1;
    c5_field field = {ml_sample, c};
    c5_cref_opts o = {.threads = c->threads, .field = analytic ? &field : NULL};
    double t0 = c5_now_s();
    int rc = c5_cref_render(s, c->sv, 0, &o, out, st, err);
    *host_s = c5_now_s() - t0;
    free(s);
    return rc;
}

static int cast_at(const c5_sweep_ctx *c, c5_cast_mode mode, int k, double step, int early, c5_image *out,
                   c5_cast_stats *st, double *host_s, c5_err *err)
{
    c5_cast_tf *tf = malloc(sizeof *tf);
    if (!tf)
        return c5_fail(err, "out of memory");
    int rc = -1;
    if (c5_cast_tf_build(&c->cast_tf, step * c->voxel, c->cast_tf.unit_distance, tf, err) != 0)
        goto done;
    c5_cast_opts o;
    c5_cast_opts_default(&o);
    int workers = c5_cref_thread_count(c->threads);
    o.mode = mode;
    o.k = mode == C5_CAST_PLAIN ? 1 : k;
    o.workers = workers > C5_CAST_MAX_WORKERS ? C5_CAST_MAX_WORKERS : workers;
    o.shading = c->cast_shading;
    o.early_termination = early;
    o.step = step * c->voxel;
    out->rgb = NULL;
    double t0 = c5_now_s();
    rc = c5_cast_render(c->cv, tf, &c->cam, c->scene->render.width, c->scene->render.height, &o, out, st, err);
    *host_s = c5_now_s() - t0;
done:
    free(tf);
    return rc;
}

int c5_sweep_reference_steps(const c5_sweep_ctx *c)
{
    return c->cast_ready ? 5 : 2;
}

int c5_sweep_reference(c5_sweep_ctx *c, double finest, c5_sweep_progress_fn progress, void *arg, c5_err *err)
{
    if (!(finest > 0) || finest > c->base.step)
        finest = c->base.step;
    c->ref_step = finest / C5_SWEEP_REF_DIV;
    c->ref_coarse_step = 2 * c->ref_step;
    c->ref_et = 1;
    c->ref_bounces = c->base.bounces > C5_SWEEP_MAX_BOUNCES ? c->base.bounces : C5_SWEEP_MAX_BOUNCES;
    c5_cref_stats st;
    c5_image coarse = {0};
    double t;
    char what[256];
    const char *src = c->analytic ? "cref, analytic Marschner-Lobb" : "cref";
    if (cref_at(c, c->ref_step, c->ref_et, c->ref_bounces, c->analytic, &c->ref, &st, &t, err) != 0)
        return -1;
    c->ref_wall_s = t;
    snprintf(what, sizeof what, "reference: %s step=%g et=1 bounces=%d", src, c->ref_step, c->ref_bounces);
    if (progress)
        progress(arg, what, t);
    if (cref_at(c, c->ref_coarse_step, c->ref_et, c->ref_bounces, c->analytic, &coarse, &st, &t, err) != 0)
        return -1;
    int rc = c5_image_compare(&c->ref, &coarse, &c->ref_conv, err);
    c5_image_free(&coarse);
    if (rc != 0)
        return -1;
    snprintf(what, sizeof what, "convergence: %s step=%g against step=%g: RMSE %.3g", src, c->ref_coarse_step,
             c->ref_step, c->ref_conv.rmse);
    if (progress)
        progress(arg, what, t);
    if (!c->cast_ready)
        return 0;
    c5_cast_stats cs;
    c->cast_ref_step = c->base.step / C5_SWEEP_REF_DIV;
    if (cast_at(c, C5_CAST_PLAIN, 1, c->cast_ref_step, 0, &c->cast_ref, &cs, &t, err) != 0)
        return -1;
    snprintf(what, sizeof what, "reference: cast plain step=%g, no early termination", c->cast_ref_step);
    if (progress)
        progress(arg, what, t);
    if (cast_at(c, C5_CAST_PLAIN, 1, 2 * c->cast_ref_step, 0, &coarse, &cs, &t, err) != 0)
        return -1;
    rc = c5_image_compare(&c->cast_ref, &coarse, &c->cast_conv, err);
    c5_image_free(&coarse);
    if (rc != 0)
        return -1;
    snprintf(what, sizeof what, "convergence: cast plain step=%g against step=%g: RMSE %.3g", 2 * c->cast_ref_step,
             c->cast_ref_step, c->cast_conv.rmse);
    if (progress)
        progress(arg, what, t);
    if (cast_at(c, C5_CAST_PLAIN, 1, c->base.step, 1, &c->cast_plain, &cs, &t, err) != 0)
        return -1;
    snprintf(what, sizeof what, "cast plain step=%g (the image every k must give)", c->base.step);
    if (progress)
        progress(arg, what, t);
    return 0;
}

int c5_sweep_run(c5_sweep_ctx *c, c5_sweep_renderer r, const c5_sweep_point *p, c5_sweep_result *out, c5_err *err)
{
    memset(out, 0, sizeof *out);
    out->board_s = NAN;
    out->psnr_db = out->rmse = out->max_abs_err = NAN;
    out->identical_to_plain = -1;
    c5_image img = {0};
    const c5_image *ref = &c->ref;
    c5_err e;
    int rendered = -1;
    if (r == C5_SW_CREF) {
        c5_cref_stats st;
        memset(&st, 0, sizeof st);
        rendered = cref_at(c, p->step, p->et, p->bounces, 0, &img, &st, &out->host_s, &e);
        out->samples = st.samples;
    } else if (r == C5_SW_MODEL) {
        c5_scene *s = scene_at(c, p->step, p->et, p->bounces, err);
        if (!s)
            return -1;
        c5_board_opts o = {.widths = &p->widths};
        c5_board_stats st;
        memset(&st, 0, sizeof st);
        double t0 = c5_now_s();
        rendered = c5_board_render(s, c->sv, 0, &o, &img, &st, &e);
        out->host_s = c5_now_s() - t0;
        free(s);
        out->board_s = st.board_s;
        out->samples = st.samples;
    } else {
        if (!c->cast_ready)
            return c5_fail(err, "sweep: the caster was not set up");
        c5_cast_stats st;
        memset(&st, 0, sizeof st);
        ref = &c->cast_ref;
        rendered = cast_at(c, C5_CAST_APPROX_REFINE, p->k, p->step, 1, &img, &st, &out->host_s, &e);
        out->samples = st.samples;
    }
    if (rendered != 0) {
        memcpy(out->msg, e.msg, sizeof out->msg);
        c5_image_free(&img);
        return 0;
    }
    c5_image_diff d;
    if (c5_image_compare(ref, &img, &d, &e) != 0) {
        memcpy(out->msg, e.msg, sizeof out->msg);
        c5_image_free(&img);
        return 0;
    }
    if (r == C5_SW_CAST && c->cast_plain.rgb && p->step == c->base.step)
        out->identical_to_plain =
            !memcmp(img.rgb, c->cast_plain.rgb, sizeof(float) * 3 * (size_t)img.w * (size_t)img.h);
    c5_image_free(&img);
    out->ok = 1;
    out->psnr_db = d.psnr_db;
    out->rmse = d.rmse;
    out->max_abs_err = d.max_abs_err;
    return 0;
}
