/* The VCD writer of the vector set (vcd.h). */
#include "vcd.h"

#include <stdlib.h>
#include <string.h>

#define VCD_MAX_FIELDS 64

struct c5_vcd {
    FILE *f;
    const c5_vblock *b;
    long n;                          /* vectors written */
    char *last[VCD_MAX_FIELDS];      /* each field's last value as written, "" before the first */
    char id[VCD_MAX_FIELDS + 2][4];  /* identifiers: clk, rst, then the fields */
};

/* The VCD identifier of signal k: printable characters '!'..'~', base 94. */
static void make_id(char *out, int k)
{
    int i = 0;
    do {
        out[i++] = (char)('!' + k % 94);
        k /= 94;
    } while (k && i < 3);
    out[i] = 0;
}

c5_vcd *c5_vcd_open(const char *path, const c5_vblock *b)
{
    if (b->n_fields > VCD_MAX_FIELDS)
        return NULL;
    c5_vcd *v = calloc(1, sizeof *v);
    if (!v)
        return NULL;
    v->b = b;
    for (int k = 0; k < b->n_fields + 2; k++)
        make_id(v->id[k], k);
    for (int k = 0; k < b->n_fields; k++)
        if (!(v->last[k] = calloc(b->fields[k].width + 1, 1))) {
            c5_vcd_close(v);
            return NULL;
        }
    if (!(v->f = fopen(path, "w"))) {
        c5_vcd_close(v);
        return NULL;
    }
    /* No $date: the same vectors give the same bytes. */
    fprintf(v->f, "$version cube5 vectors (docs/vectors.md) $end\n$timescale 1ns $end\n$scope module %s $end\n",
            b->name);
    fprintf(v->f, "$var wire 1 %s clk $end\n$var wire 1 %s rst $end\n", v->id[0], v->id[1]);
    for (int k = 0; k < b->n_fields; k++) {
        unsigned w = b->fields[k].width;
        if (w == 1)
            fprintf(v->f, "$var wire 1 %s %s $end\n", v->id[k + 2], b->fields[k].name);
        else
            fprintf(v->f, "$var wire %u %s %s [%u:0] $end\n", w, v->id[k + 2], b->fields[k].name, w - 1);
    }
    fprintf(v->f, "$upscope $end\n$enddefinitions $end\n#0\n$dumpvars\n0%s\n1%s\n", v->id[0], v->id[1]);
    for (int k = 0; k < b->n_fields; k++)
        fprintf(v->f, b->fields[k].width == 1 ? "x%s\n" : "bx %s\n", v->id[k + 2]);
    fprintf(v->f, "$end\n#%d\n1%s\n", C5_VCD_HALF_NS, v->id[0]);
    return v;
}

/* Field value from hex digits: binary, most significant bit first, `width` bits. */
static void to_bits(const char *hex, unsigned digits, unsigned width, char *out)
{
    for (unsigned i = 0; i < width; i++) {
        unsigned bit = width - 1 - i, d = digits - 1 - bit / 4;
        char c = hex[d];
        unsigned nib = (unsigned)(c <= '9' ? c - '0' : c - 'a' + 10);
        out[i] = (char)('0' + ((nib >> (bit % 4)) & 1));
    }
    out[width] = 0;
}

int c5_vcd_vector(c5_vcd *v, const char *line)
{
    long t = 2L * C5_VCD_HALF_NS * (v->n + 1);
    fprintf(v->f, "#%ld\n0%s\n", t, v->id[0]);
    if (v->n == 0)
        fprintf(v->f, "0%s\n", v->id[1]);
    char bits[257];
    const char *p = line;
    for (int k = 0; k < v->b->n_fields; k++) {
        unsigned w = v->b->fields[k].width, digits = (w + 3) / 4;
        to_bits(p, digits, w, bits);
        p += digits + 1;
        if (v->n > 0 && !strcmp(bits, v->last[k]))
            continue;
        strcpy(v->last[k], bits);
        if (w == 1) {
            fprintf(v->f, "%c%s\n", bits[0], v->id[k + 2]);
        } else {
            const char *s = bits;
            while (s[0] == '0' && s[1]) /* leading zeros are implied */
                s++;
            fprintf(v->f, "b%s %s\n", s, v->id[k + 2]);
        }
    }
    fprintf(v->f, "#%ld\n1%s\n", t + C5_VCD_HALF_NS, v->id[0]);
    v->n++;
    return ferror(v->f) ? -1 : 0;
}

int c5_vcd_close(c5_vcd *v)
{
    int rc = 0;
    if (v->f) {
        fprintf(v->f, "#%ld\n0%s\n", 2L * C5_VCD_HALF_NS * (v->n + 1), v->id[0]);
        rc = ferror(v->f) | fclose(v->f) ? -1 : 0;
    }
    for (int k = 0; k < VCD_MAX_FIELDS; k++)
        free(v->last[k]);
    free(v);
    return rc;
}
