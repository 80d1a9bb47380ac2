/* Max Work's shadow on the growing Cell Tree (mw_shadow.h). */
#include <stdlib.h>
#include <string.h>

#include "mw_shadow.h"

enum {
    SH_SEEN = 1,   /* the node has received packets */
    SH_DONE = 2,   /* its cell was loaded since: its rays are worked off on the board */
    SH_WAIT = 4,   /* waiting in the shadow (its parent's step is taken) */
    SH_TAKEN = 8,  /* worked off in the shadow */
};

int c5_mw_shadow_init(c5_mw_shadow *s, int ncells, uint32_t none)
{
    memset(s, 0, sizeof *s);
    s->ncells = ncells;
    s->none = none ? none : C5_NODE_NONE;
    size_t n = (size_t)s->none + 1, m = (size_t)(ncells > 0 ? ncells : 1);
    s->rays = calloc(n, sizeof *s->rays);
    s->cell = malloc(n * sizeof *s->cell);
    s->first = malloc(n * sizeof *s->first);
    s->sibling = malloc(n * sizeof *s->sibling);
    s->state = calloc(n, sizeof *s->state);
    s->link = malloc(n * sizeof *s->link);
    s->vlink = malloc(n * sizeof *s->vlink);
    s->head = malloc(m * sizeof *s->head);
    s->vhead = malloc(m * sizeof *s->vhead);
    s->vrays = calloc(m, sizeof *s->vrays);
    s->vpending = calloc(m, sizeof *s->vpending);
    if (!s->rays || !s->cell || !s->first || !s->sibling || !s->state || !s->link || !s->vlink || !s->head ||
        !s->vhead || !s->vrays || !s->vpending) {
        c5_mw_shadow_free(s);
        return -1;
    }
    for (size_t i = 0; i < m; i++)
        s->head[i] = s->vhead[i] = -1;
    return 0;
}

void c5_mw_shadow_free(c5_mw_shadow *s)
{
    free(s->rays), free(s->cell), free(s->first), free(s->sibling), free(s->state), free(s->link), free(s->vlink);
    free(s->head), free(s->vhead), free(s->vrays), free(s->vpending);
    memset(s, 0, sizeof *s);
}

/* Node v waits in the shadow: its parent's step is taken (or it is a root). */
static void make_wait(c5_mw_shadow *s, int32_t v)
{
    int c = s->cell[v];
    s->state[v] |= SH_WAIT;
    s->vlink[v] = s->vhead[c];
    s->vhead[c] = v;
    s->vrays[c] += s->rays[v];
    if (!(s->state[v] & SH_DONE))
        s->vpending[c]++;
}

void c5_mw_shadow_tag(c5_mw_shadow *s, uint32_t from, uint32_t node, int cell)
{
    s->ops += C5_OPS_SHADOW_TAG;
    if (s->broken)
        return;
    if (node >= s->none || cell < 0 || cell >= s->ncells || (s->state[node] & SH_DONE)) {
        s->broken = 1;
        return;
    }
    int32_t v = (int32_t)node;
    if (!(s->state[v] & SH_SEEN)) {
        s->state[v] = SH_SEEN;
        s->cell[v] = cell;
        s->first[v] = -1;
        s->link[v] = s->head[cell];
        s->head[cell] = v;
        int root = from >= s->none;
        if (!root && (from == node || !(s->state[from] & SH_SEEN))) {
            s->broken = 1; /* a node that came into being without a counted packet */
            return;
        }
        if (!root) {
            s->sibling[v] = s->first[from];
            s->first[from] = v;
        }
        if (root || (s->state[from] & SH_TAKEN))
            make_wait(s, v);
    } else if (s->cell[v] != cell) {
        s->broken = 1;
        return;
    }
    s->rays[v]++;
    if (s->state[v] & SH_WAIT)
        s->vrays[cell]++;
}

void c5_mw_shadow_load(c5_mw_shadow *s, int cell)
{
    if (s->broken || cell < 0 || cell >= s->ncells)
        return;
    for (int32_t v = s->head[cell]; v >= 0; v = s->link[v]) {
        s->state[v] |= SH_DONE;
        if (s->state[v] & SH_WAIT)
            s->vpending[cell]--;
        s->ops += C5_OPS_SHADOW_DONE;
    }
    s->head[cell] = -1;
}

/* Max Work's choice in the shadow: most waiting rays, ties to the lowest cell; -1: none. */
static int busiest(c5_mw_shadow *s)
{
    int best = -1;
    uint64_t most = 0;
    for (int c = 0; c < s->ncells; c++)
        if (s->vhead[c] >= 0 && (best < 0 || s->vrays[c] > most))
            best = c, most = s->vrays[c];
    s->ops += (uint64_t)s->ncells * C5_OPS_SHADOW_CELL;
    return best;
}

int c5_mw_shadow_advance(c5_mw_shadow *s)
{
    if (s->broken)
        return -1;
    for (;;) {
        int c = busiest(s);
        if (c < 0 || s->vpending[c] > 0)
            return c;
        int32_t v = s->vhead[c];
        s->vhead[c] = -1;
        s->vrays[c] = 0;
        for (; v >= 0; v = s->vlink[v]) {
            s->state[v] = (uint8_t)((s->state[v] & ~SH_WAIT) | SH_TAKEN);
            for (int32_t k = s->first[v]; k >= 0; k = s->sibling[k])
                make_wait(s, k);
            s->ops += C5_OPS_SHADOW_NODE;
        }
        s->steps++;
    }
}
