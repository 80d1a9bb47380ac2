/* Memory images of the DSP's Cell Tree (rtl_model/dsp/cell_tree.h) for the "cell_tree" and
 * "sched" blocks: the RAM's node slots (one 96-bit node a line, line i = slot i) and the
 * root table (64 lines of 13 bits, line c = cell c's root). */
#ifndef C5_VEC_TREE_IMAGE_H
#define C5_VEC_TREE_IMAGE_H

#include "cell_tree.h"
#include "vecset.h"

/* Writes BLOCK.SOURCE.ram_NAME.hex and (when roots) BLOCK.SOURCE.roots_NAME.hex, slots
 * 0..used-1. NAME tells which moment of the trace the image holds. */
void c5_vec_tree_image(c5_vset *s, const char *block, const char *source, const char *scene, const char *name,
                       const c5_ctree *t, int roots);

#endif
