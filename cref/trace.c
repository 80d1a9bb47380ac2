/* Tracing rays per docs/rendering-spec.md: volume sampling and compositing (sec. 4-5),
 * surfaces, spawned rays and their weights (sec. 6-7). */
#include <stdlib.h>

#include "geometry.h"
#include "trace.h"

#include <tgmath.h>

static void add_rgb(c5_real rgb[3], c5_rvec3 c)
{
    rgb[0] += c.x;
    rgb[1] += c.y;
    rgb[2] += c.z;
}

static void push(c5_ray_stack *stk, const c5_ray *r, c5_cref_stats *st)
{
    if (stk->n == stk->cap) {
        int cap = stk->cap ? 2 * stk->cap : 64;
        c5_ray *p = realloc(stk->rays, (size_t)cap * sizeof *p);
        if (!p)
            abort(); /* a few KB per thread; nothing sensible to do without them */
        stk->rays = p;
        stk->cap = cap;
    }
    stk->rays[stk->n++] = *r;
    st->rays[r->type]++;
}

static void field_sample(const c5_trace_ctx *c, c5_rvec3 p, c5_real *value, c5_rvec3 *grad)
{
#ifdef C5_CREF_LONG
    if (c->field) { /* an analytic field is evaluated in double (cref.h), at p rounded to double */
        double v;
        c5_vec3 g;
        c->field->sample(c->field, rv3_to_double(p), &v, grad ? &g : NULL);
        *value = v;
        if (grad)
            *grad = rv3_of(g);
        return;
    }
#else
    if (c->field) {
        c->field->sample(c->field, p, value, grad);
        return;
    }
#endif
    C5R(supervol_sample)(c->sv, p, value, grad);
}

#ifdef C5_CREF_LONG
/* tf.h's c5_tf_lookup in long double (keep them in step). */
static void tf_lookup(const c5_rtf_table *t, c5_real s, c5_real rgba[4])
{
    s = s < 0 ? 0 : s > 255 ? 255 : s;
    int i = (int)s;
    if (i > 254)
        i = 254;
    c5_real f = s - i;
    for (int c = 0; c < 4; c++)
        rgba[c] = t->rgba[i][c] + f * (t->rgba[i + 1][c] - t->rgba[i][c]);
}
#else
#define tf_lookup c5_tf_lookup
#endif

/* A sample belongs to the volume when its position lies in the half-open grid box. */
static int inside_grid(const c5_trace_ctx *c, c5_rvec3 p)
{
    const c5_supervol *sv = c->sv;
    c5_real u[3] = {(p.x - sv->origin.x) / sv->spacing.x, (p.y - sv->origin.y) / sv->spacing.y,
                    (p.z - sv->origin.z) / sv->spacing.z};
    for (int a = 0; a < 3; a++)
        if (!(u[a] >= 0 && u[a] < (c5_real)sv->dims[a]))
            return 0;
    return 1;
}

static c5_rvec3 light_dir(const c5_light *l, c5_rvec3 p, c5_real *dist)
{
    if (l->kind == C5_LIGHT_DIRECTIONAL) {
        *dist = INFINITY;
        return rv3_scale(rv3_of(l->direction), -1);
    }
    c5_rvec3 to = rv3_sub(rv3_of(l->position), p);
    *dist = rv3_len(to);
    return rv3_norm(to);
}

/* Phong shading of a volume sample's colour (spec sec. 4.3). */
static c5_rvec3 shade_sample(const c5_trace_ctx *c, c5_rvec3 p, c5_rvec3 view, c5_rvec3 grad, const c5_real rgba[4])
{
    const c5_tf_desc *tf = &c->s->tf;
    c5_rvec3 col = rv3(rgba[0], rgba[1], rgba[2]);
    c5_real g2 = rv3_dot(grad, grad);
    if (g2 == 0)
        return rv3_scale(col, tf->ambient);
    /* the lights' share fades in: min(|g|^2 / fade_g2, 1) (spec sec. 4.3) */
    c5_real fade = g2 < c->fade_g2 ? g2 / c->fade_g2 : 1;
    c5_rvec3 n = rv3_scale(grad, -1 / sqrt(g2));
    if (rv3_dot(n, view) < 0)
        n = rv3_scale(n, -1); /* two-sided: the normal faces the viewer */
    c5_real diff = 0, spec = 0;
    for (int i = 0; i < c->s->n_lights; i++) {
        const c5_light *l = &c->s->lights[i];
        c5_real dist;
        c5_rvec3 L = light_dir(l, p, &dist);
        c5_real ndl = rv3_dot(n, L);
        if (ndl <= 0)
            continue;
        diff += l->intensity * ndl;
        c5_real ndh = rv3_dot(n, rv3_norm(rv3_add(L, view)));
        if (ndh > 0)
            spec += l->intensity * pow(ndh, tf->specular_power);
    }
    c5_real k = tf->ambient + fade * tf->diffuse * diff, ks = fade * tf->specular * spec;
    return rv3(col.x * k + ks, col.y * k + ks, col.z * k + ks);
}

/* Marches the volume part of [0, tend) along r, front to back. Shadow rays only
 * attenuate. Returns 1 when the ray terminated early (opacity reached max_opacity). */
static int march(const c5_trace_ctx *c, const c5_ray *r, c5_real tend, c5_real *T, c5_rvec3 *col, c5_cref_stats *st)
{
    c5_real t0, t1;
    if (!c->has_volume || !C5R(ray_box)(r->o, r->d, c->box_lo, c->box_hi, &t0, &t1))
        return 0;
    if (t1 > tend)
        t1 = tend;
    if (t1 < 0)
        return 0;
    /* Candidate indices with one step of margin; the position test decides membership. */
    c5_real kfirst = t0 > 0 ? ceil(t0 / c->step) - 1 : 0;
    c5_real klast = floor(t1 / c->step) + 1;
    int is_shadow = r->type == C5_RAY_SHADOW;
    double max_opacity = c->s->render.max_opacity;
    c5_rvec3 view = rv3_scale(r->d, -1);
    /* An integer count, not a floating k: k++ stops changing k past 2^53, and a loop on it
     * never ends. c5_supervol_build refuses grids whose diagonal is more than
     * C5_MAX_RAY_SAMPLES steps, so the cap only holds against a degenerate ray (a NaN
     * span gives no samples). */
    c5_real k0 = kfirst < 0 ? 0 : kfirst, span = klast - k0;
    long long last = span >= 0 ? (span < C5_MAX_RAY_SAMPLES ? (long long)span : C5_MAX_RAY_SAMPLES) : -1;
    for (long long i = 0; i <= last; i++) {
        c5_real t = (k0 + i) * c->step;
        if (t >= tend)
            break;
        c5_rvec3 p = rv3_madd(r->o, r->d, t);
        if (!inside_grid(c, p))
            continue;
        c5_real value, rgba[4];
        c5_rvec3 grad;
        int need_grad = !is_shadow && c->shade;
        field_sample(c, p, &value, need_grad ? &grad : NULL);
        st->samples++;
        tf_lookup(&c->tf, value, rgba);
        c5_real a = rgba[3];
        if (a <= 0)
            continue;
        if (!is_shadow) {
            c5_rvec3 sc = need_grad ? shade_sample(c, p, view, grad, rgba) : rv3(rgba[0], rgba[1], rgba[2]);
            *col = rv3_add(*col, rv3_scale(rv3_mul(r->w, sc), *T * a));
        }
        *T *= 1 - a;
        if (1 - *T >= max_opacity)
            return 1;
    }
    return 0;
}

static int nearest_surface(const c5_trace_ctx *c, const c5_ray *r, c5_real *t)
{
    int hit = -1;
    c5_real best = r->tmax;
    for (int i = 0; i < c->s->n_surfaces; i++) {
        c5_real th;
        if (C5R(ray_surface)(&c->s->surfaces[i], r->o, r->d, c->eps, best, &th)) {
            best = th;
            hit = i;
        }
    }
    *t = best;
    return hit;
}

/* Spawns a ray unless it is too light or too deep; counts what was cut. */
static void spawn(const c5_trace_ctx *c, c5_ray *child, c5_cref_stats *st, c5_ray_stack *stk)
{
    if (rv3_maxc(child->w) < c->s->render.min_weight || rv3_maxc(child->w) <= 0) {
        st->ends[C5_CUT_WEIGHT]++;
        return;
    }
    if (child->type != C5_RAY_SHADOW && child->gen > c->s->render.max_bounces) {
        st->ends[C5_CUT_BOUNCES]++;
        return;
    }
    push(stk, child, st);
}

/* A ray ends on surface i at distance t with weight W (already times the volume's
 * transmittance): local shading now, shadow, reflected and refracted rays later. */
static void hit_surface(const c5_trace_ctx *c, const c5_ray *r, int i, c5_real t, c5_rvec3 W, c5_real rgb[3],
                        c5_cref_stats *st, c5_ray_stack *stk)
{
    const c5_surface *s = &c->s->surfaces[i];
    const c5_material *m = &s->mat;
    c5_rvec3 p = rv3_madd(r->o, r->d, t);
    c5_rvec3 n = C5R(surface_normal)(s, p);
    int entering = rv3_dot(n, r->d) < 0;
    if (!entering)
        n = rv3_scale(n, -1);
    c5_real kd = 1 - (c5_real)m->reflectivity - m->transparency;
    if (kd > 0) {
        c5_rvec3 base = rv3_scale(rv3_mul(W, rv3_of(m->color)), kd);
        c5_real local = m->ambient;
        for (int li = 0; li < c->s->n_lights; li++) {
            const c5_light *l = &c->s->lights[li];
            c5_real dist;
            c5_rvec3 L = light_dir(l, p, &dist);
            c5_real ndl = rv3_dot(n, L);
            if (ndl <= 0)
                continue;
            if (!l->shadows) {
                local += (c5_real)m->diffuse * l->intensity * ndl;
                continue;
            }
            c5_ray sh = {p, L, rv3_scale(base, (c5_real)m->diffuse * l->intensity * ndl), dist, C5_RAY_SHADOW, r->gen};
            spawn(c, &sh, st, stk);
        }
        add_rgb(rgb, rv3_scale(base, local));
    }
    c5_rvec3 wr = rv3_scale(W, m->reflectivity), wt = rv3_scale(W, m->transparency);
    c5_rvec3 dt = r->d; /* planes and rectangles are thin sheets: light passes unbent */
    if (m->transparency > 0 && s->kind == C5_SURF_SPHERE &&
        !C5R(refract)(r->d, n, entering ? 1 / (c5_real)m->ior : m->ior, &dt)) {
        wr = rv3_add(wr, wt); /* total internal reflection */
        wt = rv3(0, 0, 0);
    }
    if (rv3_maxc(wr) > 0) {
        c5_ray rr = {p, c5_reflect(r->d, n), wr, INFINITY, C5_RAY_REFLECT, r->gen + 1};
        spawn(c, &rr, st, stk);
    }
    if (rv3_maxc(wt) > 0) {
        c5_ray rt = {p, dt, wt, INFINITY, C5_RAY_REFRACT, r->gen + 1};
        spawn(c, &rt, st, stk);
    }
}

static void trace_shadow(const c5_trace_ctx *c, const c5_ray *r, c5_real rgb[3], c5_cref_stats *st)
{
    c5_real T = 1;
    for (int i = 0; i < c->s->n_surfaces && T > 0; i++) {
        const c5_surface *s = &c->s->surfaces[i];
        c5_real t, tmin = c->eps;
        /* Each crossing of a surface on the way to the light passes its transparency. */
        while (T > 0 && C5R(ray_surface)(s, r->o, r->d, tmin, r->tmax, &t)) {
            T *= s->mat.transparency;
            tmin = t;
        }
    }
    c5_rvec3 unused = rv3(0, 0, 0);
    if (T <= 0 || march(c, r, r->tmax, &T, &unused, st)) {
        st->ends[C5_END_BLOCKED]++;
        return;
    }
    add_rgb(rgb, rv3_scale(r->w, T));
    st->ends[C5_END_LIGHT]++;
}

static void trace_ray(const c5_trace_ctx *c, const c5_ray *r, c5_real rgb[3], c5_cref_stats *st, c5_ray_stack *stk)
{
    c5_real ts;
    int hit = nearest_surface(c, r, &ts);
    c5_real T = 1;
    c5_rvec3 col = rv3(0, 0, 0);
    int stopped = march(c, r, hit >= 0 ? ts : INFINITY, &T, &col, st);
    add_rgb(rgb, col);
    if (stopped) {
        st->ends[C5_END_OPACITY]++;
        return;
    }
    c5_rvec3 W = rv3_scale(r->w, T);
    if (hit < 0) {
        add_rgb(rgb, rv3_mul(W, rv3_of(c->s->render.background)));
        st->ends[C5_END_LEFT]++;
        return;
    }
    st->ends[C5_END_SURFACE]++;
    hit_surface(c, r, hit, ts, W, rgb, st, stk);
}

void C5R(trace_pixel)(const c5_trace_ctx *c, const c5_ray *eye, c5_real rgb[3], c5_cref_stats *st, c5_ray_stack *stk)
{
    stk->n = 0;
    push(stk, eye, st);
    while (stk->n > 0) {
        c5_ray r = stk->rays[--stk->n];
        if (r.type == C5_RAY_SHADOW)
            trace_shadow(c, &r, rgb, st);
        else
            trace_ray(c, &r, rgb, st, stk);
    }
}
