#include "supervol.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "generators.h"

/* uint16 -> uint8 through [lo, hi]: round((v - lo) * 255 / (hi - lo)), clamped. */
static void window_to_u8(const c5_volume *v, const c5_volume_desc *d, uint8_t *out, char *label, size_t label_len)
{
    size_t n = c5_volume_count(v);
    double lo, hi;
    if (d->has_window) {
        lo = d->window[0];
        hi = d->window[1];
    } else {
        unsigned mn = 65535, mx = 0;
        for (size_t i = 0; i < n; i++) {
            unsigned x = c5_volume_at(v, i);
            mn = x < mn ? x : mn;
            mx = x > mx ? x : mx;
        }
        lo = mn;
        hi = mx > mn ? mx : mn + 1;
    }
    double scale = 255.0 / (hi - lo);
    for (size_t i = 0; i < n; i++) {
        double x = floor((c5_volume_at(v, i) - lo) * scale + 0.5);
        out[i] = (uint8_t)(x < 0 ? 0 : x > 255 ? 255 : x);
    }
    size_t used = strlen(label);
    snprintf(label + used, label_len - used, " window [%g, %g]", lo, hi);
}

static const char *base_name(const char *path)
{
    const char *b = strrchr(path, '/');
    return b ? b + 1 : path;
}

/* One source volume as 8-bit voxels (malloc'd) with its dims, and the file's own spacing
 * (all 0 when it gives none for every axis: raw files, generators). */
static int load_source(const c5_volume_desc *d, uint8_t **out, size_t dims[3], double spacing[3], char *label,
                       size_t label_len, c5_err *err)
{
    spacing[0] = spacing[1] = spacing[2] = 0;
    if (d->kind == C5_SRC_GENERATOR) {
        size_t n;
        if (c5_dims_product(d->gen_dims, &n) != 0)
            return c5_fail(err, "generator %s: dims %zux%zux%zu too large", c5_generator_name(d->generator),
                           d->gen_dims[0], d->gen_dims[1], d->gen_dims[2]);
        *out = malloc(n);
        if (!*out)
            return c5_fail(err, "generator %s: out of memory for %zu voxels", c5_generator_name(d->generator), n);
        c5_generate(d, *out);
        memcpy(dims, d->gen_dims, sizeof d->gen_dims);
        snprintf(label, label_len, "generator %s %zux%zux%zu", c5_generator_name(d->generator), dims[0], dims[1],
                 dims[2]);
        return 0;
    }
    c5_volume v;
    if (c5_volume_load(d->path, &d->raw, &v, err) != 0)
        return -1;
    size_t n = c5_volume_count(&v);
    *out = malloc(n ? n : 1);
    if (!*out) {
        c5_volume_free(&v);
        return c5_fail(err, "%s: out of memory for %zu voxels", d->path, n);
    }
    snprintf(label, label_len, "file %s %zux%zux%zu %s", base_name(d->path), v.dims[0], v.dims[1], v.dims[2],
             v.type == C5_VOX_U16 ? "uint16" : "uint8");
    if (v.type == C5_VOX_U16)
        window_to_u8(&v, d, *out, label, label_len);
    else
        memcpy(*out, v.data, n);
    memcpy(dims, v.dims, sizeof v.dims);
    if (v.spacing[0] > 0 && v.spacing[1] > 0 && v.spacing[2] > 0)
        memcpy(spacing, v.spacing, sizeof v.spacing);
    c5_volume_free(&v);
    return 0;
}

/* The rule of docs/scene-format.md ("Spacing"): the scene's grid.spacing when given, else
 * the spacing the volume files state (every file that states one must state the same: the
 * grid has one), else (1, 1, 1). */
static int resolve_spacing(const c5_scene *s, const double file_sp[][3], c5_supervol *out, c5_err *err)
{
    if (s->grid.has_spacing) {
        snprintf(out->spacing_source, sizeof out->spacing_source, "scene");
        return 0;
    }
    int from = -1;
    for (int i = 0; i < s->n_volumes; i++) {
        const double *sp = file_sp[i];
        if (!(sp[0] > 0))
            continue;
        if (from < 0) {
            from = i;
            continue;
        }
        const double *f = file_sp[from];
        for (int a = 0; a < 3; a++)
            if (fabs(sp[a] - f[a]) > 1e-9 * fmax(sp[a], f[a]))
                return c5_fail(err, "%s: spacing %g %g %g differs from %s's %g %g %g: the grid has one spacing "
                                    "(give grid.spacing in the scene)", s->volumes[i].path, sp[0], sp[1], sp[2],
                               s->volumes[from].path, f[0], f[1], f[2]);
    }
    if (from < 0) {
        snprintf(out->spacing_source, sizeof out->spacing_source, "default");
        return 0;
    }
    out->spacing = v3(file_sp[from][0], file_sp[from][1], file_sp[from][2]);
    snprintf(out->spacing_source, sizeof out->spacing_source, "file %s", base_name(s->volumes[from].path));
    return 0;
}

static void paste(c5_supervol *sv, const uint8_t *src, const size_t d[3], const long off[3])
{
    for (size_t z = 0; z < d[2]; z++)
        for (size_t y = 0; y < d[1]; y++) {
            size_t gi = (((size_t)off[2] + z) * sv->dims[1] + (size_t)off[1] + y) * sv->dims[0] + (size_t)off[0];
            memcpy(sv->v + gi, src + (z * d[1] + y) * d[0], d[0]);
        }
}

int c5_supervol_build(const c5_scene *s, c5_supervol *out, c5_err *err)
{
    memset(out, 0, sizeof *out);
    out->spacing = s->grid.spacing;
    out->origin = s->grid.origin;
    if (s->n_volumes == 0)
        return 0;

    uint8_t *src[C5_MAX_VOLUMES] = {0};
    size_t dims[C5_MAX_VOLUMES][3];
    double file_sp[C5_MAX_VOLUMES][3];
    size_t need[3] = {0, 0, 0};
    int rc = -1;
    for (int i = 0; i < s->n_volumes; i++) {
        if (load_source(&s->volumes[i], &src[i], dims[i], file_sp[i], out->source_label[i],
                        sizeof out->source_label[i], err) != 0)
            goto done;
        out->n_sources++;
        for (int a = 0; a < 3; a++)
            if ((size_t)s->volumes[i].offset[a] + dims[i][a] > need[a])
                need[a] = (size_t)s->volumes[i].offset[a] + dims[i][a];
    }
    for (int a = 0; a < 3; a++) {
        out->dims[a] = s->grid.dims[a] ? s->grid.dims[a] : need[a];
        if (need[a] > out->dims[a]) {
            c5_fail(err, "grid.dims: the volumes need %zux%zux%zu voxels, the grid has %zux%zux%zu", need[0], need[1],
                    need[2], s->grid.dims[0], s->grid.dims[1], s->grid.dims[2]);
            goto done;
        }
    }
    if (resolve_spacing(s, file_sp, out, err) != 0)
        goto done;
    size_t n;
    if (c5_dims_product(out->dims, &n) != 0) {
        c5_fail(err, "grid: %zux%zux%zu voxels is too large", out->dims[0], out->dims[1], out->dims[2]);
        goto done;
    }
    if (s->grid.size > 0) {
        c5_vec3 ext = v3(out->dims[0] * out->spacing.x, out->dims[1] * out->spacing.y, out->dims[2] * out->spacing.z);
        out->spacing = v3_scale(out->spacing, s->grid.size / v3_maxc(ext));
    }
    if (s->grid.has_center) {
        c5_vec3 half = v3(out->dims[0] * out->spacing.x / 2, out->dims[1] * out->spacing.y / 2,
                          out->dims[2] * out->spacing.z / 2);
        out->origin = v3_sub(s->grid.center, half);
    }
    /* Bounded work per ray: the step (render.step, else the smallest spacing) against the
     * diagonal. A tiny step, or one spacing far below the others, would ask for ~1e11
     * samples per ray. */
    c5_vec3 ext = v3(out->dims[0] * out->spacing.x, out->dims[1] * out->spacing.y, out->dims[2] * out->spacing.z);
    double step = s->render.step > 0 ? s->render.step : c5_supervol_min_spacing(out);
    double samples = v3_len(ext) / step;
    if (!(samples <= C5_MAX_RAY_SAMPLES)) {
        /* name what set the step: the scene's render.step, else the spacing, which is the
         * scene's grid.spacing or a volume file's own */
        char key[200] = "render.step";
        if (!(s->render.step > 0))
            snprintf(key, sizeof key, "%s%s", strcmp(out->spacing_source, "scene") ? "the spacing of " : "grid.",
                     strcmp(out->spacing_source, "scene") ? out->spacing_source : "spacing");
        c5_fail(err, "%s%s%s: a ray across the grid (%g world units) takes %g samples of %g; at most %d (a larger "
                "render.step, or spacing components closer to each other)",
                s->source, *s->source ? ": " : "", key, v3_len(ext), samples, step, C5_MAX_RAY_SAMPLES);
        goto done;
    }
    out->v = malloc(n);
    if (!out->v) {
        c5_fail(err, "grid: out of memory for %zu voxels", n);
        goto done;
    }
    memset(out->v, (int)s->grid.fill, n);
    for (int i = 0; i < s->n_volumes; i++)
        paste(out, src[i], dims[i], s->volumes[i].offset);

    rc = 0;
done:
    for (int i = 0; i < s->n_volumes; i++)
        free(src[i]);
    if (rc != 0) {
        free(out->v);
        out->v = NULL;
    }
    return rc;
}

void c5_supervol_free(c5_supervol *sv)
{
    free(sv->v);
    memset(sv, 0, sizeof *sv);
}

void c5_supervol_marschner_lobb(const c5_supervol *sv, double f_m, double alpha, c5_vec3 p, double *value,
                                c5_vec3 *grad)
{
    double ext[3] = {sv->dims[0] * sv->spacing.x, sv->dims[1] * sv->spacing.y, sv->dims[2] * sv->spacing.z};
    double q[3] = {2 * (p.x - sv->origin.x) / ext[0] - 1, 2 * (p.y - sv->origin.y) / ext[1] - 1,
                   2 * (p.z - sv->origin.z) / ext[2] - 1};
    *value = 255 * c5_marschner_lobb(q[0], q[1], q[2], f_m, alpha);
    if (grad) {
        double g[3];
        c5_marschner_lobb_grad(q[0], q[1], q[2], f_m, alpha, g);
        *grad = v3(255 * g[0] * 2 / ext[0], 255 * g[1] * 2 / ext[1], 255 * g[2] * 2 / ext[2]);
    }
}
