/* Cell Tree memory images (tree_image.h). */
#include "tree_image.h"

#include <stdio.h>

static const c5_vfield node_field[] = {{"node", C5_CELL_TREE_NODE_WIDTH, 1, "cell_tree_node"}};
static const c5_vfield root_field[] = {{"root", C5_CELL_TREE_NODE_CHILD0_WIDTH, 1, "uint"}};

void c5_vec_tree_image(c5_vset *s, const char *block, const char *source, const char *scene, const char *name,
                       const c5_ctree *t, int roots)
{
    char img[64];
    c5_vblock ram = {block, "DSP RAM image of the Cell Tree: line i = the 12-byte node in slot i "
                            "(docs/bit-layouts.md, cell_tree_node), slots 0..used-1",
                     node_field, 1};
    snprintf(img, sizeof img, "ram_%s", name);
    c5_vfile *f = c5_vfile_open(s, &ram, source, scene, img);
    if (!f)
        return;
    for (uint32_t i = 0; i < t->used; i++) {
        c5_vfile_bytes(f, t->ram + (size_t)i * C5_CELL_TREE_NODE_BYTES);
        c5_vfile_end(f);
    }
    c5_vfile_set(f, "config", json_pack("{s:i, s:i, s:b}", "slots_used", (int)t->used, "nodes", (int)t->nodes,
                                        "overflow", t->overflow));
    c5_vfile_close(f);
    if (!roots)
        return;
    c5_vblock rt = {block, "the DSP's root table beside the RAM: line c = cell c's root node (8191: none)", root_field,
                    1};
    snprintf(img, sizeof img, "roots_%s", name);
    if (!(f = c5_vfile_open(s, &rt, source, scene, img)))
        return;
    for (int c = 0; c < C5_MAX_CELLS; c++) {
        c5_vfile_u(f, t->root[c]);
        c5_vfile_end(f);
    }
    c5_vfile_close(f);
}
