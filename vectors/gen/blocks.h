/* The blocks `cube5 vectors` writes vectors for (docs/vectors.md), each in its own file
 * vec_BLOCK.c with the same shape: its field list (a c5_vblock), its directed corner cases,
 * and optionally its taps on the model while a scene renders. */
#ifndef C5_VEC_BLOCKS_H
#define C5_VEC_BLOCKS_H

#include "board.h"
#include "regs.h"
#include "taps.h"
#include "vecset.h"

/* Each block's tap state inside a scene run. */
enum {
    C5_VB_PACKET,
    C5_VB_QUEUE,
    C5_VB_TREE,
    C5_VB_SCHED,
    C5_VB_INTERP,
    C5_VB_GRADIENT,
    C5_VB_CLASSIFY,
    C5_VB_SHADE,
    C5_VB_COMPOSITE,
    C5_VB_TRAVERSE,
    C5_VB_MAX = 16,
};

/* One scene being rendered with taps. */
typedef struct {
    c5_vset *set;
    const char *scene;      /* the scene's name: the files' source */
    uint64_t seed;          /* this scene's stream (set seed mixed with the scene name) */
    c5_ctree *tree;         /* the DSP's Cell Tree of the frame (blocks may read it) */
    const c5_frame_regs *regs; /* the frame registers the board loads (a block's configuration) */
    void *st[C5_VB_MAX];    /* each block's tap state */
} c5_vscene;

typedef struct {
    const char *name;
    int (*directed)(c5_vset *s);                   /* writes the directed files; 0 or -1 */
    int (*tap_begin)(c5_vscene *v, c5_taps *taps); /* sets its callbacks (taps->ctx is v); NULL: no taps */
    void (*tap_end)(c5_vscene *v);                 /* after the frame: writes its files, frees its state */
} c5_vblock_gen;

extern const c5_vblock_gen *const c5_vblock_gens[];

/* Taps that keep a uniform sample (reservoir.h) of `count` of a frame's transactions of
 * `rec_size` bytes in v->st[slot]: begin (0, or -1 when out of memory); offer one record
 * (copied when chosen); end writes BLOCK.SCENE.hex, the records in stream order through
 * write(), with config (stolen, may be NULL) and "offered", and frees the sample. */
int c5_vsample_begin(c5_vscene *v, int slot, size_t rec_size, uint64_t salt);
void c5_vsample_offer(c5_vscene *v, int slot, const void *rec);
void c5_vsample_end(c5_vscene *v, int slot, const c5_vblock *b, void (*write)(c5_vfile *f, const void *rec),
                    json_t *config);
extern const int c5_n_vblock_gens;

/* The ray queue's fields, the ports of fpga/rtl/ray_queue.vhd: its vectors' columns and the
 * queue scope of a frame's waveform (frame_vcd.h). */
extern const c5_vblock c5_vblock_ray_queue;

/* Renders scene `name` (loaded, at its final size) on the board model split into cells[3],
 * with every block's taps, and returns its end-to-end record: the CRC-32s of the frame
 * buffer (w x h x 3 little-endian uint64 sums), of the packet trace (every packet written
 * into a queue, in order) and of the DSP RAM (all 96 KB) after the frame. NULL on error. */
json_t *c5_vec_scene(c5_vset *s, const char *name, const c5_scene *sc, const c5_supervol *sv, const int cells[3]);

#endif
