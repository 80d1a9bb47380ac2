/* The board model's limits that come from its field widths (docs/scene-format.md, "Scenes
 * the board model refuses"), checked where the command line can still refuse with exit 2:
 * c5_model_check_scene on the parsed scene and the split, BEFORE any volume is read or
 * generated; c5_model_check_grid once the grid is built, for the limits that depend on
 * its spacing and size. Each message is "WHAT: key or option: value: limit (field)". */
#ifndef C5_MODEL_LIMITS_H
#define C5_MODEL_LIMITS_H

#include "err.h"
#include "ray.h" /* the limits of the fields: C5_MODEL_MAX_GRID, ... */
#include "scene.h"
#include "supervol.h"

/* The split where it is left to the model: every cells[a] == 0 becomes the fewest cells that
 * keep a cell within C5_CELL_MAX_EDGE voxels along axis a (1 for up to 256 voxels). */
void c5_model_auto_split(const size_t dims[3], int cells[3]);

/* Image size, surfaces, bounces, cells (cells[3], NULL or 0 along an axis: the automatic
 * split, c5_model_auto_split), the shading, light,
 * material and background factors, and the grid's size where the scene fixes it
 * (grid.dims, or volumes whose dims the scene gives: generators, raw files with dims or an
 * Open SciVis name). `what` names the scene (a file, "built-in scene NAME"). */
int c5_model_check_scene(const c5_scene *s, const int cells[3], const char *what, c5_err *err);
/* The limits that need the built grid (grid size, step and spacing ratios, the packet's
 * lifetime, positions in geom coordinates): the model's own frame set-up (c5_regs_build),
 * its message prefixed with `what`. */
int c5_model_check_grid(const c5_scene *s, const c5_supervol *sv, const int cells[3], const char *what,
                        c5_err *err);

#endif
