/* The table of sweepable datapath widths (widths.h). */
#include "widths.h"

#include <string.h>

#include "c5_layouts.h"

static const char *const names[C5_W_COUNT] = {
    [C5_W_POS] = "pos",         [C5_W_DIR] = "dir", [C5_W_VALUE] = "value",   [C5_W_RGBA] = "rgba",
    [C5_W_OPACITY] = "opacity", [C5_W_RGB] = "rgb", [C5_W_NORMAL] = "normal",
};

/* The shipped format of each signal, from spec/layouts.toml (the generated header): the
 * packet's fields for pos, dir, opacity (contribution has the same format) and rgb, the
 * declared datapath signals for the others. step_vec shares pos's fraction
 * (test widths_shipped_from_the_spec). */
static c5_fx_fmt shipped_fmt(c5_width_id id)
{
    switch (id) {
    case C5_W_POS: return C5_RAY_PACKET_POS_X_FMT;
    case C5_W_DIR: return C5_RAY_PACKET_DIR_X_FMT;
    case C5_W_VALUE: return C5_SIG_SAMPLE_VALUE_FMT;
    case C5_W_RGBA: return C5_SIG_TF_RGBA_FMT;
    case C5_W_OPACITY: return C5_RAY_PACKET_OPACITY_FMT;
    case C5_W_RGB: return C5_RAY_PACKET_RED_FMT;
    case C5_W_NORMAL: return C5_SIG_NORMAL_FMT;
    default: return C5_UQ(0, 0, NULL);
    }
}

int c5_width_shipped(c5_width_id id) { return shipped_fmt(id).frac_bits; }
const char *c5_width_name(c5_width_id id) { return names[id]; }

c5_widths c5_widths_shipped(void)
{
    c5_widths w;
    for (int i = 0; i < C5_W_COUNT; i++)
        w.frac[i] = c5_width_shipped((c5_width_id)i);
    return w;
}

int c5_widths_are_shipped(const c5_widths *w)
{
    for (int i = 0; i < C5_W_COUNT; i++)
        if (w->frac[i] != c5_width_shipped((c5_width_id)i))
            return 0;
    return 1;
}

int c5_widths_set(c5_widths *w, const char *name, int bits, c5_err *err)
{
    for (int i = 0; i < C5_W_COUNT; i++)
        if (strcmp(name, names[i]) == 0) {
            int shipped = c5_width_shipped((c5_width_id)i);
            if (bits < 1 || bits > shipped)
                return c5_fail(err, "width %s=%d: must be 1 .. %d (its shipped fraction bits; the packet is fixed)",
                               name, bits, shipped);
            w->frac[i] = bits;
            return 0;
        }
    char known[128] = "";
    for (int i = 0; i < C5_W_COUNT; i++) {
        strcat(known, i ? ", " : "");
        strcat(known, names[i]);
    }
    return c5_fail(err, "unknown datapath width '%s' (known: %s)", name, known);
}
