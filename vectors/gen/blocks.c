/* The registry of vector blocks (blocks.h). */
#include "blocks.h"

extern const c5_vblock_gen c5_vgen_packet, c5_vgen_queue, c5_vgen_tree, c5_vgen_sched;
extern const c5_vblock_gen c5_vgen_interp, c5_vgen_gradient, c5_vgen_classify, c5_vgen_shade, c5_vgen_composite,
    c5_vgen_traverse;

const c5_vblock_gen *const c5_vblock_gens[] = {
    &c5_vgen_packet,
    &c5_vgen_queue,
    &c5_vgen_tree,
    &c5_vgen_sched,
    &c5_vgen_interp,
    &c5_vgen_gradient,
    &c5_vgen_classify,
    &c5_vgen_shade,
    &c5_vgen_composite,
    &c5_vgen_traverse,
};
const int c5_n_vblock_gens = (int)(sizeof c5_vblock_gens / sizeof c5_vblock_gens[0]);
