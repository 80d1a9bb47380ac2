/* Datapath fraction widths the model can be run at (`cube5 sweep`): the error a
 * narrower signal costs, measured rather than argued. Each entry names one signal of
 * docs/bit-layouts.md; its width may be set to 1 .. its shipped fraction bits. A narrowed
 * signal keeps its container and format: where the datapath produces it, its value is
 * rounded half to even to a multiple of 2^(shipped - width) LSBs. Widening is not offered:
 * the ray packet is a fixed 32 bytes, so a wider pos/dir/colour would be another board.
 * With every width at its shipped value (the default, c5_widths_shipped) the model's bits
 * are exactly those of the golden vectors. */
#ifndef C5_WIDTHS_H
#define C5_WIDTHS_H

#include "err.h"

typedef enum {
    C5_W_POS,     /* pos (15 fraction bits) and step_vec SQ3.15 (they share their fraction) */
    C5_W_DIR,     /* dir SQ1.14 */
    C5_W_VALUE,   /* sample_value UQ8.8 */
    C5_W_RGBA,    /* tf_rgba UQ1.15 */
    C5_W_OPACITY, /* opacity UQ1.15 and contribution UQ1.15 */
    C5_W_RGB,     /* red/green/blue UQ2.12 */
    C5_W_NORMAL,  /* normal SQ1.14 */
    C5_W_COUNT
} c5_width_id;

typedef struct {
    int frac[C5_W_COUNT]; /* fraction bits per signal */
} c5_widths;

/* Every signal at its shipped width. */
c5_widths c5_widths_shipped(void);
/* The shipped fraction bits of a signal, and its name as the sweep knob spells it
 * ("pos", "dir", "value", "rgba", "opacity", "rgb", "normal"). */
int c5_width_shipped(c5_width_id id);
const char *c5_width_name(c5_width_id id);
/* Sets signal `name` to `bits`: -1 with a message for an unknown name or bits outside
 * 1 .. shipped. */
int c5_widths_set(c5_widths *w, const char *name, int bits, c5_err *err);
/* 1 when every width is the shipped one. */
int c5_widths_are_shipped(const c5_widths *w);

#endif
