/* The waveform of a frame's cycle-level parts (frame_vcd.h). */
#include "frame_vcd.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "blocks.h"
#include "c5_layouts.h"
#include "ray.h"
#include "vcd.h"

/* valid, to_dsp, then the packet vectors' columns (vectors/gen/vec_packet.c): the generated
 * layout's fields and the 256-bit packet. */
static const c5_vfield bus_fields[] = {
    {"valid", 1, 0, "uint"},
    {"to_dsp", 1, 0, "uint"},
#define X(m, lsb, w, sgn, fmt) {#m, w, 0, fmt},
    C5_RAY_PACKET_FIELDS_FORMAT(X)
#undef X
    {"packet", C5_RAY_PACKET_WIDTH, 0, "bits"},
};
static const c5_vblock bus_block = {"ray_bus", "packets between the processor and the DSP", bus_fields,
                                    (int)(sizeof bus_fields / sizeof bus_fields[0])};

#define LINE_MAX_CHARS 512

typedef struct {
    uint8_t pk[C5_PACKET_BYTES];
} packet;

struct c5_frame_vcd {
    c5_vcd *v;
    char path[4096];
    c5_taps taps;
    uint64_t from, to;          /* the window of sorter cycles [from, to) */
    int64_t pend;               /* the cycle waiting to be written (-1: the reset, before the first) */
    char q_line[LINE_MAX_CHARS];
    int refill;                 /* the pending cycle inserts a packet from the DSP: */
    packet in;                  /* that packet */
    packet *gap;                /* packets to the DSP after the pending cycle's rising edge */
    size_t n_gap, cap_gap;
    char bus_last[LINE_MAX_CHARS]; /* the bus scope's values as last written */
    int rst_low;                /* rst written low */
    int io, oom;
    c5_frame_vcd_stats st;
};

/* Appends `width` bits of the little-endian bytes `le` as hex digits, and a space. */
static char *put_hex(char *p, const uint8_t *le, unsigned width)
{
    unsigned digits = (width + 3) / 4;
    for (unsigned d = digits; d-- > 0;) {
        unsigned nib = (le[d / 2] >> (4 * (d % 2))) & 15u;
        if (d == digits - 1 && width % 4)
            nib &= (1u << (width % 4)) - 1u;
        *p++ = "0123456789abcdef"[nib];
    }
    *p++ = ' ';
    return p;
}

static char *put_u(char *p, uint64_t v, unsigned width)
{
    uint8_t le[8];
    for (int i = 0; i < 8; i++)
        le[i] = (uint8_t)(v >> (8 * i));
    return put_hex(p, le, width);
}

/* The bus scope's line for a packet (valid 1). */
static void bus_line(char *out, const uint8_t *pk, int to_dsp)
{
    c5_ray_packet_t f;
    c5_ray_packet_unpack(pk, &f);
    char *p = put_u(out, 1, 1);
    p = put_u(p, (uint64_t)(to_dsp != 0), 1);
#define X(m, lsb, w, sgn) p = put_u(p, (uint64_t)f.m, w);
    C5_RAY_PACKET_FIELDS(X)
#undef X
    p = put_hex(p, pk, C5_RAY_PACKET_WIDTH);
    p[-1] = 0;
}

/* The bus idle: valid low, the rest as last written. */
static void bus_idle(c5_frame_vcd *w)
{
    w->bus_last[0] = '0';
    if (c5_vcd_values(w->v, 1, w->bus_last) != 0)
        w->io = 1;
}

static void bus_packet(c5_frame_vcd *w, const uint8_t *pk, int to_dsp)
{
    bus_line(w->bus_last, pk, to_dsp);
    if (c5_vcd_values(w->v, 1, w->bus_last) != 0)
        w->io = 1;
}

static int in_window(const c5_frame_vcd *w, int64_t n)
{
    return n < 0 ? w->from == 0 : (uint64_t)n >= w->from && (uint64_t)n < w->to;
}

/* Writes the pending cycle (its falling and rising edges) and the packets after its rising
 * edge, when they are in the window. */
static void flush(c5_frame_vcd *w)
{
    if (!in_window(w, w->pend)) {
        w->n_gap = 0;
        return;
    }
    long long unit = c5_vcd_unit(w->v), half = C5_VCD_HALF_NS * unit;
    long long edge = half; /* the reset's rising edge */
    if (w->pend >= 0) {
        long long t = 2 * half * (w->pend + 1);
        if (!w->rst_low) { /* the testbench's reset ends at the first cycle, 10 ns */
            c5_vcd_at(w->v, 2 * half);
            c5_vcd_rst(w->v, 0);
            w->rst_low = 1;
        }
        c5_vcd_at(w->v, t);
        c5_vcd_clk(w->v, 0);
        if (c5_vcd_values(w->v, 0, w->q_line) != 0)
            w->io = 1;
        if (w->refill)
            bus_packet(w, w->in.pk, 0);
        else
            bus_idle(w);
        edge = t + half;
        c5_vcd_at(w->v, edge);
        c5_vcd_clk(w->v, 1);
        w->st.written++;
    }
    /* Evenly spaced in the 5 ns after the edge, each with a pulse of half the spacing
     * (>= 1 fs: at most 512 x 512 eye rays at once, far below 2.5 million). */
    long long step = half / (long long)(w->n_gap + 1);
    for (size_t j = 0; j < w->n_gap && step >= 2; j++) {
        c5_vcd_at(w->v, edge + (long long)(j + 1) * step);
        bus_packet(w, w->gap[j].pk, 1);
        c5_vcd_at(w->v, edge + (long long)(j + 1) * step + step / 2);
        bus_idle(w);
    }
    w->n_gap = 0;
}

static void tap_queue(void *ctx, const c5_rq_in *in, const c5_rq_out *o)
{
    c5_frame_vcd *w = ctx;
    flush(w);
    w->pend = (int64_t)w->st.cycles++;
    w->refill = 0;
    if (!in_window(w, w->pend)) {
        if ((uint64_t)w->pend >= w->to)
            w->st.cut = 1;
        return;
    }
    char *p = w->q_line;
    p = put_u(p, in->insert_valid != 0, 1);
    p = put_u(p, in->insert_valid ? in->insert_key : 0, 32);
    p = put_u(p, in->insert_valid ? in->insert_payload : 0, 32);
    p = put_u(p, in->pop_ready != 0, 1);
    p = put_u(p, (uint64_t)o->pop_valid, 1);
    p = put_u(p, o->pop_key, 32);
    p = put_u(p, o->pop_payload, 32);
    p = put_u(p, (uint64_t)o->insert_accepted, 1);
    p = put_u(p, (uint64_t)o->full, 1);
    p = put_u(p, o->count, 9);
    p = put_u(p, (uint64_t)o->empty, 1);
    p[-1] = 0;
}

static void tap_bus(void *ctx, const uint8_t *pk, int to_dsp)
{
    c5_frame_vcd *w = ctx;
    if (!to_dsp) { /* into the sorter in the cycle just stepped */
        w->st.from_dsp++;
        w->refill = 1;
        memcpy(w->in.pk, pk, C5_PACKET_BYTES);
        return;
    }
    w->st.to_dsp++;
    if (!in_window(w, w->pend))
        return;
    if (w->n_gap == w->cap_gap) {
        size_t cap = w->cap_gap ? 2 * w->cap_gap : 64;
        packet *g = realloc(w->gap, cap * sizeof *g);
        if (!g) {
            w->oom = 1;
            return;
        }
        w->gap = g;
        w->cap_gap = cap;
    }
    memcpy(w->gap[w->n_gap++].pk, pk, C5_PACKET_BYTES);
}

c5_frame_vcd *c5_frame_vcd_open(const char *path, uint64_t from, uint64_t cycles, const char *about, c5_err *err)
{
    c5_frame_vcd *w = calloc(1, sizeof *w);
    if (!w) {
        c5_fail(err, "out of memory");
        return NULL;
    }
    const c5_vblock *scopes[2] = {&c5_vblock_ray_queue, &bus_block};
    w->v = c5_vcd_open_scopes(path, scopes, 2, "cube5 render --vcd (docs/vectors.md)", about, 1, 0);
    if (!w->v) {
        c5_fail(err, "%s: cannot write: %s", path, strerror(errno));
        free(w);
        return NULL;
    }
    snprintf(w->path, sizeof w->path, "%s", path);
    w->from = from;
    w->to = from + cycles;
    w->pend = -1;
    /* Before the first packet the bus's fields are unknown. */
    char *p = w->bus_last;
    for (int k = 0; k < bus_block.n_fields; k++) {
        unsigned digits = (bus_fields[k].width + 3) / 4;
        memset(p, k == 0 ? '0' : 'x', digits);
        p += digits;
        *p++ = ' ';
    }
    p[-1] = 0;
    w->taps = (c5_taps){.ctx = w, .queue = tap_queue, .bus = tap_bus};
    return w;
}

const c5_taps *c5_frame_vcd_taps(c5_frame_vcd *w) { return &w->taps; }

void c5_frame_vcd_abort(c5_frame_vcd *w)
{
    c5_vcd_abort(w->v);
    free(w->gap);
    free(w);
}

int c5_frame_vcd_close(c5_frame_vcd *w, c5_frame_vcd_stats *st, c5_err *err)
{
    flush(w);
    int rc = c5_vcd_close(w->v, err) != 0 ? -1 : w->io ? c5_fail(err, "%s: cannot write the waveform", w->path) : 0;
    if (rc == 0 && w->oom)
        rc = c5_fail(err, "out of memory for the waveform");
    if (st)
        *st = w->st;
    free(w->gap);
    free(w);
    return rc;
}
