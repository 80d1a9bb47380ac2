/* The table of sweepable datapath widths (widths.h). */
#include "widths.h"

#include <string.h>

#include "ray.h"

static const struct {
    const char *name;
    int shipped;
} table[C5_W_COUNT] = {
    [C5_W_POS] = {"pos", C5_POS_F},     [C5_W_DIR] = {"dir", C5_DIR_F},
    [C5_W_VALUE] = {"value", 8},        [C5_W_RGBA] = {"rgba", 15},
    [C5_W_OPACITY] = {"opacity", 15},   [C5_W_RGB] = {"rgb", C5_RGB_F},
    [C5_W_NORMAL] = {"normal", 14},
};

int c5_width_shipped(c5_width_id id) { return table[id].shipped; }
const char *c5_width_name(c5_width_id id) { return table[id].name; }

c5_widths c5_widths_shipped(void)
{
    c5_widths w;
    for (int i = 0; i < C5_W_COUNT; i++)
        w.frac[i] = table[i].shipped;
    return w;
}

int c5_widths_are_shipped(const c5_widths *w)
{
    for (int i = 0; i < C5_W_COUNT; i++)
        if (w->frac[i] != table[i].shipped)
            return 0;
    return 1;
}

int c5_widths_set(c5_widths *w, const char *name, int bits, c5_err *err)
{
    for (int i = 0; i < C5_W_COUNT; i++)
        if (strcmp(name, table[i].name) == 0) {
            if (bits < 1 || bits > table[i].shipped)
                return c5_fail(err, "width %s=%d: must be 1 .. %d (its shipped fraction bits; the packet is fixed)",
                               name, bits, table[i].shipped);
            w->frac[i] = bits;
            return 0;
        }
    char names[128] = "";
    for (int i = 0; i < C5_W_COUNT; i++) {
        strcat(names, i ? ", " : "");
        strcat(names, table[i].name);
    }
    return c5_fail(err, "unknown datapath width '%s' (known: %s)", name, names);
}
