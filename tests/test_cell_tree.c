/* The Cell Tree in DSP RAM (rtl_model/dsp/cell_tree.h): construction by the paper's rule on
 * hand-made ray traces (Figure 3), the node layout in the RAM bytes, child lists longer than
 * Figure 8's six (five a slot here), and what happens when the RAM is full. */
#include <stdlib.h>
#include <string.h>

#include "cell_tree.h"
#include "harness.h"

/* A node's path of cells from its root, as digits: "121" for root 1 -> 2 -> 1. */
static void path_of(int i, const int *parent, const int *cell, char *buf)
{
    char rev[64];
    int n = 0;
    for (; i >= 0; i = parent[i])
        rev[n++] = (char)('0' + cell[i]);
    for (int k = 0; k < n; k++)
        buf[k] = rev[n - 1 - k];
    buf[n] = 0;
}

static int has_path(const c5_ctree *t, const char *want)
{
    int parent[C5_TREE_SLOTS], cell[C5_TREE_SLOTS];
    uint32_t id[C5_TREE_SLOTS];
    c5_ctree_export(t, parent, cell, id);
    for (uint32_t i = 0; i < t->nodes; i++) {
        char p[64];
        path_of((int)i, parent, cell, p);
        if (strcmp(p, want) == 0)
            return 1;
    }
    return 0;
}

/* Figure 3: (a) eye rays enter cells 1 and 2; (b) reflection, refraction and shadow rays
 * enter cell 2 from cell 1, and cells 1 and 5 from cell 2; (c) secondary rays enter cell 1
 * from cell 2, cell 2 from cell 1 and cell 2 from cell 5. Each step is a packet the DSP
 * tags on its way to a queue; rays spawned inside a cell keep their parent's node. */
TEST(ctree_figure3_construction)
{
    static c5_ctree t;
    c5_ctree_init(&t, 0);
    /* (a) */
    uint32_t r1 = c5_ctree_tag(&t, C5_NODE_NONE, 1), r2 = c5_ctree_tag(&t, C5_NODE_NONE, 2);
    CHECK(r1 != r2);
    CHECK_INT(c5_ctree_tag(&t, C5_NODE_NONE, 1), r1); /* more eye rays in cell 1: same root */
    CHECK_INT(c5_ctree_tag(&t, r1, 1), r1);           /* a ray spawned in cell 1 stays in it */
    /* (b) */
    uint32_t n12 = c5_ctree_tag(&t, r1, 2), n21 = c5_ctree_tag(&t, r2, 1), n25 = c5_ctree_tag(&t, r2, 5);
    CHECK_INT(c5_ctree_tag(&t, r1, 2), n12); /* a second ray on the same dependency */
    /* (c) */
    uint32_t n121 = c5_ctree_tag(&t, n12, 1), n212 = c5_ctree_tag(&t, n21, 2), n252 = c5_ctree_tag(&t, n25, 2);
    CHECK_INT(t.nodes, 8);
    CHECK_INT(t.used, 8);
    CHECK_INT(t.overflow, 0);
    /* The two branches holding the dependency 2 -> 1 are two nodes, as the paper requires. */
    CHECK(n121 != n21);
    CHECK(n212 != r2 && n252 != r2 && n212 != n252);
    const char *paths[] = {"1", "2", "12", "21", "25", "121", "212", "252"};
    for (size_t i = 0; i < sizeof paths / sizeof paths[0]; i++)
        CHECK_MSG(has_path(&t, paths[i]), "no node for path %s", paths[i]);
    CHECK(!has_path(&t, "11") && !has_path(&t, "5"));
}

/* Bits lsb .. lsb + width - 1 of a little-endian byte string. */
static unsigned bits(const uint8_t *b, int lsb, int width)
{
    unsigned v = 0;
    for (int i = 0; i < width; i++)
        v |= (unsigned)((b[(lsb + i) / 8] >> ((lsb + i) % 8)) & 1) << i;
    return v;
}

/* The RAM holds the node as Figure 8's 12 bytes, through the generated layout: a child
 * appended to a root is visible in the root's bytes. */
TEST(ctree_nodes_live_in_the_ram_bytes)
{
    static c5_ctree t;
    c5_ctree_init(&t, 0);
    uint32_t r = c5_ctree_tag(&t, C5_NODE_NONE, 7);
    uint32_t k = c5_ctree_tag(&t, r, 4095);
    const uint8_t *b = t.ram + (size_t)r * C5_CELL_TREE_NODE_BYTES;
    /* child0 (13 bits at 83) = k, child1..4 (at 70, 45, 32, 13) all ones, cell_id 7 (12 bits
     * at 58), generation 0 (6 bits at 26). */
    CHECK_INT(bits(b, 83, 13), k);
    CHECK_INT(bits(b, 70, 13), C5_NODE_NONE);
    CHECK_INT(bits(b, 45, 13), C5_NODE_NONE);
    CHECK_INT(bits(b, 32, 13), C5_NODE_NONE);
    CHECK_INT(bits(b, 13, 13), C5_NODE_NONE);
    CHECK_INT(bits(b, 58, 12), 7);
    CHECK_INT(bits(b, 26, 6), 0);
    CHECK(c5_cell_tree_node_reserved_zero(b));
    c5_cell_tree_node_t n;
    c5_ctree_read(&t, k, &n);
    CHECK_INT(n.cell_id, 4095);
    CHECK_INT(n.child0, C5_NODE_NONE);
    CHECK_INT(n.ready, 0);
    CHECK_INT(n.extension, 0);
}

/* Every field at its extremes survives pack and unpack, and the node is 12 bytes in
 * 96 KB: 8,192 slots, ids 0..8190. */
TEST(ctree_node_layout_round_trip)
{
    CHECK_INT(C5_CELL_TREE_NODE_BYTES, 12);
    CHECK_INT(C5_TREE_SLOTS, 8192);
    c5_cell_tree_node_t a = {.child0 = 8190, .child1 = 0, .cell_id = 4095, .child2 = 1, .child3 = 4096,
                             .generation = 63, .child4 = 5461, .ready = 1, .chained = 1, .extension = 0};
    uint8_t buf[C5_CELL_TREE_NODE_BYTES];
    c5_cell_tree_node_pack(&a, buf);
    c5_cell_tree_node_t b;
    c5_cell_tree_node_unpack(buf, &b);
    CHECK(memcmp(&a, &b, sizeof a) == 0);
    CHECK(c5_cell_tree_node_reserved_zero(buf));
    buf[0] |= 1; /* a reserved bit */
    CHECK(!c5_cell_tree_node_reserved_zero(buf));
}

/* A node can have any number of children: past five, extension slots carry the list, every
 * child is found again without new slots, and the export sees one parent for all. */
TEST(ctree_more_than_six_children_chain)
{
    static c5_ctree t;
    c5_ctree_init(&t, 0);
    uint32_t r = c5_ctree_tag(&t, C5_NODE_NONE, 0);
    uint32_t kid[40];
    for (int c = 1; c <= 40; c++)
        kid[c - 1] = c5_ctree_tag(&t, r, c);
    CHECK_INT(t.nodes, 41);
    CHECK(t.extensions >= (40 - 5 + 3) / 4);
    CHECK_INT(t.used, t.nodes + t.extensions);
    uint32_t used = t.used;
    for (int c = 40; c >= 1; c--)
        CHECK_INT(c5_ctree_tag(&t, r, c), kid[c - 1]);
    CHECK_INT(t.used, used);
    int parent[64], cell[64];
    uint32_t id[64];
    c5_ctree_export(&t, parent, cell, id);
    for (int i = 1; i < 41; i++) {
        CHECK_INT(parent[i], 0);
        CHECK_INT(cell[i], i);
    }
    /* Grandchildren under a child found through the chain attach to it. */
    uint32_t g = c5_ctree_tag(&t, kid[8], 5); /* cell 9: in an extension slot (paths print digits) */
    CHECK(has_path(&t, "095"));
    CHECK(g != kid[4]);
}

/* A full RAM freezes the tree: every later answer is none, nothing past the capacity is
 * written, and the flag says so. */
TEST(ctree_overflow_freezes)
{
    static c5_ctree t;
    c5_ctree_init(&t, 7);
    uint32_t r = c5_ctree_tag(&t, C5_NODE_NONE, 0);
    for (int c = 1; c <= 5; c++)
        c5_ctree_tag(&t, r, c); /* 6 slots: the root and five children, one slot free */
    CHECK_INT(t.used, 6);
    CHECK_INT(t.overflow, 0);
    uint8_t after[C5_CELL_TREE_NODE_BYTES];
    memcpy(after, t.ram + 6 * C5_CELL_TREE_NODE_BYTES, sizeof after);
    CHECK_INT(c5_ctree_tag(&t, r, 9), C5_NODE_NONE); /* needs an extension and a node */
    CHECK_INT(t.overflow, 1);
    CHECK_INT(t.used, 6);
    CHECK(memcmp(after, t.ram + 6 * C5_CELL_TREE_NODE_BYTES, sizeof after) == 0);
    CHECK_INT(c5_ctree_tag(&t, r, 1), C5_NODE_NONE);
    CHECK_INT(c5_ctree_tag(&t, C5_NODE_NONE, 3), C5_NODE_NONE);
    /* The default capacity is the whole RAM less the "none" id. */
    c5_ctree_init(&t, 0);
    CHECK_INT(t.capacity, 8191);
    c5_ctree_init(&t, 100000);
    CHECK_INT(t.capacity, 8191);
}

/* The scheduler's results land in the RAM bytes; a generation that does not fit is refused
 * and nothing is written. */
TEST(ctree_annotate_writes_generation_and_ready)
{
    static c5_ctree t;
    c5_ctree_init(&t, 0);
    uint32_t r = c5_ctree_tag(&t, C5_NODE_NONE, 1);
    uint32_t k = c5_ctree_tag(&t, r, 2);
    uint32_t ids[2] = {r, k};
    int gen[2] = {1, 63};
    c5_err err;
    CHECK(c5_ctree_annotate(&t, ids, gen, 2, &err) == 0);
    c5_cell_tree_node_t n;
    c5_ctree_read(&t, k, &n);
    CHECK_INT(n.generation, 63);
    CHECK_INT(n.ready, 1);
    int bad[2] = {2, 64};
    uint8_t before[2 * C5_CELL_TREE_NODE_BYTES];
    memcpy(before, t.ram, sizeof before);
    CHECK(c5_ctree_annotate(&t, ids, bad, 2, &err) == -1);
    CHECK_HAS(err.msg, "generation 64");
    CHECK(memcmp(before, t.ram, sizeof before) == 0);
}
