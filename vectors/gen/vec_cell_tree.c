/* Block "cell_tree": the DSP's Cell Tree construction (rtl_model/dsp/cell_tree.h). One vector
 * per packet the DSP tags: its node and destination cell in, its new node out, from an
 * empty tree; beside the trace the RAM image and root table after its last vector. */
#include <stdlib.h>
#include <string.h>

#include "blocks.h"
#include "rng.h"
#include "tree_image.h"

static const c5_vfield fields[] = {
    {"node_in", C5_CELL_TREE_NODE_CHILD0_WIDTH, 0, "uint"},
    {"cell", C5_CELL_TREE_NODE_CELL_ID_WIDTH, 0, "uint"},
    {"node_out", C5_CELL_TREE_NODE_CHILD0_WIDTH, 1, "uint"},
};

static const c5_vblock block = {"cell_tree",
                                "Cell Tree construction: a packet's node (8191: none) and cell in, its new node "
                                "out, from an empty tree (docs/cell-tree.md); images: the RAM and roots after "
                                "the last vector",
                                fields, 3};

static uint32_t tag(c5_ctree *t, c5_vfile *f, uint32_t node, int cell)
{
    uint32_t out = c5_ctree_tag(t, node, cell);
    c5_vfile_u(f, node);
    c5_vfile_u(f, (uint64_t)cell);
    c5_vfile_u(f, out);
    c5_vfile_end(f);
    return out;
}

static int finish(c5_vset *s, c5_vfile *f, const char *source, const c5_ctree *t)
{
    c5_vfile_close(f);
    c5_vec_tree_image(s, block.name, source, NULL, "final", t, 1);
    return 0;
}

/* "directed": the paper's Figure 3 trace; a node with 14 children (two extension slots);
 * random chains with bounces; cell 4095. "overflow": chains until the 8,191 slots are full,
 * then tags on the frozen tree (existing nodes among them). */
static int directed(c5_vset *s)
{
    c5_ctree *t = malloc(sizeof *t);
    if (!t)
        return c5_fail(s->err, "out of memory for the Cell Tree");
    c5_ctree_init(t, 0);
    c5_vfile *f = c5_vfile_open(s, &block, "directed", NULL, NULL);
    if (!f) {
        free(t);
        return -1;
    }
    const uint32_t N = C5_NODE_NONE;
    uint32_t r1 = tag(t, f, N, 1), r2 = tag(t, f, N, 2);
    tag(t, f, N, 1);
    tag(t, f, r1, 1);
    uint32_t n12 = tag(t, f, r1, 2), n21 = tag(t, f, r2, 1), n25 = tag(t, f, r2, 5);
    tag(t, f, r1, 2);
    tag(t, f, n12, 1);
    tag(t, f, n21, 2);
    tag(t, f, n25, 2);
    uint32_t wide = tag(t, f, N, 63);
    for (int c = 0; c < 14; c++)
        tag(t, f, wide, c);
    for (int c = 13; c >= 0; c -= 3)
        tag(t, f, wide, c); /* existing children found through the chain */
    uint64_t rng = s->seed ^ 0x74726565ull; /* "tree" */
    for (long i = 0; i < s->count; i++) {
        uint32_t node = N;
        int len = 1 + (int)(c5_splitmix64(&rng) % 6);
        for (int k = 0; k < len; k++)
            node = tag(t, f, node, (int)(c5_splitmix64(&rng) % 8));
    }
    /* Appended after the random chains, which keep their lines: cell id 4095, the last of a
     * 4,096-cell split (the 12-bit cell id's largest, the root table's last entry). */
    uint32_t r4095 = tag(t, f, N, 4095); /* a new root for cell 4095 */
    tag(t, f, N, 4095);                   /* found again */
    uint32_t n4095_0 = tag(t, f, r4095, 0); /* its child for cell 0 */
    tag(t, f, n4095_0, 4095);               /* and back: a child for cell 4095 */
    tag(t, f, r1, 4095);                    /* cell 4095 as a child of cell 1's root */
    tag(t, f, r4095, 4095);                 /* a node of cell 4095 bound for 4095: kept */
    finish(s, f, "directed", t);

    c5_ctree_init(t, 0);
    if (!(f = c5_vfile_open(s, &block, "overflow", NULL, NULL))) {
        free(t);
        return -1;
    }
    uint32_t node = N, first_cell[2] = {0, 0}, first_node[2] = {N, N};
    for (int i = 0; !t->overflow; i++) { /* random chains of 100 tags: nearly every tag a new node */
        uint32_t in = i % 100 == 0 ? N : node;
        int cell = (int)(c5_splitmix64(&rng) % 64);
        node = tag(t, f, in, cell);
        if (i < 2) {
            first_cell[i] = (uint32_t)cell;
            first_node[i] = node;
        }
    }
    tag(t, f, N, 5);
    tag(t, f, 0, 7);
    /* Appended: the tree is frozen after the overflow (cell_tree.h), so tags for nodes that
     * exist answer 8191 too: the first chain's root and its first child, asked again. */
    tag(t, f, N, (int)first_cell[0]);
    tag(t, f, first_node[0], (int)first_cell[1]);
    finish(s, f, "overflow", t);
    free(t);
    return 0;
}

/* Scene taps. The first `count` tags of a frame are eye rays finding their roots, so the
 * trace is thinned instead: every tag that changes the tree (a node made, a child list
 * grown) is kept, and of the tags that only read, one in 16, at most `count`. Dropping a
 * read-only tag leaves the tree as it was, so the thinned trace replayed from an empty tree
 * gives exactly the outputs written and ends in the frame's RAM image. */
typedef struct {
    c5_vfile *f;
    uint64_t tags, reads_kept;
    uint32_t used, writes;
    uint64_t rng;
} tap_state;

static void tap_tag(void *ctx, uint32_t node, int cell, uint32_t result)
{
    c5_vscene *v = ctx;
    tap_state *st = v->st[C5_VB_TREE];
    st->tags++;
    int changed = v->tree->used != st->used || v->tree->writes != st->writes;
    st->used = v->tree->used;
    st->writes = (uint32_t)v->tree->writes;
    if (!changed && (c5_splitmix64(&st->rng) % 16 != 0 || st->reads_kept >= (uint64_t)v->set->count))
        return;
    st->reads_kept += !changed;
    c5_vfile_u(st->f, node);
    c5_vfile_u(st->f, (uint64_t)cell);
    c5_vfile_u(st->f, result);
    c5_vfile_end(st->f);
}

static int tap_begin(c5_vscene *v, c5_taps *t)
{
    tap_state *st = calloc(1, sizeof *st);
    if (!st)
        return -1;
    st->rng = v->seed ^ 3;
    if (!(st->f = c5_vfile_open(v->set, &block, v->scene, v->scene, NULL))) {
        free(st);
        return -1;
    }
    v->st[C5_VB_TREE] = st;
    t->tree_tag = tap_tag;
    return 0;
}

static void tap_end(c5_vscene *v)
{
    tap_state *st = v->st[C5_VB_TREE];
    c5_vfile_set(st->f, "offered", json_integer((json_int_t)st->tags));
    c5_vfile_close(st->f);
    c5_vec_tree_image(v->set, block.name, v->scene, v->scene, "final", v->tree, 1);
    free(st);
    v->st[C5_VB_TREE] = NULL;
}

const c5_vblock_gen c5_vgen_tree = {"cell_tree", directed, tap_begin, tap_end};
