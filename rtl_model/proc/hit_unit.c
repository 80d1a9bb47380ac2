/* The hit unit: the end of a ray's volume part (docs/rendering-spec.md sec. 6-7) in fixed
 * point. Background, light reached, or a surface hit with its local light and the shadow,
 * reflected and refracted rays it spawns. */
#include "fxops.h"
#include "geom.h"
#include "processor.h"

static void add_scaled(int64_t out[3], const int64_t v[3], int64_t k, int shift)
{
    for (int c = 0; c < 3; c++)
        out[c] += c5_rshift128_he((__int128)v[c] * k, shift);
}

/* The spawn rules: too light (in every channel), or one bounce too many. */
static int spawn_ok(c5_proc *p, const c5_bray *child)
{
    const c5_frame_regs *r = p->r;
    int64_t m = child->w; /* a shadow ray's weight is its colour: its largest channel */
    if (child->type == C5_RAY_SHADOW)
        for (int c = 0; c < 3; c++)
            m = c == 0 || child->rgb[c] > m ? child->rgb[c] : m;
    if (m <= 0 || m < (child->type == C5_RAY_SHADOW ? r->min_rgb : r->min_w)) {
        p->st.ends[C5_CUT_WEIGHT]++;
        return 0;
    }
    if (child->type != C5_RAY_SHADOW && (int)child->gen > r->max_bounces) {
        p->st.ends[C5_CUT_BOUNCES]++;
        return 0;
    }
    return 1;
}

/* Direction and distance (geom_t) from H to a light. */
static int64_t light_dir(const c5_light_regs *l, const int64_t H[3], int64_t L[3])
{
    if (l->kind == C5_LIGHT_DIRECTIONAL) {
        L[0] = l->dir[0], L[1] = l->dir[1], L[2] = l->dir[2];
        return C5_T_INF;
    }
    int64_t to[3] = {l->pos[0] - H[0], l->pos[1] - H[1], l->pos[2] - H[2]};
    return c5_geom_normalize(to, L);
}

void c5_proc_finish(c5_proc *p, c5_bray *ray, int64_t tmin)
{
    const c5_frame_regs *r = p->r;
    int64_t T = C5_ONE15 - ray->opa;
    int64_t out[3] = {0, 0, 0};
    if (ray->type == C5_RAY_SHADOW) {
        add_scaled(out, ray->rgb, T, 15);
        p->io.deliver(p->io.ctx, ray->u, ray->v, out);
        p->st.ends[C5_END_LIGHT]++;
        return;
    }
    int64_t W = c5_rshift_he(ray->w * T, 15); /* weight at the end, UQ1.15 */
    for (int c = 0; c < 3; c++)
        out[c] = ray->rgb[c];
    if (ray->surf == C5_SURF_NONE) {
        add_scaled(out, r->bg, W, 15);
        p->io.deliver(p->io.ctx, ray->u, ray->v, out);
        p->st.ends[C5_END_LEFT]++;
        return;
    }
    p->st.ends[C5_END_SURFACE]++;
    p->st.hits++;
    p->st.cycles += C5_CYC_HIT;
    int si = (int)ray->surf;
    const c5_surface_regs *s = &r->surf[si];
    int64_t Q[3], H[3], n[3], t;
    c5_geom_from_voxel(r, ray->pos, Q);
    /* The hit lies at most a step behind the position (the lifetime ran out) or ahead of it. */
    if (!c5_geom_hit(s, Q, ray->dir, tmin, C5_T_INF, &t))
        t = 0; /* grazing: rounding moved the position off the surface; end where it is */
    c5_geom_point(Q, ray->dir, t, H);
    c5_geom_normal(s, H, n);
    if (r->nsh[C5_W_NORMAL])
        for (int a = 0; a < 3; a++)
            n[a] = c5_narrow(n[a], r->nsh[C5_W_NORMAL]); /* a unit vector: stays in SQ1.14 */
    int entering = c5_geom_dot14(n, ray->dir) < 0;
    if (!entering)
        for (int a = 0; a < 3; a++)
            n[a] = -n[a];
    int plane = s->kind != C5_SURF_SPHERE ? si : -1; /* a spawned ray never re-hits its plane */
    c5_bray child = *ray;
    child.opa = 0;
    if (s->kdiff > 0) {
        int64_t base[3]; /* W k c_m, UQ1.15 */
        for (int c = 0; c < 3; c++)
            base[c] = c5_rshift128_he((__int128)W * s->kdiff * s->color[c], 30);
        int64_t local = s->ambient; /* light_term UQ4.12 */
        for (int i = 0; i < r->n_lights; i++) {
            const c5_light_regs *l = &r->lights[i];
            int64_t L[3];
            int64_t dist = light_dir(l, H, L);
            int64_t ndl = c5_geom_dot14(n, L);
            if (ndl <= 0)
                continue;
            if (!l->shadows) {
                local += c5_rshift_he(s->diffuse * l->intensity * ndl, 26);
                continue;
            }
            child.type = C5_RAY_SHADOW;
            child.w = 0;
            for (int c = 0; c < 3; c++) /* radiance delivered if nothing is in the way, UQ2.12 */
                child.rgb[c] = c5_narrow_clamp(
                    c5_clamp64(c5_rshift128_he((__int128)base[c] * s->diffuse * l->intensity * ndl,
                                               15 + 12 + 12 + 14 - 12),
                               0, C5_RGB_MAX, &p->st.saturations),
                    r->nsh[C5_W_RGB], 0, C5_RGB_MAX, &p->st.saturations);
            if (spawn_ok(p, &child))
                c5_proc_new_ray(p, H, L, dist, plane, &child);
        }
        local = c5_clamp64(local, 0, 65535, &p->st.saturations); /* UQ4.12, saturating */
        add_scaled(out, base, local, 15);
    }
    p->io.deliver(p->io.ctx, ray->u, ray->v, out);

    int64_t wr = c5_rshift_he(W * s->refl, 15), wt = c5_rshift_he(W * s->transp, 15);
    int64_t dt[3] = {ray->dir[0], ray->dir[1], ray->dir[2]}; /* thin sheets pass light unbent */
    if (s->transp > 0 && s->kind == C5_SURF_SPHERE &&
        !c5_geom_refract(ray->dir, n, entering ? s->eta_in : s->eta_out, dt)) {
        wr += wt; /* total internal reflection */
        wt = 0;
    }
    /* The spawned rays' contributions (UQ1.15, narrowed with opacity: widths.h). */
    wr = c5_narrow_clamp(wr, r->nsh[C5_W_OPACITY], 0, 65535, &p->st.saturations);
    wt = c5_narrow_clamp(wt, r->nsh[C5_W_OPACITY], 0, 65535, &p->st.saturations);
    child.gen = ray->gen + 1;
    child.rgb[0] = child.rgb[1] = child.rgb[2] = 0;
    if (wr > 0) {
        int64_t dr[3];
        c5_geom_reflect(ray->dir, n, dr);
        child.type = C5_RAY_REFLECT;
        child.w = wr;
        if (spawn_ok(p, &child))
            c5_proc_new_ray(p, H, dr, C5_T_INF, plane, &child);
    }
    if (wt > 0) {
        child.type = C5_RAY_REFRACT;
        child.w = wt;
        if (spawn_ok(p, &child))
            c5_proc_new_ray(p, H, dt, C5_T_INF, plane, &child);
    }
}
