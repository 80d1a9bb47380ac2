/* The DSP's choice of the next cell during a frame (c5_board_render): Max Work (most queued
 * rays) or fewest-first on the board's queues, an external schedule of cells or of groups, and
 * an external schedule followed under the certificate, which keeps the frame within Max
 * Work's fetches plus the ledger's budget (docs/cell-tree.md, "The certificate"). */
#include "board_internal.h"
#include "ledger.h"

/* The longest an entry of the plan across boards waits for the boards it depends on, in fetch
 * times of its cell (plan_next). */
#define C5_PLAN_WAIT_FETCHES 8

/* The cell of group g with the most queued rays (ties: lowest id), -1: none holds a ray. */
static int busiest_in_group(const c5_bd *b, int g)
{
    int best = -1;
    size_t best_n = 0;
    for (int c = 0; c < b->cells.count; c++) {
        size_t n = b->q[c].n - b->q[c].head;
        if (n > best_n && c5_bd_group_of(b, c, b->sgroup, b->nsgroup) == g) {
            best = c;
            best_n = n;
        }
    }
    return best;
}

/* The queues the set-up left against the previous frame's: the sum over cells of the
 * smaller count over the larger total (1: the same rays in the same cells; 0: no cell in
 * common). 3 DSP operations a cell (in the certificate's). */
double c5_bd_start_overlap(c5_bd *b)
{
    const c5_board_opts *o = b->o;
    int n = b->cells.count;
    uint64_t both = 0, now = 0, before = 0;
    for (int c = 0; c < n; c++) {
        uint64_t q = c5_bd_queued_in(b, c), p = o->prev_start[c];
        both += q < p ? q : p;
        now += q;
        before += p;
    }
    b->shadow.ops += 3 * (uint64_t)n;
    uint64_t most = now > before ? now : before;
    return most ? (double)both / (double)most : 1.0;
}

/* The frame's budget, after the set-up (ledger.h). */
void c5_bd_set_budget(c5_bd *b)
{
    c5_board_stats *st = b->st;
    b->budget = st->ledger_budget = c5_ledger_budget(b->o->plan, st->frame_key, st->start_overlap, &st->identical);
}

/* The shadow broke (a packet it cannot place: the tree's RAM overflowed): nothing bounds the
 * rest of the frame, and Max Work on the board's queues chooses it. */
void c5_bd_certificate_lost(c5_bd *b)
{
    b->certify = 0;
    b->st->shadow_broken = 1;
}

/* Max Work's choice on the board's queues: most queued rays, ties to the lowest id (fewest:
 * the fewest-first rule); -1: every queue is empty. */
static int pick_cell(const c5_bd *b, int fewest)
{
    int best = -1;
    size_t best_n = 0;
    for (int c = 0; c < b->cells.count; c++) {
        size_t n = c5_bd_queued_in(b, c);
        if (n && (best < 0 || (fewest ? n < best_n : n > best_n))) {
            best = c;
            best_n = n;
        }
    }
    return best;
}

/* The next load under the certificate: the board's own choice (the schedule's next cell with
 * rays, then Max Work on its queues) while the lead (the board's loads less the shadow's steps)
 * stays within the budget, else the cell of the shadow's next step. A load of the shadow's
 * cell lets it take at least one step, so the lead never grows past the budget, and the frame
 * ends within budget + Max Work's fetches. */
static int certified_next(c5_bd *b, int *pos)
{
    const c5_board_opts *o = b->o;
    c5_mw_shadow *sh = &b->shadow;
    int next = c5_mw_shadow_advance(sh);
    int64_t lead = (int64_t)b->st->fetches - (int64_t)sh->steps;
    if (sh->broken || (next < 0 && b->queued)) {
        c5_bd_certificate_lost(b); /* nothing bounds the rest: Max Work on the board's queues */
        *pos = o->schedule_len;
        return -3;
    }
    if (lead > b->st->lead_max)
        b->st->lead_max = lead;
    while (*pos < o->schedule_len && !c5_bd_queued_in(b, o->schedule[*pos])) {
        (*pos)++;
        b->st->sched_skipped++;
    }
    if (next < 0)
        return -1;
    int in_sched = *pos < o->schedule_len;
    if (lead + 1 <= b->budget) {
        if (in_sched) {
            b->st->sched_loads++;
            return o->schedule[(*pos)++];
        }
        b->st->sched_fallback++;
        return pick_cell(b, 0);
    }
    if (in_sched && !b->st->sched_switches++) {
        b->st->switched_at_load = (int64_t)b->st->fetches;
        b->st->switch_reason = C5_SWITCH_BUDGET;
        b->st->switch_value = (double)lead;
    }
    b->st->shadow_loads++;
    return next;
}

/* When this board learns that board k has passed entry d: a link latency after it did, as the
 * exchanges reported it; UINT64_MAX: not known yet. */
static uint64_t known_passed(const c5_bd *b, int k, int64_t d)
{
    for (size_t i = 0; i < b->seen_n[k]; i++)
        if (b->seen_prog[k][i] >= d)
            return b->seen_t[k][i] + b->o->link->lookahead;
    return UINT64_MAX;
}

/* Several asynchronous boards following the plan across boards (the schedule of the boards'
 * pooled Cell Tree, docs/multi-board.md): an entry of this board's cells waits until every
 * entry of another board it depends on (o->sched_dep: whose loads hand rays on to its nodes)
 * is known to be passed there, a link latency after it was, or at most C5_PLAN_WAIT_FETCHES
 * fetch times of its cell: a board with no rays does not pass its entries, and the frame
 * differs from the one the plan was made on. C5_BD_WAIT: until b->wake. */
static int plan_next(c5_bd *b, int *pos)
{
    const c5_board_opts *o = b->o;
    const c5_board_link *l = o->link;
    uint64_t now = c5_bd_clock(b);
    while (*pos < o->schedule_len) {
        int c = o->schedule[*pos];
        if (l->owner[c] != l->self) {
            (*pos)++;
            continue;
        }
        uint64_t ready = now;
        for (int k = 0; k < l->boards && ready != UINT64_MAX; k++) {
            int d = o->sched_dep[(size_t)*pos * (size_t)l->boards + (size_t)k];
            if (d >= 0 && k != l->self) {
                uint64_t t = known_passed(b, k, d);
                ready = t > ready ? t : ready;
            }
        }
        if (b->wait_since == UINT64_MAX)
            b->wait_since = now;
        uint64_t limit = b->wait_since + C5_PLAN_WAIT_FETCHES * c5_bd_fetch_cycles(b, c);
        if (ready > now && now < limit) {
            b->wake = ready < limit ? ready : limit;
            b->st->sched_waits++;
            return C5_BD_WAIT;
        }
        b->wait_since = UINT64_MAX;
        int64_t at = (*pos)++;
        if (c5_bd_queued_in(b, c)) {
            b->cur_entry = at;
            b->st->sched_loads++;
            return c;
        }
        b->progress = at;
        b->progress_t = now;
        b->st->sched_skipped++;
    }
    return -3;
}

/* Which cell to load next, or -1 when every queue is empty. */
int c5_bd_schedule(c5_bd *b, int *sched_pos)
{
    const c5_board_opts *o = b->o;
    if (o->sched == C5_SCHED_EXTERNAL && o->sched_dep && o->link && o->link->exchange_async) {
        int c = plan_next(b, sched_pos);
        if (c != -3)
            return c;
        c = pick_cell(b, 0);
        b->st->sched_fallback += c >= 0;
        return c;
    }
    if (o->sched == C5_SCHED_EXTERNAL && b->sgroup[0] * b->sgroup[1] * b->sgroup[2] > 1) {
        for (;;) {
            int c = b->cur_group < 0 ? -1 : busiest_in_group(b, b->cur_group);
            if (c >= 0) {
                b->st->sched_loads++;
                return c;
            }
            if (*sched_pos >= o->schedule_len)
                break;
            b->cur_group = o->schedule[(*sched_pos)++];
            if (busiest_in_group(b, b->cur_group) < 0)
                b->st->sched_skipped++;
        }
        b->st->sched_fallback++;
    } else if (o->sched == C5_SCHED_EXTERNAL) {
        int c = b->certify ? certified_next(b, sched_pos) : -3;
        if (c != -3)
            return c;
        while (*sched_pos < o->schedule_len) {
            int c = o->schedule[(*sched_pos)++];
            if (b->q[c].n > b->q[c].head) {
                b->st->sched_loads++;
                return c;
            }
            b->st->sched_skipped++;
        }
        b->st->sched_fallback++; /* undone below when no queue holds a ray */
    }
    int best = pick_cell(b, o->sched == C5_SCHED_MINWORK);
    if (best < 0 && o->sched == C5_SCHED_EXTERNAL)
        b->st->sched_fallback--;
    return best;
}

