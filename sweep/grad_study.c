#include "grad_study.h"

#include <math.h>
#include <string.h>

#include "board.h"
#include "cref.h"
#include "generators.h"
#include "metrics.h"

int c5_grad_study_applies(const c5_scene *s, const c5_supervol *sv)
{
    if (s->n_volumes != 1 || c5_supervol_empty(sv) || !sv->v)
        return 0;
    const c5_volume_desc *d = &s->volumes[0];
    if (d->kind != C5_SRC_GENERATOR ||
        (d->generator != C5_GEN_BLOBS && d->generator != C5_GEN_CLOUD && d->generator != C5_GEN_MARSCHNER_LOBB))
        return 0;
    for (int a = 0; a < 3; a++)
        if (d->offset[a] != 0 || d->gen_dims[a] != sv->dims[a])
            return 0;
    return 1;
}

/* ---- the unquantised field ----------------------------------------------------------- */

typedef struct {
    const c5_supervol *sv;
    const c5_volume_desc *d;
    c5_gen_state g;
    double ext[3];
} field_ctx;

/* The generator's value (0..255, clamped as the voxels are) at generator coordinates q. */
static double unit255(const field_ctx *c, const double q[3])
{
    double u = c5_gen_unit(c->d, &c->g, q);
    return 255 * (u < 0 ? 0 : u > 1 ? 1 : u);
}

static void analytic_sample(const c5_field *f, c5_vec3 p, double *value, c5_vec3 *grad)
{
    const field_ctx *c = f->ctx;
    const double o[3] = {c->sv->origin.x, c->sv->origin.y, c->sv->origin.z}, pp[3] = {p.x, p.y, p.z};
    double q[3];
    for (int a = 0; a < 3; a++)
        q[a] = 2 * (pp[a] - o[a]) / c->ext[a] - 1; /* voxel centre (i + 0.5) / n onto [-1, 1] */
    *value = unit255(c, q);
    if (!grad)
        return;
    /* central differences of the field itself, h = 1e-4 of the half extent (far below a
     * voxel; the generators are smooth there except on the clamp's plateaus) */
    double g[3];
    for (int a = 0; a < 3; a++) {
        double qp[3] = {q[0], q[1], q[2]}, qm[3] = {q[0], q[1], q[2]}, h = 1e-4;
        qp[a] += h;
        qm[a] -= h;
        g[a] = (unit255(c, qp) - unit255(c, qm)) / (2 * h) * 2 / c->ext[a];
    }
    *grad = v3(g[0], g[1], g[2]);
}

/* ---- the cubic B-spline's gradient (the alternative measured) ---------------------------- */

static void spline_sample(const c5_field *f, c5_vec3 p, double *value, c5_vec3 *grad)
{
    const c5_supervol *sv = ((const field_ctx *)f->ctx)->sv;
    c5_supervol_sample(sv, p, value, NULL); /* the trilinear value, as cref's */
    if (!grad)
        return;
    double x = (p.x - sv->origin.x) / sv->spacing.x - 0.5, y = (p.y - sv->origin.y) / sv->spacing.y - 0.5,
           z = (p.z - sv->origin.z) / sv->spacing.z - 0.5;
    double fx = floor(x), fy = floor(y), fz = floor(z);
    long i = (long)fx, j = (long)fy, k = (long)fz;
    double t[3] = {x - fx, y - fy, z - fz}, w[3][4], d[3][4], g[3] = {0, 0, 0};
    for (int a = 0; a < 3; a++) {
        double u = t[a], v = 1 - u;
        w[a][0] = v * v * v / 6;
        w[a][1] = (3 * u * u * u - 6 * u * u + 4) / 6;
        w[a][2] = (-3 * u * u * u + 3 * u * u + 3 * u + 1) / 6;
        w[a][3] = u * u * u / 6;
        d[a][0] = -v * v / 2;
        d[a][1] = (3 * u * u - 4 * u) / 2;
        d[a][2] = (-3 * u * u + 2 * u + 1) / 2;
        d[a][3] = u * u / 2;
    }
    /* the 4^3 voxels i - 1 .. i + 2, each index clamped to the grid */
    for (int c = 0; c < 4; c++)
        for (int b = 0; b < 4; b++)
            for (int a = 0; a < 4; a++) {
                double v = c5_supervol_at_resident(sv, i - 1 + a, j - 1 + b, k - 1 + c);
                g[0] += d[0][a] * w[1][b] * w[2][c] * v;
                g[1] += w[0][a] * d[1][b] * w[2][c] * v;
                g[2] += w[0][a] * w[1][b] * d[2][c] * v;
            }
    *grad = v3(g[0] / sv->spacing.x, g[1] / sv->spacing.y, g[2] / sv->spacing.z);
}

/* ---- the measure --------------------------------------------------------------------- */

double c5_fine_error(const c5_image *ref, const c5_image *test)
{
    const int w = ref->w, h = ref->h;
    double acc = 0;
    long n = 0;
    for (int y = 2; y < h - 2; y++)
        for (int x = 2; x < w - 2; x++)
            for (int ch = 0; ch < 3; ch++) {
                double mean = 0;
                for (int yy = -2; yy <= 2; yy++)
                    for (int xx = -2; xx <= 2; xx++) {
                        size_t o = 3 * ((size_t)(y + yy) * (size_t)w + (size_t)(x + xx)) + (size_t)ch;
                        mean += (double)test->rgb[o] - ref->rgb[o];
                    }
                size_t o = 3 * ((size_t)y * (size_t)w + (size_t)x) + (size_t)ch;
                double e = (double)test->rgb[o] - ref->rgb[o] - mean / 25;
                acc += e * e;
                n++;
            }
    return n ? sqrt(acc / (double)n) : 0;
}

void c5_grad_study_free(c5_grad_study *r)
{
    for (int i = 0; i < C5_GS_N; i++)
        c5_image_free(&r->img[i]);
    c5_image_free(&r->ref);
}

int c5_grad_study_run(const c5_scene *s, const c5_supervol *sv, int keep_images, c5_grad_study *r, c5_err *err)
{
    memset(r, 0, sizeof *r);
    if (!c5_grad_study_applies(s, sv))
        return c5_fail(err, "the gradient study needs a scene whose one volume is a blobs, cloud or marschner_lobb "
                            "generator filling the grid");
    static field_ctx fc; /* large (the blobs); one study at a time */
    fc.sv = sv;
    fc.d = &s->volumes[0];
    c5_gen_prepare(fc.d, &fc.g);
    fc.ext[0] = sv->dims[0] * sv->spacing.x;
    fc.ext[1] = sv->dims[1] * sv->spacing.y;
    fc.ext[2] = sv->dims[2] * sv->spacing.z;
    c5_field analytic = {analytic_sample, &fc}, spline = {spline_sample, &fc};

    c5_scene fine = *s;
    fine.render.step = c5_render_step(s, sv) / 4;
    c5_cref_opts ro = {.field = &analytic};
    c5_cref_stats st;
    if (c5_cref_render(&fine, sv, 0, &ro, &r->ref, &st, err) != 0)
        return -1;
    c5_cref_opts co = {0}, so = {.field = &spline};
    c5_board_opts bo = {0};
    c5_board_stats bs;
    if (c5_cref_render(s, sv, 0, &co, &r->img[C5_GS_CENTRAL], &st, err) != 0 ||
        c5_cref_render(s, sv, 0, &so, &r->img[C5_GS_SPLINE], &st, err) != 0 ||
        c5_board_render(s, sv, 0, &bo, &r->img[C5_GS_BOARD], &bs, err) != 0) {
        c5_grad_study_free(r);
        return -1;
    }
    for (int i = 0; i < C5_GS_N; i++) {
        c5_image_diff d;
        if (c5_image_compare(&r->ref, &r->img[i], &d, err) != 0) {
            c5_grad_study_free(r);
            return -1;
        }
        r->psnr_db[i] = d.psnr_db;
        r->fine[i] = c5_fine_error(&r->ref, &r->img[i]);
    }
    if (!keep_images)
        c5_grad_study_free(r);
    return 0;
}
