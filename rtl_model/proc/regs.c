/* The DSP's frame set-up: scene doubles -> processor registers, with the model's limits. */
#include <math.h>
#include <string.h>

#include "regs.h"
#include "tf.h"

#define GEOM_F 15
#define GEOM_MAX ((int64_t)1 << 28) /* SQ13.15: |x| < 8192 geom units */

int64_t c5_regs_fx(double x, int frac_bits, int64_t lo, int64_t hi)
{
    /* x 2^frac_bits is exact (or inf, as ldexp gives it) for 0 <= frac_bits < 63: no call at
     * every eye ray's direction */
    double v = nearbyint(x * (double)((uint64_t)1 << frac_bits)); /* default rounding mode: half to even */
    if (!(v >= (double)lo))
        return lo;
    if (v > (double)hi)
        return hi;
    return (int64_t)v;
}

c5_board_stages c5_regs_stages(const c5_scene *s, const c5_supervol *sv, int cells)
{
    c5_board_stages st = {0};
    int vol = !c5_supervol_empty(sv);
    st.gradients = vol && s->render.shading && s->n_lights > 0;
    int shadow_light = 0;
    for (int i = 0; i < s->n_lights; i++)
        shadow_light |= s->lights[i].shadows;
    for (int i = 0; i < s->n_surfaces; i++) {
        const c5_material *m = &s->surfaces[i].mat;
        double kd = 1 - m->reflectivity - m->transparency;
        if (shadow_light && kd > 0 && m->diffuse > 0)
            st.shadow = 1;
        if (m->reflectivity > 0 || (m->transparency > 0 && s->surfaces[i].kind == C5_SURF_SPHERE))
            st.reflect = 1; /* a transparent sphere can reflect totally */
        if (m->transparency > 0)
            st.refract = 1;
    }
    if (s->render.max_bounces == 0)
        st.reflect = st.refract = 0;
    st.scheduling = vol && cells > 1;
    return st;
}

/* A world point in geom coordinates (world / s_min, relative to the grid origin). */
int c5_regs_geom_point(c5_vec3 p, const c5_supervol *sv, int64_t out[3], const char *what, c5_err *err)
{
    double smin = c5_supervol_empty(sv) ? 1 : c5_supervol_min_spacing(sv);
    double g[3] = {(p.x - sv->origin.x) / smin, (p.y - sv->origin.y) / smin, (p.z - sv->origin.z) / smin};
    for (int a = 0; a < 3; a++) {
        if (!(fabs(g[a]) < 8000))
            return c5_fail(err, "%s lies %g grid steps from the grid origin; the model's geometry (geom_coord "
                                "SQ13.15) reaches 8000",
                           what, fabs(g[a]));
        out[a] = c5_regs_fx(g[a], GEOM_F, -GEOM_MAX, GEOM_MAX - 1);
    }
    return 0;
}

void c5_regs_unit14(c5_vec3 d, int64_t out[3])
{
    d = v3_norm(d);
    out[0] = c5_regs_fx(d.x, 14, -(1 << 15), (1 << 15) - 1);
    out[1] = c5_regs_fx(d.y, 14, -(1 << 15), (1 << 15) - 1);
    out[2] = c5_regs_fx(d.z, 14, -(1 << 15), (1 << 15) - 1);
}

static int check_max(double v, double max, const char *what, c5_err *err)
{
    if (!(v < max))
        return c5_fail(err, "%s = %g: the model's format holds values below %g", what, v, max);
    return 0;
}

/* The limits the ray packet's fields put on the frame, and the run-time datapath widths. */
static int packet_limits(const c5_scene *s, const c5_board_opts *o, int cells, c5_frame_regs *r, c5_err *err)
{
    if (s->render.width > 512 || s->render.height > 512)
        return c5_fail(err, "image %dx%d: the ray packet's destination (9+9 bits) holds images up to 512x512",
                       s->render.width, s->render.height);
    if (s->n_surfaces > 31)
        return c5_fail(err, "%d surfaces: the packet's interaction field (5 bits) names up to 31", s->n_surfaces);
    if (s->render.max_bounces > C5_MAX_GEN)
        return c5_fail(err, "max_bounces %d: the packet's generation field (4 bits) counts up to %d",
                       s->render.max_bounces, C5_MAX_GEN);
    if (cells > C5_MAX_CELLS)
        return c5_fail(err, "%d cells: the packet's cell id (12 bits) names up to %d", cells, C5_MAX_CELLS);
    if (o->widths)
        for (int i = 0; i < C5_W_COUNT; i++) {
            int shipped = c5_width_shipped((c5_width_id)i), w = o->widths->frac[i];
            if (w < 1 || w > shipped)
                return c5_fail(err, "width %s=%d: must be 1 .. %d (its shipped fraction bits; the packet is fixed)",
                               c5_width_name((c5_width_id)i), w, shipped);
            r->nsh[i] = shipped - w;
        }
    return 0;
}

/* The grid's registers: dims, step and scales per axis, the transfer-function table; with no
 * grid, the unit scales the hit unit needs. */
static int grid_regs(const c5_scene *s, const c5_supervol *sv, const c5_board_opts *o, double smin, double step,
                     c5_frame_regs *r, c5_err *err)
{
    if (r->has_volume) {
        double sp[3] = {sv->spacing.x, sv->spacing.y, sv->spacing.z}, diag = 0;
        for (int a = 0; a < 3; a++) {
            int n = o->cells[a] > 1 ? o->cells[a] : 1;
            if (n > (int)sv->dims[a])
                return c5_fail(err, "%d cells along axis %d but the grid has %zu voxels there", o->cells[a], a,
                               sv->dims[a]);
            size_t edge = (sv->dims[a] + (size_t)n - 1) / (size_t)n;
            if (edge > C5_CELL_MAX_EDGE)
                return c5_fail(err, "grid %zux%zux%zu in %d cells along axis %d: cells of %zu voxels; the packet "
                                    "position (UQ8.15 from the cell's corner) holds cells up to %d a side (use at "
                                    "least %zu cells along axis %d)",
                               sv->dims[0], sv->dims[1], sv->dims[2], n, a, edge, C5_CELL_MAX_EDGE,
                               (sv->dims[a] + C5_CELL_MAX_EDGE - 1) / C5_CELL_MAX_EDGE, a);
            if (!(sv->dims[a] * sp[a] / smin <= C5_MODEL_MAX_GRID))
                return c5_fail(err, "grid %zux%zux%zu: %g grid steps along axis %d; the model's geometry "
                                    "(geom_coord SQ13.15) reaches %d",
                               sv->dims[0], sv->dims[1], sv->dims[2], sv->dims[a] * sp[a] / smin, a,
                               C5_MODEL_MAX_GRID);
            r->dims[a] = (int)sv->dims[a];
            if (check_max(step / sp[a], 7.99, "step / spacing (step_k, step_vec SQ3.15)", err) ||
                check_max(sp[a] / smin, 255, "spacing ratio (UQ8.16)", err))
                return -1;
            r->step_k[a] = c5_regs_fx(step / sp[a], 20, 0, ((int64_t)16 << 20) - 1);
            r->gscale[a] = c5_regs_fx(sp[a] / smin, 16, 0, ((int64_t)256 << 16) - 1);
            r->vscale[a] = c5_regs_fx(smin / sp[a], 20, 0, (int64_t)1 << 20);
            r->gs[a] = c5_regs_fx(smin / sp[a], 15, 0, (int64_t)1 << 15);
            r->gdims[a] = c5_regs_fx(sv->dims[a] * sp[a] / smin, GEOM_F, 0, GEOM_MAX - 1);
            diag += pow(sv->dims[a] * sp[a], 2);
        }
        if (sqrt(diag) / step + 2 > C5_LIFE_MAX)
            return c5_fail(err, "the grid's diagonal is %g samples long: the packet's lifetime (12 bits) counts "
                                "up to %u (use a larger render.step)",
                           sqrt(diag) / step, C5_LIFE_MAX);
        r->step_g = c5_regs_fx(step / smin, 20, 1, ((int64_t)16 << 20) - 1);
        c5_tf_table t;
        c5_tf_build(&s->tf, step, c5_render_unit(s, sv), &t);
        for (int i = 0; i < 256; i++)
            for (int c = 0; c < 4; c++)
                r->tf[i][c] = (int32_t)c5_regs_fx(t.rgba[i][c], 15, 0, C5_ONE15);
        double diag_g = sqrt(diag) / smin;
        r->eps_g = c5_regs_fx(fmax(1e-6 * diag_g, 1.0 / 64), GEOM_F, 1, GEOM_MAX);
    } else {
        r->eps_g = 1 << (GEOM_F - 6);
        /* No grid: geom and "voxel" coordinates are both world units from the origin. The hit
         * unit finds a hit again from the ray's position (c5_geom_from_voxel of the pos that
         * c5_proc_new_ray stored with c5_geom_to_voxel); with these scales left 0 every
         * surfaces-only ray was re-intersected from the origin instead of its own start. */
        for (int a = 0; a < 3; a++) {
            r->gscale[a] = (int64_t)1 << 16;
            r->vscale[a] = (int64_t)1 << 20;
        }
    }
    return 0;
}

static int light_regs(const c5_scene *s, const c5_supervol *sv, c5_frame_regs *r, c5_err *err)
{
    r->n_lights = s->n_lights;
    for (int i = 0; i < s->n_lights; i++) {
        const c5_light *l = &s->lights[i];
        c5_light_regs *lr = &r->lights[i];
        lr->kind = l->kind;
        lr->shadows = l->shadows;
        if (check_max(l->intensity, 16, "light intensity (light_term UQ4.12)", err))
            return -1;
        lr->intensity = c5_regs_fx(l->intensity, 12, 0, 65535);
        if (l->kind == C5_LIGHT_POINT) {
            if (c5_regs_geom_point(l->position, sv, lr->pos, "a point light", err))
                return -1;
        } else {
            c5_regs_unit14(v3_scale(l->direction, -1), lr->dir);
        }
    }
    return 0;
}

static int surface_regs(const c5_scene *s, const c5_supervol *sv, double smin, c5_frame_regs *r, c5_err *err)
{
    r->n_surfaces = s->n_surfaces;
    for (int i = 0; i < s->n_surfaces; i++) {
        const c5_surface *f = &s->surfaces[i];
        const c5_material *m = &f->mat;
        c5_surface_regs *q = &r->surf[i];
        q->kind = f->kind;
        if (c5_regs_geom_point(f->point, sv, q->p, "a surface", err))
            return -1;
        c5_regs_unit14(f->kind == C5_SURF_RECT ? v3_cross(f->u, f->v) : f->normal, q->n);
        for (int a = 0; a < 3; a++) {
            q->eu[a] = c5_regs_fx(v3_comp(f->u, a) / smin, GEOM_F, -GEOM_MAX, GEOM_MAX);
            q->ev[a] = c5_regs_fx(v3_comp(f->v, a) / smin, GEOM_F, -GEOM_MAX, GEOM_MAX);
            q->color[a] = c5_regs_fx(v3_comp(m->color, a), 15, 0, C5_ONE15);
        }
        if (f->kind == C5_SURF_SPHERE && check_max(f->radius / smin, 8000, "sphere radius / spacing", err))
            return -1;
        q->r = c5_regs_fx(f->radius / smin, GEOM_F, 1, GEOM_MAX);
        if (check_max(m->ambient, 16, "material ambient", err) || check_max(m->diffuse, 16, "material diffuse", err) ||
            check_max(m->ior, 16, "material ior", err) || check_max(1 / m->ior, 16, "1 / material ior", err))
            return -1;
        q->ambient = c5_regs_fx(m->ambient, 12, 0, 65535);
        q->diffuse = c5_regs_fx(m->diffuse, 12, 0, 65535);
        q->refl = c5_regs_fx(m->reflectivity, 15, 0, C5_ONE15);
        q->transp = c5_regs_fx(m->transparency, 15, 0, C5_ONE15);
        q->kdiff = C5_ONE15 - q->refl - q->transp;
        if (q->kdiff < 0)
            q->kdiff = 0;
        q->eta_in = c5_regs_fx(1 / m->ior, 28, 0, (int64_t)16 << 28);
        q->eta_out = c5_regs_fx(m->ior, 28, 0, (int64_t)16 << 28);
    }
    return 0;
}

int c5_regs_build(const c5_scene *s, const c5_supervol *sv, const c5_board_opts *o, c5_frame_regs *r, c5_err *err)
{
    memset(r, 0, sizeof *r);
    int cells = 1;
    for (int a = 0; a < 3; a++)
        cells *= o->cells[a] > 1 ? o->cells[a] : 1;
    r->st = c5_regs_stages(s, sv, cells);
    if (o->all_stages) {
        r->st.gradients = !c5_supervol_empty(sv) && s->render.shading; /* computed even without lights */
        r->st.shadow = r->st.reflect = r->st.refract = 1;
    }
    if (packet_limits(s, o, cells, r, err) != 0)
        return -1;
    r->has_volume = !c5_supervol_empty(sv);
    double smin = r->has_volume ? c5_supervol_min_spacing(sv) : 1;
    double step = r->has_volume ? c5_render_step(s, sv) : 1;
    if (grid_regs(s, sv, o, smin, step, r, err) != 0)
        return -1;
    if (check_max(s->tf.ambient, 16, "shading.ambient", err) || check_max(s->tf.diffuse, 16, "shading.diffuse", err) ||
        check_max(s->tf.specular, 16, "shading.specular", err))
        return -1;
    r->ka = c5_regs_fx(s->tf.ambient, 12, 0, 65535);
    r->kd = c5_regs_fx(s->tf.diffuse, 12, 0, 65535);
    r->ks = c5_regs_fx(s->tf.specular, 12, 0, 65535);
    for (int i = 0; i <= 1 << C5_POW_BITS; i++)
        r->pow_tab[i] = (int32_t)c5_regs_fx(pow(ldexp(i, -C5_POW_BITS), s->tf.specular_power), 15, 0, C5_ONE15);
    r->a_max = c5_regs_fx(s->render.max_opacity, 15, 1, C5_ONE15);

    if (light_regs(s, sv, r, err) != 0 || surface_regs(s, sv, smin, r, err) != 0)
        return -1;
    r->min_w = c5_regs_fx(s->render.min_weight, 15, 0, C5_ONE15);
    r->min_rgb = c5_regs_fx(s->render.min_weight, 12, 0, C5_RGB_MAX);
    r->max_bounces = s->render.max_bounces;
    for (int a = 0; a < 3; a++) {
        if (check_max(v3_comp(s->render.background, a), 4, "background (UQ2.12)", err))
            return -1;
        r->bg[a] = c5_regs_fx(v3_comp(s->render.background, a), 12, 0, C5_RGB_MAX);
    }
    return 0;
}
