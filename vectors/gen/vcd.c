/* The VCD writer of the vector set and of the frame waveform (vcd.h). */
#include "vcd.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define VCD_MAX_FIELDS 64

typedef struct {
    const c5_vblock *b;
    char *last[VCD_MAX_FIELDS];      /* each field's last value as written, "" before the first */
    char id[VCD_MAX_FIELDS][4];      /* the fields' identifiers */
} vcd_scope;

struct c5_vcd {
    c5_afile af;
    int opened;
    long n;                          /* vectors written (c5_vcd_vector) */
    long long unit;                  /* time units a ns */
    long long now;                   /* the time last written */
    long long next_fall;             /* the falling edge after the last rising edge */
    int n_scopes;
    vcd_scope s[C5_VCD_MAX_SCOPES];
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

/* clk and rst are identifiers 0 and 1 in every scope. */
#define ID_CLK "!"
#define ID_RST "\""

static void free_vcd(c5_vcd *v)
{
    for (int s = 0; s < v->n_scopes; s++)
        for (int k = 0; k < VCD_MAX_FIELDS; k++)
            free(v->s[s].last[k]);
    free(v);
}

c5_vcd *c5_vcd_open_scopes(const char *path, const c5_vblock *const *blocks, int n, const char *version,
                           const char *comment, int fs, int exclusive)
{
    if (n < 1 || n > C5_VCD_MAX_SCOPES) {
        errno = EINVAL;
        return NULL;
    }
    for (int s = 0; s < n; s++)
        if (blocks[s]->n_fields > VCD_MAX_FIELDS) {
            errno = EINVAL;
            return NULL;
        }
    c5_vcd *v = calloc(1, sizeof *v);
    if (!v)
        return NULL;
    v->n_scopes = n;
    v->unit = fs ? 1000000 : 1;
    int next_id = 2;
    for (int s = 0; s < n; s++) {
        v->s[s].b = blocks[s];
        for (int k = 0; k < blocks[s]->n_fields; k++) {
            make_id(v->s[s].id[k], next_id++);
            if (!(v->s[s].last[k] = calloc(blocks[s]->fields[k].width + 1, 1))) {
                free_vcd(v);
                return NULL;
            }
        }
    }
    c5_err e;
    if (exclusive && access(path, F_OK) == 0) {
        free_vcd(v);
        errno = EEXIST;
        return NULL;
    }
    if (c5_afile_open(&v->af, path, &e) != 0) {
        int no = v->af.err_no ? v->af.err_no : EINVAL;
        free_vcd(v);
        errno = no;
        return NULL;
    }
    v->opened = 1;
    /* No $date: the same vectors give the same bytes. */
    c5_afile_printf(&v->af, "$version %s $end\n", version);
    if (comment)
        c5_afile_printf(&v->af, "$comment %s $end\n", comment);
    c5_afile_printf(&v->af, "$timescale 1%s $end\n", fs ? "fs" : "ns");
    for (int s = 0; s < n; s++) {
        const c5_vblock *b = blocks[s];
        c5_afile_printf(&v->af, "$scope module %s $end\n", b->name);
        c5_afile_printf(&v->af, "$var wire 1 %s clk $end\n$var wire 1 %s rst $end\n", ID_CLK, ID_RST);
        for (int k = 0; k < b->n_fields; k++) {
            unsigned w = b->fields[k].width;
            if (w == 1)
                c5_afile_printf(&v->af, "$var wire 1 %s %s $end\n", v->s[s].id[k], b->fields[k].name);
            else
                c5_afile_printf(&v->af, "$var wire %u %s %s [%u:0] $end\n", w, v->s[s].id[k], b->fields[k].name, w - 1);
        }
        c5_afile_printf(&v->af, "$upscope $end\n");
    }
    c5_afile_printf(&v->af, "$enddefinitions $end\n#0\n$dumpvars\n0%s\n1%s\n", ID_CLK, ID_RST);
    for (int s = 0; s < n; s++)
        for (int k = 0; k < blocks[s]->n_fields; k++)
            c5_afile_printf(&v->af, blocks[s]->fields[k].width == 1 ? "x%s\n" : "bx %s\n", v->s[s].id[k]);
    c5_afile_printf(&v->af, "$end\n");
    c5_vcd_at(v, C5_VCD_HALF_NS * v->unit);
    c5_vcd_clk(v, 1);
    return v;
}

c5_vcd *c5_vcd_open(const char *path, const c5_vblock *b)
{
    return c5_vcd_open_scopes(path, &b, 1, "cube5 vectors (docs/vectors.md)", NULL, 0, 0);
}

long long c5_vcd_unit(const c5_vcd *v) { return v->unit; }

int c5_vcd_at(c5_vcd *v, long long t)
{
    if (t < v->now)
        return -1;
    if (t > v->now)
        c5_afile_printf(&v->af, "#%lld\n", t);
    v->now = t;
    return 0;
}

void c5_vcd_clk(c5_vcd *v, int level)
{
    c5_afile_printf(&v->af, "%d%s\n", level != 0, ID_CLK);
    if (level)
        v->next_fall = v->now + C5_VCD_HALF_NS * v->unit;
}

void c5_vcd_rst(c5_vcd *v, int level) { c5_afile_printf(&v->af, "%d%s\n", level != 0, ID_RST); }

/* Field value from hex digits: binary, most significant bit first, `width` bits; 'x' digits
 * give unknown bits. */
static void to_bits(const char *hex, unsigned digits, unsigned width, char *out)
{
    for (unsigned i = 0; i < width; i++) {
        unsigned bit = width - 1 - i, d = digits - 1 - bit / 4;
        char c = hex[d];
        if (c == 'x') {
            out[i] = 'x';
            continue;
        }
        unsigned nib = (unsigned)(c <= '9' ? c - '0' : c - 'a' + 10);
        out[i] = (char)('0' + ((nib >> (bit % 4)) & 1));
    }
    out[width] = 0;
}

int c5_vcd_values(c5_vcd *v, int k, const char *line)
{
    vcd_scope *sc = &v->s[k];
    char bits[257];
    const char *p = line;
    for (int i = 0; i < sc->b->n_fields; i++) {
        unsigned w = sc->b->fields[i].width, digits = (w + 3) / 4;
        to_bits(p, digits, w, bits);
        p += digits + 1;
        if (!strcmp(bits, sc->last[i]))
            continue;
        strcpy(sc->last[i], bits);
        if (w == 1) {
            c5_afile_printf(&v->af, "%c%s\n", bits[0], sc->id[i]);
        } else {
            const char *s = bits;
            while (s[1] && ((s[0] == '0' && s[1] != 'x') || (s[0] == 'x' && s[1] == 'x'))) /* leading 0s (xs) are implied */
                s++;
            c5_afile_printf(&v->af, "b%s %s\n", s, sc->id[i]);
        }
    }
    return v->af.err_no ? -1 : 0;
}

int c5_vcd_vector(c5_vcd *v, const char *line)
{
    long long t = 2LL * C5_VCD_HALF_NS * (v->n + 1) * v->unit;
    c5_vcd_at(v, t);
    c5_vcd_clk(v, 0);
    if (v->n == 0)
        c5_vcd_rst(v, 0);
    c5_vcd_values(v, 0, line);
    c5_vcd_at(v, t + C5_VCD_HALF_NS * v->unit);
    c5_vcd_clk(v, 1);
    v->n++;
    return v->af.err_no ? -1 : 0;
}

void c5_vcd_abort(c5_vcd *v)
{
    if (v->opened)
        c5_afile_abort(&v->af);
    free_vcd(v);
}

int c5_vcd_close(c5_vcd *v, c5_err *err)
{
    int rc = 0;
    if (v->opened) {
        c5_vcd_at(v, v->next_fall);
        c5_vcd_clk(v, 0);
        rc = c5_afile_commit(&v->af, err);
    }
    free_vcd(v);
    return rc;
}
