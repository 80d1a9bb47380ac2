/* The board model's field-width limits, checked before any work (model_limits.h). The
 * numbers come from the formats the model stores them in (docs/bit-layouts.md); c5_regs_build
 * checks the same ones again when it converts a scene, as a second line. */
#include "model_limits.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "ray.h"
#include "regs.h"
#include "nrrd_precheck.h"
#include "volume.h"

/* A factor stored as UQ4.12 (shading, light and material factors): values below 16. */
#define UQ4_MAX 16.0
/* The background and pixel colour channels, UQ2.12: values below 4. */
#define UQ2_MAX 4.0

static int factor(double v, double max, const char *what, const char *key, const char *field, c5_err *err)
{
    if (!(v < max))
        return c5_fail(err, "%s: %s: %g: the board model stores it as %s, which holds values below %g", what, key, v,
                       field, max);
    return 0;
}

/* A NRRD header's sizes, read by the precheck's header rules (never Teem, not the data); -1 for
 * anything else or a header the load will refuse with its own message. */
static int nrrd_dims(const char *path, size_t d[3])
{
    size_t n = strlen(path);
    if (n < 5 || (strcasecmp(path + n - 5, ".nrrd") != 0 && strcasecmp(path + n - 5, ".nhdr") != 0))
        return -1;
    c5_nrrd_header h;
    c5_err ignored;
    if (c5_nrrd_header_info(path, &h, &ignored) != 0)
        return -1;
    memcpy(d, h.dims, sizeof h.dims);
    return 0;
}

/* The grid's voxels per axis where the scene or a volume's header fixes them; 0 where only
 * a file's contents decide. */
static void known_grid(const c5_scene *s, size_t dims[3], int *from_volume)
{
    *from_volume = -1;
    for (int a = 0; a < 3; a++)
        dims[a] = s->grid.dims[a];
    if (s->grid.dims[0])
        return;
    for (int i = 0; i < s->n_volumes; i++) {
        const c5_volume_desc *v = &s->volumes[i];
        size_t d[3] = {0, 0, 0};
        c5_voxel_type t;
        if (v->kind == C5_SRC_GENERATOR)
            for (int a = 0; a < 3; a++)
                d[a] = v->gen_dims[a];
        else if (v->raw.dims[0])
            for (int a = 0; a < 3; a++)
                d[a] = v->raw.dims[a];
        else if (c5_scivis_name(v->path, d, &t) != 0 && nrrd_dims(v->path, d) != 0)
            continue;
        for (int a = 0; a < 3; a++)
            if (d[a] && (size_t)v->offset[a] + d[a] > dims[a]) {
                dims[a] = (size_t)v->offset[a] + d[a];
                if (dims[a] > C5_CELL_MAX_EDGE && *from_volume < 0)
                    *from_volume = i;
            }
    }
}

void c5_model_auto_split(const size_t dims[3], int cells[3])
{
    for (int a = 0; a < 3; a++)
        if (cells[a] == 0)
            cells[a] = dims[a] > C5_CELL_MAX_EDGE ? (int)((dims[a] + C5_CELL_MAX_EDGE - 1) / C5_CELL_MAX_EDGE) : 1;
}

int c5_model_check_scene(const c5_scene *s, const int cells_in[3], const char *what, c5_err *err)
{
    size_t dims[3];
    int vol;
    known_grid(s, dims, &vol);
    int split[3] = {0, 0, 0}; /* NULL: the automatic split, as the board takes it */
    if (cells_in)
        memcpy(split, cells_in, sizeof split);
    c5_model_auto_split(dims, split); /* dims the scene leaves to a file's contents are 0 here */
    const int *cells = split;
    const c5_render_settings *r = &s->render;
    if (r->width > C5_MODEL_MAX_IMAGE || r->height > C5_MODEL_MAX_IMAGE)
        return c5_fail(err, "%s: image %dx%d (camera.width/height or --size): the board model's ray packet "
                            "destination (9+9 bits) holds images up to %dx%d",
                       what, r->width, r->height, C5_MODEL_MAX_IMAGE, C5_MODEL_MAX_IMAGE);
    if (s->n_surfaces > (int)C5_SURF_NONE)
        return c5_fail(err, "%s: surfaces: %d of them: the board model's packet interaction field (5 bits) names "
                            "up to %u (%u means none)",
                       what, s->n_surfaces, C5_SURF_NONE, C5_SURF_NONE);
    if (r->max_bounces > C5_MAX_GEN)
        return c5_fail(err, "%s: render.max_bounces: %d: the board model's packet generation field (4 bits) "
                            "counts up to %d",
                       what, r->max_bounces, C5_MAX_GEN);
    if (cells) {
        long n = (long)cells[0] * cells[1] * cells[2];
        if (n > C5_MAX_CELLS)
            return c5_fail(err, "%s: --cells %dx%dx%d: %ld cells: the board model's packet cell id (12 bits) "
                                "names up to %d",
                           what, cells[0], cells[1], cells[2], n, C5_MAX_CELLS);
    }
    const char *uq4 = "UQ4.12", *light = "light_term UQ4.12", *eta = "eta UQ4.28";
    if (factor(s->tf.ambient, UQ4_MAX, what, "transfer_function.shading.ambient", uq4, err) ||
        factor(s->tf.diffuse, UQ4_MAX, what, "transfer_function.shading.diffuse", uq4, err) ||
        factor(s->tf.specular, UQ4_MAX, what, "transfer_function.shading.specular", uq4, err))
        return -1;
    char key[96];
    for (int i = 0; i < s->n_lights; i++) {
        snprintf(key, sizeof key, "lights[%d].intensity", i);
        if (factor(s->lights[i].intensity, UQ4_MAX, what, key, light, err))
            return -1;
    }
    for (int i = 0; i < s->n_surfaces; i++) {
        const c5_material *m = &s->surfaces[i].mat;
        struct {
            const char *name;
            double v;
            const char *field;
        } f[] = {{"ambient", m->ambient, uq4}, {"diffuse", m->diffuse, uq4}, {"ior", m->ior, eta},
                 {"ior (as 1 / ior)", 1 / m->ior, eta}};
        for (size_t k = 0; k < sizeof f / sizeof f[0]; k++) {
            snprintf(key, sizeof key, "surfaces[%d].material.%s", i, f[k].name);
            if (factor(f[k].v, UQ4_MAX, what, key, f[k].field, err))
                return -1;
        }
    }
    for (int a = 0; a < 3; a++) {
        snprintf(key, sizeof key, "render.background[%d]", a);
        if (factor(v3_comp(r->background, a), UQ2_MAX, what, key, "red/green/blue UQ2.12", err))
            return -1;
    }
    if (vol >= 0)
        snprintf(key, sizeof key, "volumes[%d] (dims + offset)", vol);
    else
        snprintf(key, sizeof key, "grid.dims");
    for (int a = 0; a < 3; a++) {
        if (dims[a] > C5_MODEL_MAX_GRID)
            return c5_fail(err, "%s: %s: a grid of %zu voxels along axis %d: the board model's geometry "
                                "(geom_coord SQ13.15) reaches %d per axis",
                           what, key, dims[a], a, C5_MODEL_MAX_GRID);
        int n = cells && cells[a] > 1 ? cells[a] : 1;
        size_t edge = (dims[a] + (size_t)n - 1) / (size_t)n;
        if (edge > C5_CELL_MAX_EDGE)
            return c5_fail(err, "%s: %s: %zu voxels along axis %d in %d cell(s): cells of %zu voxels; the board "
                                "model's packet position (UQ8.15 from the cell's corner) holds cells up to %d a side "
                                "(--cells with at least %zu along axis %d)",
                           what, key, dims[a], a, n, edge, C5_CELL_MAX_EDGE,
                           (dims[a] + C5_CELL_MAX_EDGE - 1) / C5_CELL_MAX_EDGE, a);
    }
    return 0;
}

int c5_model_check_grid(const c5_scene *s, const c5_supervol *sv, const int cells[3], const char *what,
                        c5_err *err)
{
    c5_board_opts o = {0};
    for (int a = 0; a < 3; a++)
        o.cells[a] = cells && cells[a] > 0 ? cells[a] : 0;
    c5_model_auto_split(sv->dims, o.cells);
    c5_frame_regs *r = malloc(sizeof *r);
    if (!r)
        return c5_fail(err, "%s: out of memory", what);
    c5_err e;
    int rc = c5_regs_build(s, sv, &o, r, &e);
    free(r);
    if (rc != 0)
        return c5_fail(err, "%s: %s", what, e.msg);
    return 0;
}
