/* A ray's run recorded on a helper thread and replayed on the board's (ray_log.h). */
#include <stdlib.h>
#include <string.h>

#include "ray_log.h"

/* The log: the two counts, the cache runs, the events. */
typedef struct {
    uint32_t n_acc, n_ev;
} header;

_Static_assert(sizeof(header) == 8 && sizeof(c5_rlog_event) % 8 == 0, "a log's parts stay 8-byte aligned");

static int grow(void **a, uint32_t *cap, size_t size)
{
    uint32_t c = *cap ? 2 * *cap : 64;
    void *p = realloc(*a, c * size);
    if (!p)
        return -1;
    *a = p;
    *cap = c;
    return 0;
}

void c5_rlog_access_slow(c5_ray_rec *rec, uint64_t tag)
{
    if (rec->n_acc == rec->cap_acc && grow((void **)&rec->acc, &rec->cap_acc, sizeof *rec->acc) != 0) {
        rec->oom = 1;
        return;
    }
    rec->acc[rec->n_acc++] = tag | 1ull << C5_RLOG_TAG_BITS;
}

static c5_rlog_event *event(c5_ray_rec *rec, uint32_t kind)
{
    if (rec->n_ev == rec->cap_ev && grow((void **)&rec->ev, &rec->cap_ev, sizeof *rec->ev) != 0) {
        rec->oom = 1;
        return NULL;
    }
    c5_rlog_event *e = &rec->ev[rec->n_ev++];
    e->kind = kind;
    return e;
}

static void rec_enqueue(void *ctx, const c5_bray *r)
{
    c5_ray_rec *rec = ctx;
    c5_rlog_event *e = event(rec, C5_RLOG_ENQUEUE);
    if (e) {
        e->shadow = r->shadow;
        e->cell = r->cell;
        e->node = r->node;
        c5_bray_pack(r, rec->cells, e->pk);
    }
}

static void rec_deliver(void *ctx, uint32_t u, uint32_t v, const int64_t rgb[3])
{
    c5_rlog_event *e = event(ctx, C5_RLOG_DELIVER);
    if (e) {
        e->px.u = u;
        e->px.v = v;
        memcpy(e->px.rgb, rgb, sizeof e->px.rgb);
    }
}

void c5_rlog_recorder(c5_proc *w, const c5_proc *p, c5_ray_rec *rec)
{
    *w = *p;
    w->taps = NULL;
    w->io = (c5_proc_io){rec, rec_enqueue, rec_deliver, NULL};
    w->rec = rec;
    rec->cells = p->cells;
    memset(&w->st, 0, sizeof w->st);
}

size_t c5_rlog_size(const c5_ray_rec *rec)
{
    return sizeof(header) + rec->n_acc * sizeof *rec->acc + rec->n_ev * sizeof *rec->ev;
}

void c5_rlog_write(const c5_ray_rec *rec, void *dst)
{
    header h = {rec->n_acc, rec->n_ev};
    char *o = dst;
    memcpy(o, &h, sizeof h);
    o += sizeof h;
    if (rec->n_acc) /* a run that samples nothing has no array yet (memcpy from NULL is undefined) */
        memcpy(o, rec->acc, rec->n_acc * sizeof *rec->acc);
    o += rec->n_acc * sizeof *rec->acc;
    if (rec->n_ev)
        memcpy(o, rec->ev, rec->n_ev * sizeof *rec->ev);
}

void c5_rlog_replay(c5_proc *p, const void *log)
{
    header h;
    memcpy(&h, log, sizeof h);
    const uint64_t *acc = (const uint64_t *)((const char *)log + sizeof h);
    for (uint32_t i = 0; i < h.n_acc; i++) {
        int64_t tag = (int64_t)(acc[i] & ((1ull << C5_RLOG_TAG_BITS) - 1));
        uint64_t n = acc[i] >> C5_RLOG_TAG_BITS;
        int line = c5_cache_line_of(tag);
        if (p->cache_tag[line] == tag) {
            p->st.cache_hits += n;
        } else {
            p->st.cache_misses++;
            p->st.cache_hits += n - 1;
            p->cache_tag[line] = tag;
        }
    }
    const c5_rlog_event *ev = (const c5_rlog_event *)(acc + h.n_acc);
    for (uint32_t i = 0; i < h.n_ev; i++) {
        const c5_rlog_event *e = &ev[i];
        if (e->kind == C5_RLOG_DELIVER) {
            p->io.deliver(p->io.ctx, e->px.u, e->px.v, e->px.rgb);
        } else if (p->io.enqueue_packet) {
            p->io.enqueue_packet(p->io.ctx, e->pk, e->cell, e->node, e->shadow);
        } else {
            c5_bray r; /* unpack(pack(r)) is r: packing asserts every field is in its range */
            c5_bray_unpack(e->pk, p->cells, &r);
            r.shadow = e->shadow;
            p->io.enqueue(p->io.ctx, &r);
        }
    }
}

void c5_rlog_free(c5_ray_rec *rec)
{
    free(rec->acc);
    free(rec->ev);
    memset(rec, 0, sizeof *rec);
}
