/* The super volume: the scene's one 8-bit grid (the volume the board splits into cells).
 * Voxel (i,j,k) is centred at origin + (i+0.5, j+0.5, k+0.5) * spacing; the grid fills the
 * box [origin, origin + dims * spacing). */
#ifndef C5_SUPERVOL_H
#define C5_SUPERVOL_H

#include <stddef.h>
#include <stdint.h>

#include "err.h"
#include "scene.h"

typedef struct {
    size_t dims[3];
    c5_vec3 origin, spacing;
    uint8_t *v;           /* dims[0]*dims[1]*dims[2], x fastest; NULL when the scene has no volume (dims 0) */
    /* what was placed, for summaries */
    int n_sources;
    char source_label[C5_MAX_VOLUMES][160];
    /* where the spacing came from (docs/scene-format.md, "Spacing"): "scene" (grid.spacing),
     * "file NAME" (a volume file's own spacing) or "default" (1, 1, 1); before grid.size */
    char spacing_source[180];
} c5_supervol;

/* Loads or generates every volume of the scene, maps uint16 through its window, places
 * each at its offset and resolves the grid's dims, spacing and origin (grid.center). The
 * spacing is the scene's grid.spacing when it gives one, else the files' own spacing (they
 * must agree), else (1, 1, 1); grid.size then scales it. A scene without volumes gives an
 * empty super volume (v == NULL). */
int c5_supervol_build(const c5_scene *s, c5_supervol *out, c5_err *err);
void c5_supervol_free(c5_supervol *sv);

/* The analytic Marschner-Lobb signal (f_m, alpha) that the marschner_lobb generator samples
 * when it fills this whole grid, at world point p: value in 0..255 and its gradient per world
 * unit. The generator maps voxel centre (i + 0.5) / n onto [-1, 1] (generators.c), so the
 * signal at p is rho(2 (p - origin) / extent - 1). The analytic reference of tests and sweeps. */
void c5_supervol_marschner_lobb(const c5_supervol *sv, double f_m, double alpha, c5_vec3 p, double *value,
                                c5_vec3 *grad);

/* No volume: the scene is surfaces only. A grid with dims but v == NULL is a shell: its
 * geometry without its voxels, as the emulated board knows it (the voxels stay in the host's
 * memory and arrive cell by cell, c5_board_host). */
static inline int c5_supervol_empty(const c5_supervol *sv) { return !sv->dims[0] || !sv->dims[1] || !sv->dims[2]; }
static inline double c5_supervol_min_spacing(const c5_supervol *sv)
{
    return fmin(sv->spacing.x, fmin(sv->spacing.y, sv->spacing.z));
}
/* Voxel value with indices clamped to the grid (clamp-to-edge). */
static inline unsigned c5_supervol_at(const c5_supervol *sv, long i, long j, long k)
{
    long nx = (long)sv->dims[0], ny = (long)sv->dims[1], nz = (long)sv->dims[2];
    i = i < 0 ? 0 : i >= nx ? nx - 1 : i;
    j = j < 0 ? 0 : j >= ny ? ny - 1 : j;
    k = k < 0 ? 0 : k >= nz ? nz - 1 : k;
    return sv->v[((size_t)k * (size_t)ny + (size_t)j) * (size_t)nx + (size_t)i];
}

#endif
