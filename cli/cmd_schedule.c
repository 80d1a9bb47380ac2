/* cube5 schedule: the Cell Tree across the frames of an animation against Max Work
 * (docs/cell-tree.md), per frame on stdout (text or --json). */
#include <jansson.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "board.h"
#include "camera.h"
#include "motion_cli.h"
#include "plan_deps.h"
#include "boards_cli.h"
#include "cli.h"
#include "dsp_cost.h"
#include "dsp_sched.h"
#include "progress.h"
#include "sched_report.h"

#define EXACT_STATES_DEFAULT 200000
#define EXACT_NODES_MAX 4096
#define FETCH_LOG_MAX 65536 /* fetches of a frame kept for the window rule's warm start */

typedef struct {
    const char *scene_arg;
    int cells[3], size[2], json, still;
    long frames, exact_states, tree_nodes, local_window, local_walk;
    int partial; /* --on-overflow partial */
    long group;  /* --tree-group G: the tree over groups of GxGxG cells; 0: auto (c5_dsp_next_group) */
    int rule;         /* --split: a c5_split_rule */
    c5_motion_args mv; /* --orbit, --jumps, --dolly */
    int stale_off;    /* --stale-check off */
    int own_trees;    /* --plan own: with several boards, each board follows its own tree's schedule */
    int tree_ram;     /* --tree-ram: TREE_RAM_AUTO (c5_dsp_tree_in_sdram), _ONCHIP or _SDRAM */
    c5_cli_volumes volumes;
    c5_boards_args bd;
} sched_args;

enum { TREE_RAM_AUTO, TREE_RAM_ONCHIP, TREE_RAM_SDRAM };

static int local_window_opt(const c5_opt *o, const char *v, void *field, c5_err *err)
{
    long *n = field;
    if (c5_cli_int(o->name, v, 0, 1000, n, err))
        return -1;
    if (*n > 0 && *n < 3)
        return c5_fail(err, "%s: %ld is too small for a window (0, or 3..1000)", o->name, *n);
    return 0;
}

static int group_opt(const c5_opt *o, const char *v, void *field, c5_err *err)
{
    if (!strcmp(v, "auto")) {
        *(long *)field = 0;
        return 0;
    }
    return c5_cli_int(o->name, v, 1, C5_CLI_MAX_CELLS, field, err);
}

/* The split rules' names, in c5_split_rule order from C5_SPLIT_MOST_LEAVES: --split, the
 * report's split_rule and its schedule_len keys. */
static const char *const rule_names[] = {"paper", "lookahead", "rollout", "bounded", "window", "subtree", NULL};
#define NRULES ((int)(sizeof rule_names / sizeof *rule_names) - 1)

static int split_opt(const c5_opt *o, const char *v, void *field, c5_err *err)
{
    return c5_opt_pick(o, v, rule_names, C5_SPLIT_MOST_LEAVES, field, err);
}

static int tree_ram_opt(const c5_opt *o, const char *v, void *field, c5_err *err)
{
    static const char *const names[] = {"auto", "onchip", "sdram", NULL}; /* TREE_RAM_* */
    return c5_opt_pick(o, v, names, TREE_RAM_AUTO, field, err);
}

static int overflow_opt(const c5_opt *o, const char *v, void *field, c5_err *err)
{
    static const char *const names[] = {"maxwork", "partial", NULL};
    return c5_opt_pick(o, v, names, 0, field, err);
}

static int check_opt(const c5_opt *o, const char *v, void *field, c5_err *err)
{
    static const char *const names[] = {"on", "off", NULL};
    return c5_opt_pick(o, v, names, 0, field, err);
}

static int plan_opt(const c5_opt *o, const char *v, void *field, c5_err *err)
{
    static const char *const names[] = {"pooled", "own", NULL};
    return c5_opt_pick(o, v, names, 0, field, err);
}

#define OFF(f) offsetof(sched_args, f)
static const c5_opt opts[] = {
    {"--cells", "N|NxMxK", c5_opt_cells, OFF(cells), 0, 0, 0,
     "split into NxNxN (or NxMxK) cells; default 2: memory holds 1/8"},
    {"--frames", "N", c5_opt_long, OFF(frames), 1, C5_MAX_FRAMES, 0,
     "frames (default: the camera path's, or 2 for a still camera, so that frame 1 follows frame 0's tree); a path "
     "is spread over N frames"},
    {"--still", NULL, c5_opt_flag, OFF(still), 0, 0, 0,
     "every frame from the path's first camera: the next frame repeats this one, so only the scheduling differs "
     "(the paper's Figure 6)"},
    {"--size", "N|WxH", c5_opt_size, OFF(size), 0, 0, 0, "image size instead of the scene's (N: NxN)"},
    {"--split", "R", split_opt, OFF(rule), 0, 0, 0,
     "rule of the schedule the board follows: window (default: the shortest of the paper's schedule, the subtree "
     "rule's and the frame's own fetches, shortened window by window within the DSP's budget of counted "
     "operations), paper (split peels take the cell with most leaf nodes), lookahead or rollout (ours), bounded "
     "(the rollout within that budget, else the paper's), or subtree (ours: forward, the cell whose ready nodes "
     "head the largest subtrees first); docs/cell-tree.md. The lengths of all are reported, with the DSP's "
     "operations per frame at 255 MIPS"},
    {"--exact-states", "N", c5_opt_long, OFF(exact_states), 0, 100000000, 0,
     "state budget of the exact optimum (default 200000; 0: not computed); when it gives up: the best proven bound "
     "and the best schedule found"},
    {"--local-window", "N", local_window_opt, OFF(local_window), 0, 0, 0,
     "the best schedule found is shortened by windows of 2N/3, then N loads solved exactly (default 45; 0, or "
     "3..1000; 0: not, the beam search's and the window rule's, much faster on 27-cell trees)"},
    {"--local-walk", "N", c5_opt_long, OFF(local_walk), 0, 100000, 0,
     "then N steps of the local walk (default 0: none; 0..100000; scripts/optimum-study.sh runs 500: minutes a "
     "27-cell tree)"},
    {"--tree-nodes", "N", c5_opt_long, OFF(tree_nodes), 1, C5_TREE_MAX_SLOTS, 0,
     "DSP RAM node slots, 1..8191 (default 8191: 96 KB of 12-byte nodes)"},
    {"--tree-ram", "auto|onchip|sdram", tree_ram_opt, OFF(tree_ram), 0, 0, 0,
     "where the DSP keeps the Cell Tree: the 96 KB on chip, or 16 MiB of its SDRAM (16-byte nodes; the packet "
     "carries the node's index among its cell's nodes; a scheduling budget of 10% of the frame's board time). auto "
     "(default): on chip up to 64 cells, in SDRAM beyond and after a frame whose tree overflowed the on-chip RAM. "
     "docs/cell-tree.md"},
    {"--tree-group", "G|auto", group_opt, OFF(group), 0, 0, 0,
     "the Cell Tree over groups of GxGxG cells; the next frame works off each scheduled group, Max Work within it. "
     "auto (default): over cells, groups doubled per axis after a frame whose tree overflowed the RAM it stays in"},
    {"--on-overflow", "maxwork|partial", overflow_opt, OFF(partial), 0, 0, 0,
     "a tree that outgrew the RAM: no schedule, the next frame runs Max Work (default), or the schedule of the part "
     "it holds, then Max Work"},
    {"--stale-check", "on|off", check_opt, OFF(stale_off), 0, 0, 0,
     "on (default): the board follows the schedule under its certificate (Max Work's shadow on the growing tree): "
     "never past Max Work plus the path's bank and one allowance; off: it follows the schedule to its end (the "
     "paper's board). docs/cell-tree.md, \"The certificate\""},
    {"--plan", "pooled|own", plan_opt, OFF(own_trees), 0, 0, 0,
     "with several boards: pooled (default): the boards pool their Cell Trees between frames, schedule the pooled "
     "tree as one board would, and each follows its own cells' entries, waiting for the entries of other boards "
     "it depends on; own: each board schedules its own tree. docs/multi-board.md"},
    {"--json", NULL, c5_opt_flag, OFF(json), 0, 0, 0, "one JSON object instead of the text"},
    {"--volume", "[I=]FILE", c5_opt_volume, OFF(volumes), 0, 0, 0, "replace volume I (default 0) by a raw or NRRD file"},
    {0},
};

const c5_cmd_spec c5_spec_schedule = {
    "schedule", "[SCENE|FILE.json]",
    "Renders each frame of a scene (default: 'default') on the board model twice: with the online Max Work "
    "scheduler, and as the board runs with the Cell Tree: following the schedule the DSP made from the previous "
    "frame's tree (Max Work in the first frame, and after an overflow of the DSP RAM). Per frame: rays, the tree's "
    "nodes and bytes, the cell fetches of each, the lower bound and the exact optimum of the frame's own tree (when "
    "the search fits its budget), the peels and the cost of building and scheduling. The two images of a frame must "
    "be the same bits; a difference is reported as an error. docs/cell-tree.md.\n\n"
    "With --boards N, each board schedules its own cells from its own Cell Tree; the tree columns are board 0's, "
    "\"boards\" lines (JSON \"multi_board\") add up every board's fetches and lower bounds.",
    {{opts, 0}, {c5_motion_opts, OFF(mv)}, {c5_boards_opts, OFF(bd)}, {c5_progress_opts, 0}},
};
#undef OFF

static int parse_args(int argc, char **argv, sched_args *a, c5_err *err)
{
    memset(a, 0, sizeof *a);
    a->scene_arg = "default";
    a->cells[0] = a->cells[1] = a->cells[2] = 2;
    a->rule = C5_SPLIT_WINDOW; /* within the DSP's budget; docs/cell-tree.md, "The window rule" */
    a->exact_states = EXACT_STATES_DEFAULT;
    a->local_window = C5_DSP_LOCAL_WINDOW;
    a->tree_nodes = C5_TREE_MAX_SLOTS;
    if (c5_opt_parse(&c5_spec_schedule, argc, argv, a, &a->scene_arg, err) != 0)
        return -1;
    if (a->still && a->mv.given)
        return c5_fail(err, "--still: a still camera cannot also move (--orbit, --jumps, --dolly)");
    return 0;
}

/* One frame's row. */
typedef struct {
    uint64_t rays, fetches_maxwork, fetches_celltree;
    const char *followed; /* what the Cell Tree run followed */
    c5_board_stats ct;    /* the Cell Tree run (the board as it runs) */
    double board_s_maxwork;
    c5_dsp_sched_result sch; /* the DSP's work on this frame's tree */
    int group;               /* cells a group of this frame's tree holds per axis (1: cells) */
    int sdram;               /* this frame's tree is in the DSP's SDRAM (cell_tree_sdram.h) */
    int *tparent, *tcell, tn; /* that tree as the DSP reads it, until the next frame's refinement */
    c5_schedule refined;     /* the previous frame's schedule, shortened during this frame (refine) */
    uint64_t refine_budget;  /* the DSP's idle operations in this frame */
    uint64_t budget_ops;     /* the DSP's scheduling budget after this frame (dsp_cost.h) */
    uint64_t demand_nodes, demand_slots; /* the tree with unbounded RAM (tree_demand.h) */
    int jump;                /* the camera motion cut to a new view at this frame */
    uint32_t *start;         /* [cells] rays queued per cell after the set-up (the ledger's start overlap) */
    c5_stale_plan plan;      /* the DSP's replay of this frame's tree for the next frame */
    int *dep;                /* several boards, the plan across boards: what each entry waits for */
    /* With --boards: both runs' per-board figures, and each board's tree's lower bound (-1:
     * its tree overflowed) and nodes. */
    c5_mb_stats *mb_mw, *mb_ct;
    int lower_bound[C5_MB_MAX_BOARDS], nodes[C5_MB_MAX_BOARDS];
} frame_row;

/* One render of the frame: the board, or every board (the summed counters into st). */
static int model(const sched_args *a, const c5_scene *s, const c5_supervol *sv, int f, const c5_board_opts *o,
                 const c5_board_out *keep, c5_image *img, c5_board_stats *st, c5_mb_stats *mb, c5_err *err)
{
    if (!a->bd.given)
        return c5_board_render_keep(s, sv, f, o, keep, img, st, err);
    if (c5_mb_render(s, sv, f, o, keep, &a->bd.mo, &a->bd.t, img, mb, err) != 0)
        return -1;
    *st = mb->sum;
    return 0;
}

/* The frame's figures of every board (after each board scheduled its own tree). */
static int gather_bounds(const sched_args *a, frame_row *r, c5_err *err)
{
    int mine[2] = {r->sch.overflow ? -1 : r->sch.lower_bound, r->sch.nodes}, all[2 * C5_MB_MAX_BOARDS];
    if (a->bd.t.allgather(a->bd.t.ctx, mine, sizeof mine, all, err) != 0)
        return -1;
    for (int k = 0; k < a->bd.t.size; k++) {
        r->lower_bound[k] = all[2 * k];
        r->nodes[k] = all[2 * k + 1];
    }
    return 0;
}

/* The boards' lower bound of the frame: the sum of their own trees' bounds, or with the plan
 * across boards the pooled tree's, which every board scheduled (-1: a tree overflowed). */
static long boards_bound(const sched_args *a, const frame_row *r)
{
    long bound = 0;
    for (int k = 0; k < a->bd.t.size; k++)
        bound = bound < 0 || r->lower_bound[k] < 0 ? -1 : bound + r->lower_bound[k];
    return a->own_trees || bound < 0 ? bound : r->lower_bound[0];
}

static json_t *boards_json(const sched_args *a, const frame_row *r)
{
    json_t *per = json_array();
    for (int k = 0; k < a->bd.t.size; k++)
        json_array_append_new(per, json_pack("{s:i, s:I, s:I, s:i, s:i}", "board", k, "fetches_maxwork",
                                             (json_int_t)r->mb_mw->board[k].fetches, "fetches_celltree",
                                             (json_int_t)r->mb_ct->board[k].fetches, "lower_bound", r->lower_bound[k],
                                             "nodes", r->nodes[k]));
    long bound = boards_bound(a, r);
    return json_pack("{s:s, s:o, s:o, s:o, s:o}", "plan", a->own_trees ? "own" : "pooled", "maxwork",
                     c5_cli_mb_json(r->mb_mw), "celltree", c5_cli_mb_json(r->mb_ct), "lower_bound_sum",
                     bound < 0 ? json_null() : json_integer(bound), "per_board", per);
}

static uint64_t rays_of(const c5_board_stats *st)
{
    uint64_t n = 0;
    for (int t = 0; t < C5_RAY_TYPES; t++)
        n += st->rays[t];
    return n;
}

static double reduction(uint64_t mw, uint64_t ct)
{
    return mw ? 100.0 * ((double)mw - (double)ct) / (double)mw : 0.0;
}

static const char *rule_name(c5_split_rule r)
{
    int k = (int)r - C5_SPLIT_MOST_LEAVES;
    return k >= 0 && k < NRULES ? rule_names[k] : rule_names[0];
}

/* What became of the exact search on a frame's tree. */
static const char *exact_status(const c5_dsp_sched_result *s, long exact_states)
{
    if (s->overflow)
        return "not computed (tree overflowed)";
    if (exact_states <= 0)
        return "not computed (--exact-states 0)";
    if (s->exact_skipped)
        return "not computed (more than 64 cells)";
    return s->optimum >= 0 ? "optimum" : "gave up (budget): lower_bound and best_known";
}

/* The DSP's operations of a frame (dsp_cost.h): building the tree during the frame (its
 * packets' tag decisions and node accesses), scheduling between frames (the chosen rule). */
static uint64_t dsp_ops_tree(const frame_row *r)
{
    if (r->ct.tree_sdram)
        return r->ct.tree_tags * C5_OPS_TAG + (r->ct.tree_reads + r->ct.tree_writes) * C5_OPS_SDRAM_NODE;
    return r->ct.tree_tags * C5_OPS_TAG + r->ct.tree_reads * C5_OPS_NODE_READ + r->ct.tree_writes * C5_OPS_NODE_WRITE;
}

/* Bytes of the frame's tree in its RAM. */
static uint64_t tree_bytes(const frame_row *r)
{
    return r->sdram ? r->ct.tree_sdram_bytes : (uint64_t)r->sch.slots * C5_CELL_TREE_NODE_BYTES;
}

static void dsp_json(json_t *o, const frame_row *r)
{
    const c5_dsp_sched_result *s = &r->sch;
    json_object_set_new(o, "dsp_ops_tree", json_integer((json_int_t)dsp_ops_tree(r)));
    json_object_set_new(o, "dsp_ops_schedule", json_integer((json_int_t)s->dsp_ops_schedule));
    json_object_set_new(o, "dsp_ops_schedule_parts",
                        json_pack("{s:I, s:I, s:I}", "export", (json_int_t)s->dsp_ops_export, "rule",
                                  (json_int_t)s->dsp_ops_rule, "writeback", (json_int_t)s->dsp_ops_writeback));
    json_object_set_new(o, "dsp_us_at_255mips",
                        json_pack("{s:f, s:f}", "tree", c5_dsp_us(dsp_ops_tree(r)), "schedule",
                                  c5_dsp_us(s->dsp_ops_schedule)));
    json_object_set_new(o, "dsp_budget_ops", json_integer((json_int_t)r->budget_ops));
    json_object_set_new(o, "dsp_within_budget", json_boolean(s->dsp_ops_schedule <= r->budget_ops));
    json_object_set_new(o, "bounded_gave_up", json_boolean(s->bounded_gave_up));
    json_object_set_new(o, "bounded_fell_back", json_boolean(s->bounded_fell_back));
    json_object_set_new(o, "window_warm", json_boolean(s->next.warm));
    json_object_set_new(o, "window_subtree", json_boolean(s->next.subtree));
    json_object_set_new(o, "refined", r->refined.len > 0 ? json_pack("{s:I, s:I, s:i}", "budget_ops",
                                                                      (json_int_t)r->refine_budget, "dsp_ops",
                                                                      (json_int_t)r->refined.dsp_ops, "len",
                                                                      r->refined.len)
                                                         : json_null());
}

/* The DSP's operations per frame, as text. */
static void dsp_text(const frame_row *rows, int frames)
{
    printf("  DSP at %.0f MIPS (dsp_cost.h), scheduling budget between frames %llu ops (%.0f us) for a tree on "
           "chip, %.0f%% of the frame's board time for a tree in SDRAM:\n",
           C5_DSP_MIPS, (unsigned long long)C5_DSP_SCHED_BUDGET_OPS, c5_dsp_us(C5_DSP_SCHED_BUDGET_OPS),
           100.0 * C5_DSP_SDRAM_FRAME_SHARE);
    for (int f = 0; f < frames; f++) {
        const frame_row *r = &rows[f];
        const c5_dsp_sched_result *s = &r->sch;
        uint64_t tree = dsp_ops_tree(r);
        printf("  frame %d: tree %s %llu ops (%.0f us, %.2f%% of the frame); schedule %llu ops (%.0f us: export %llu, "
               "rule %llu, write-back %llu)%s; bounded rule %d loads, window rule %d loads%s\n",
               f, r->sdram ? "in SDRAM" : "on chip", (unsigned long long)tree, c5_dsp_us(tree),
               r->ct.board_s > 0 ? 100.0 * c5_dsp_us(tree) * 1e-6 / r->ct.board_s : 0.0,
               (unsigned long long)s->dsp_ops_schedule, c5_dsp_us(s->dsp_ops_schedule),
               (unsigned long long)s->dsp_ops_export, (unsigned long long)s->dsp_ops_rule,
               (unsigned long long)s->dsp_ops_writeback,
               s->dsp_ops_schedule > r->budget_ops ? " OVER BUDGET" : "", s->len_bounded,
               s->len_window,
               s->bounded_fell_back ? " (followed rule: the paper's schedule)"
               : s->bounded_gave_up ? " (followed rule: stopped at the budget)"
                                    : "");
    }
}

/* Why the board stopped following the schedule, in words. */
static const char *switch_reason(const c5_board_stats *st, char *buf, size_t n)
{
    if (st->switch_reason == C5_SWITCH_BUDGET)
        snprintf(buf, n, "the next scheduled load would take the board %.0f loads past Max Work's shadow, its budget is %lld",
                 st->switch_value + 1, (long long)st->ledger_budget);
    else
        snprintf(buf, n, "none");
    return buf;
}

static json_t *row_json(int f, const frame_row *r, long exact_states)
{
    const c5_dsp_sched_result *s = &r->sch;
    json_t *o = json_object();
    json_object_set_new(o, "frame", json_integer(f));
    json_object_set_new(o, "jump", json_boolean(r->jump));
    json_object_set_new(o, "rays", json_integer((json_int_t)r->rays));
    json_object_set_new(o, "nodes", json_integer(s->nodes));
    json_object_set_new(o, "tree_slots", json_integer(s->slots));
    json_object_set_new(o, "tree_bytes", json_integer((json_int_t)tree_bytes(r)));
    json_object_set_new(o, "tree_ram", json_string(r->sdram ? "sdram" : "onchip"));
    /* in SDRAM: the most nodes one cell holds (the packet's index runs below 8,191) */
    json_object_set_new(o, "tree_cell_nodes_max",
                        r->sdram ? json_integer((json_int_t)r->ct.tree_cell_nodes_max) : json_null());
    json_object_set_new(o, "tree_overflow", json_boolean(s->overflow));
    json_object_set_new(o, "tree_group", json_integer(r->group));
    json_object_set_new(o, "tree_demand_nodes", json_integer((json_int_t)r->demand_nodes));
    /* over groups the instrument's generations are the groups' (a weaker bound); null */
    json_object_set_new(o, "lower_bound_demand",
                        r->group == 1 && r->ct.tree_demand_sum_maxgen
                            ? json_integer((json_int_t)r->ct.tree_demand_sum_maxgen)
                            : json_null());
    json_object_set_new(o, "tree_demand_bytes", json_integer((json_int_t)r->demand_slots * C5_CELL_TREE_NODE_BYTES));
    json_object_set_new(o, "fetches_maxwork", json_integer((json_int_t)r->fetches_maxwork));
    json_object_set_new(o, "fetches_celltree", json_integer((json_int_t)r->fetches_celltree));
    json_object_set_new(o, "reduction_pct", json_real(reduction(r->fetches_maxwork, r->fetches_celltree)));
    json_object_set_new(o, "followed", json_string(r->followed));
    json_object_set_new(o, "sched_loads", json_integer((json_int_t)r->ct.sched_loads));
    json_object_set_new(o, "sched_skipped", json_integer((json_int_t)r->ct.sched_skipped));
    json_object_set_new(o, "sched_fallback", json_integer((json_int_t)r->ct.sched_fallback));
    json_object_set_new(o, "sched_switches", json_integer((json_int_t)r->ct.sched_switches));
    json_object_set_new(o, "switched_at_load",
                        r->ct.sched_switches ? json_integer((json_int_t)r->ct.switched_at_load) : json_null());
    char why[160];
    json_object_set_new(o, "switch_reason", r->ct.sched_switches ? json_string(switch_reason(&r->ct, why, sizeof why)) : json_null());
    json_object_set_new(o, "start_overlap", r->ct.start_overlap >= 0 ? json_real(r->ct.start_overlap) : json_null());
    json_object_set_new(o, "certificate",
                        !r->ct.certified
                            ? json_null()
                            : json_pack("{s:o, s:b, s:I, s:I, s:I, s:b, s:I}", "budget",
                                        r->ct.identical ? json_null() : json_integer((json_int_t)r->ct.ledger_budget),
                                        "identical", r->ct.identical,
                                        "lead_max", (json_int_t)r->ct.lead_max, "shadow_loads",
                                        (json_int_t)r->ct.shadow_loads, "maxwork_fetches",
                                        (json_int_t)r->ct.shadow_steps, "broken", r->ct.shadow_broken, "dsp_ops",
                                        (json_int_t)r->ct.shadow_ops));
    const c5_stale_plan *p = &r->plan;
    json_object_set_new(o, "replay", p->valid ? json_pack("{s:i, s:i, s:I, s:i, s:I, s:I}", "maxwork_loads", p->maxwork_loads,
                                                          "schedule_loads", p->sched_loads, "rays", (json_int_t)p->rays, "lag_loads", p->lag_loads,
                                                          "dsp_ops", (json_int_t)p->ops, "bank", (json_int_t)p->bank)
                                              : json_null());
    json_object_set_new(o, "lower_bound", s->overflow ? json_null() : json_integer(s->lower_bound));
    json_object_set_new(o, "sum_maxgen", s->overflow ? json_null() : json_integer(s->sum_maxgen));
    json_object_set_new(o, "paper_bound", s->overflow ? json_null() : json_integer(s->paper_bound));
    json_object_set_new(o, "optimum", s->optimum >= 0 ? json_integer(s->optimum) : json_null());
    json_object_set_new(o, "exact", json_string(exact_status(s, exact_states)));
    json_object_set_new(o, "best_known", s->best_known > 0 ? json_integer(s->best_known) : json_null());
    /* 0: not run (overflow); null: gave up at the report's cap (more than 64 cells) */
    json_t *lens = json_object();
    int lv[NRULES] = {s->len_paper, s->len_lookahead, s->len_rollout, s->len_bounded, s->len_window, s->len_subtree};
    for (int k = 0; k < NRULES; k++)
        json_object_set_new(lens, rule_names[k], lv[k] >= 0 ? json_integer(lv[k]) : json_null());
    json_object_set_new(o, "schedule_len", lens);
    json_object_set_new(o, "peels", json_pack("{s:i, s:i}", "completion", s->peels_completion, "split", s->peels_split));
    json_object_set_new(o, "nodes_examined", json_integer((json_int_t)s->nodes_examined));
    json_object_set_new(o, "max_generation", json_integer(s->max_gen));
    json_object_set_new(o, "build", json_pack("{s:I, s:I, s:I, s:f}", "packets", (json_int_t)r->ct.tree_tags,
                                              "node_reads", (json_int_t)r->ct.tree_reads, "node_writes",
                                              (json_int_t)r->ct.tree_writes, "host_s", r->ct.tree_wall_s));
    json_object_set_new(o, "schedule_host_s", json_real(s->sched_wall_s));
    dsp_json(o, r);
    json_object_set_new(o, "exact_host_s", json_real(s->exact_wall_s));
    json_object_set_new(o, "board_s_maxwork", json_real(r->board_s_maxwork));
    json_object_set_new(o, "board_s_celltree", json_real(r->ct.board_s));
    return o;
}

static void print_json(const sched_args *a, const c5_scene *s, const frame_row *rows, int frames)
{
    json_t *o = json_object(), *arr = json_array();
    uint64_t mw = 0, ct = 0;
    for (int f = 0; f < frames; f++) {
        json_t *rj = row_json(f, &rows[f], a->exact_states);
        if (a->bd.given)
            json_object_set_new(rj, "multi_board", boards_json(a, &rows[f]));
        json_array_append_new(arr, rj);
        if (f > 0) {
            mw += rows[f].fetches_maxwork;
            ct += rows[f].fetches_celltree;
        }
    }
    json_object_set_new(o, "scene", json_string(s->name));
    json_object_set_new(o, "size", json_pack("[i, i]", s->render.width, s->render.height));
    json_object_set_new(o, "cells", json_integer(a->cells[0] * a->cells[1] * a->cells[2]));
    json_object_set_new(o, "cells_split", json_pack("[i, i, i]", a->cells[0], a->cells[1], a->cells[2]));
    json_object_set_new(o, "split_rule", json_string(rule_name(a->rule)));
    json_object_set_new(o, "still", json_boolean(a->still));
    const c5_motion *m = &a->mv.m;
    json_object_set_new(o, "motion", json_pack("{s:f, s:o, s:i, s:f, s:f}", "orbit_deg", m->orbit_deg, "jumps_seed",
                                               m->jumps ? json_integer((json_int_t)m->jump_seed) : json_null(),
                                               "jumps_every", m->jumps ? m->jump_every : 0, "jumps_prob",
                                               m->jumps ? m->jump_prob : 0.0, "dolly", m->dolly ? m->dolly : 1.0));
    json_object_set_new(o, "tree_capacity_nodes", json_integer(a->tree_nodes));
    json_object_set_new(o, "exact_states", json_integer(a->exact_states));
    json_object_set_new(o, "local_window", json_integer(a->local_window));
    json_object_set_new(o, "local_walk", json_integer(a->local_walk));
    json_object_set_new(o, "frames", arr);
    json_object_set_new(o, "scheduled_frames",
                        json_pack("{s:I, s:I, s:f}", "fetches_maxwork", (json_int_t)mw, "fetches_celltree",
                                  (json_int_t)ct, "reduction_pct", reduction(mw, ct)));
    json_object_set_new(o, "outputs", json_array()); /* schedule writes no file */
    char *text = json_dumps(o, JSON_COMPACT | JSON_REAL_PRECISION(9));
    puts(text);
    free(text);
    json_decref(o);
}

static void print_text(const char *label, const sched_args *a, const c5_scene *s, const frame_row *rows, int frames)
{
    printf("cube5 schedule: %s, %dx%d, %d cells (%dx%dx%d), %d frame(s), split rule %s\n", label, s->render.width,
           s->render.height, a->cells[0] * a->cells[1] * a->cells[2], a->cells[0], a->cells[1], a->cells[2], frames,
           rule_name(a->rule));
    printf("  fetches: Max Work vs the board following the previous frame's Cell Tree schedule;\n"
           "  of this frame's own tree: bound (proven), s3.4 (Section 3.4's formula, not a bound),\n"
           "  optimum (exact search; <=N: not proven, the best schedule found), schedule lengths\n"
           "  by rule paper/lookahead/rollout (bounded, window: below), peels\n");
    printf("%5s %8s %5s %6s %7s %8s %6s %5s %5s %7s %5s %5s %5s %9s %s\n", "frame", "rays", "nodes", "bytes",
           "maxwork", "celltree", "fewer", "bound", "s3.4", "optimum", "paper", "look", "roll", "peels c/s",
           "followed");
    uint64_t mw = 0, ct = 0;
    for (int f = 0; f < frames; f++) {
        const frame_row *r = &rows[f];
        const c5_dsp_sched_result *x = &r->sch;
        /* Of this frame's own tree: nothing to show when it overflowed. */
        char v[6][24];
        int vals[6] = {x->lower_bound, x->paper_bound, x->optimum, x->len_paper, x->len_lookahead, x->len_rollout};
        for (int k = 0; k < 6; k++)
            snprintf(v[k], sizeof v[k], x->overflow || vals[k] < 0 ? "-" : "%d", vals[k]);
        if (!x->overflow && x->optimum < 0 && x->best_known > 0) /* not found: the best known, as "<=N" */
            snprintf(v[2], sizeof v[2], "<=%d", x->best_known);
        char peels[24];
        snprintf(peels, sizeof peels, x->overflow ? "-" : "%d/%d", x->peels_completion, x->peels_split);
        printf("%5d %8llu %5d %6d %7llu %8llu %5.1f%% %5s %5s %7s %5s %5s %5s %9s %s%s\n", f,
               (unsigned long long)r->rays, x->nodes, (int)tree_bytes(r),
               (unsigned long long)r->fetches_maxwork, (unsigned long long)r->fetches_celltree,
               reduction(r->fetches_maxwork, r->fetches_celltree), v[0], v[1], v[2], v[3], v[4], v[5], peels,
               r->followed, !x->overflow ? ""
                            : r->sdram ? " (tree OVERFLOWED its SDRAM region: next frame runs Max Work)"
                            : a->partial ? " (tree OVERFLOWED the DSP RAM: next frame follows what it holds)"
                                         : " (tree OVERFLOWED the DSP RAM: next frame runs Max Work)");
        if (a->bd.given) {
            long bound = boards_bound(a, r);
            printf("%5s boards %d: frame %llu cycles with Max Work, %llu following the %s; %s %ld%s\n", "",
                   a->bd.t.size, (unsigned long long)r->mb_mw->frame_cycles,
                   (unsigned long long)r->mb_ct->frame_cycles,
                   a->own_trees ? "boards' own Cell Trees" : "plan across boards (the pooled Cell Tree)",
                   a->own_trees ? "sum of the boards' lower bounds" : "the pooled tree's lower bound", bound,
                   bound < 0 ? " (a tree overflowed)" : "");
        }
        if (r->sdram)
            printf("%5s this frame's tree is in the DSP's SDRAM\n", "");
        if (r->group > 1)
            printf("%5s this frame's tree is over groups of %dx%dx%d cells\n", "", r->group, r->group, r->group);
        if (r->ct.sched_switches) {
            char why[160];
            printf("%5s certificate: %llu loads taken from Max Work's shadow, the first at load %lld: %s\n", "",
                   (unsigned long long)r->ct.shadow_loads, (long long)r->ct.switched_at_load,
                   switch_reason(&r->ct, why, sizeof why));
        }
        if (r->jump)
            printf("%5s (the camera cut to a new view at this frame)\n", "");
        if (f > 0) {
            mw += r->fetches_maxwork;
            ct += r->fetches_celltree;
        }
    }
    for (int f = 0; f < frames; f++)
        if (rows[f].sch.len_lookahead < 0 || rows[f].sch.len_rollout < 0) {
            printf("  look/roll \"-\": over the report's cap of %llu nodes examined (more than 64 cells)\n",
                   (unsigned long long)C5_DSP_REPORT_MAX_EXAMINED);
            break;
        }
    for (int f = 0; f < frames; f++)
        if (rows[f].sch.exact_skipped) {
            printf("  optimum, best known and bounds beyond the sum of maxGen: not computed (more than 64 cells;\n"
                   "  the exact search works on 64-bit cell masks): bound = sum of maxGen\n");
            break;
        }
    if (frames > 1)
        printf("  frames 1..%d: %llu fetches with Max Work, %llu following the Cell Tree: %.1f%% fewer\n", frames - 1,
               (unsigned long long)mw, (unsigned long long)ct, reduction(mw, ct));
    double build = 0, sched = 0;
    uint64_t reads = 0, writes = 0, examined = 0;
    for (int f = 0; f < frames; f++) {
        build += rows[f].ct.tree_wall_s;
        sched += rows[f].sch.sched_wall_s;
        reads += rows[f].ct.tree_reads;
        writes += rows[f].ct.tree_writes;
        examined += rows[f].sch.nodes_examined;
    }
    dsp_text(rows, frames);
    printf("  cost: building %llu node reads, %llu writes, %.3f ms host; scheduling %llu nodes examined, %.3f ms "
           "host (all frames)\n",
           (unsigned long long)reads, (unsigned long long)writes, 1e3 * build, (unsigned long long)examined, 1e3 * sched);
}

static int same_bits(const c5_image *a, const c5_image *b)
{
    return a->w == b->w && a->h == b->h && !memcmp(a->rgb, b->rgb, sizeof(float) * 3 * (size_t)a->w * (size_t)a->h);
}

/* Why frame f runs Max Work when it does: there is no previous frame, the previous tree
 * overflowed the DSP RAM, or it was empty (no ray reached a cell: nothing to schedule). */
static const char *maxwork_reason(int f, const c5_dsp_sched_result *prev)
{
    if (f == 0 || !prev)
        return "maxwork (first frame)";
    return prev->overflow ? "maxwork (previous tree overflowed)" : "maxwork (previous tree empty)";
}

/* Frame f: the Max Work baseline, then the board as it runs (following the schedule the DSP
 * made from frame f-1's tree, `prev`, when there is one), then the DSP's work on this frame's
 * tree. */
/* The DSP's refinement during frame f of the schedule it follows (c5_dsp_refine), when its tree
 * is the previous frame's: a tree in SDRAM kept as the DSP read it, and the same camera. */
static int refine(const frame_row *pr, frame_row *row, c5_err *err)
{
    if (!pr || !pr->tn || pr->sch.next.len == 0 || row->ct.frame_key != pr->ct.frame_key || row->group != 1 ||
        pr->group != 1)
        return 0;
    double idle = row->ct.board_s * C5_DSP_MIPS * 1e6 -
                  (double)(dsp_ops_tree(row) + row->ct.node_count_ops + row->ct.shadow_ops);
    row->refine_budget = idle > 1e15 ? (uint64_t)1e15 : idle > 1 ? (uint64_t)idle : 1;
    c5_dep_tree dt = {pr->tn, pr->tparent, pr->tcell};
    return c5_dsp_refine(&dt, row->refine_budget, &pr->sch.next, &row->refined, err);
}

/* The DSP's schedule of the frame's tree (on chip, or in SDRAM within its share of the frame's
 * board time, going on from the refinement of the previous frame's when the tree is the same),
 * warm-started from the fetches of the run that built it. 0, or -1 with err. */
static int schedule_tree(const sched_args *a, const frame_row *pr, frame_row *row, c5_ctree *tree,
                         c5_sdram_tree *sdt, const int *log, int g, c5_err *err)
{
    c5_dsp_sched_opts so = {.report = c5_dsp_sched_report, .rule = a->rule, .all_rules = 1, .exact_states = a->exact_states, .partial = a->partial,
                            .exact_nodes = EXACT_NODES_MAX, .split = {a->cells[0], a->cells[1], a->cells[2]},
                            .local_window = a->local_window >= 3 ? (int)a->local_window : -1,
                            .walk_steps = (int)a->local_walk};
    if (log && row->ct.fetches <= FETCH_LOG_MAX) {
        so.warm = log;
        so.warm_len = (int)row->ct.fetches;
    }
    if (g > 1)
        memset(so.split, 0, sizeof so.split); /* the slab bound knows cells, not groups */
    row->demand_nodes = row->ct.tree_demand_nodes;
    row->demand_slots = row->ct.tree_demand_slots;
    if (sdt) {
        if (refine(pr, row, err) != 0)
            return -1;
        if (row->refined.len > 0) { /* the same tree: go on from the refinement */
            so.warm = row->refined.cells;
            so.warm_len = row->refined.len;
            so.resume = &row->refined.cursor;
        }
        /* The DSP's budget in SDRAM: a share of this frame's board time (dsp_cost.h). */
        so.rule_budget = c5_dsp_sdram_budget(row->ct.board_s, (sdt->slots + sdt->t.n) * C5_OPS_SDRAM_NODE);
        row->budget_ops = so.rule_budget + (sdt->slots + sdt->t.n) * C5_OPS_SDRAM_NODE;
        return c5_dsp_schedule_sdram(sdt, &so, &row->sch, err);
    }
    row->budget_ops = C5_DSP_SCHED_BUDGET_OPS;
    return c5_dsp_schedule(tree, &so, &row->sch, err);
}

/* Keeps the frame's tree in SDRAM as the DSP reads it, for the refinement during the next frame. */
static int keep_tree(const c5_sdram_tree *t, frame_row *row, c5_err *err)
{
    if (t->overflow || t->t.oom || t->t.n == 0)
        return 0;
    int n = (int)t->t.n;
    row->tparent = malloc(sizeof *row->tparent * (size_t)n);
    row->tcell = malloc(sizeof *row->tcell * (size_t)n);
    if (!row->tparent || !row->tcell)
        return c5_fail(err, "out of memory for the Cell Tree in SDRAM (%d nodes)", n);
    c5_sdram_tree_export(t, row->tparent, row->tcell);
    row->tn = n;
    return 0;
}

static void drop_tree(frame_row *row)
{
    free(row->tparent);
    free(row->tcell);
    row->tparent = row->tcell = NULL;
    row->tn = 0;
}

/* The plan across boards: the pooled tree's schedule (row->sch) and, for each entry, the last
 * entry of each other board it waits for (c5_plan_deps). */
static int plan_deps(const sched_args *a, const c5_ctree *pool, frame_row *row, c5_err *err)
{
    int nb = a->bd.t.size, len = row->sch.next.len, n = (int)pool->nodes, nn[3] = {a->cells[0], a->cells[1], a->cells[2]};
    int *par = malloc(sizeof *par * (size_t)(n ? n : 1)), *cel = malloc(sizeof *cel * (size_t)(n ? n : 1));
    uint32_t *ids = malloc(sizeof *ids * (size_t)(n ? n : 1));
    uint16_t *owner = malloc(sizeof *owner * (size_t)(nn[0] * nn[1] * nn[2]));
    row->dep = malloc(sizeof *row->dep * (size_t)len * (size_t)nb);
    int rc = !par || !cel || !ids || !owner || !row->dep ? c5_fail(err, "out of memory for the plan across boards")
                                                         : c5_mb_assign(a->bd.mo.assign ? a->bd.mo.assign : C5_ASSIGN_KD,
                                                                        nn, nb, owner, err);
    if (rc == 0) {
        c5_ctree_export(pool, par, cel, ids);
        c5_plan_deps(par, cel, n, row->sch.next.cells, len, owner, nb, row->dep);
    }
    free(par), free(cel), free(ids), free(owner);
    return rc;
}

static int run_frame(const sched_args *a, const c5_scene *s, const c5_supervol *sv, int f, const frame_row *pr,
                     c5_ctree *trees, frame_row *row, c5_progress *prog, c5_err *err)
{
    const c5_dsp_sched_result *prev = pr ? &pr->sch : NULL;
    const c5_stale_plan *prev_plan = pr ? &pr->plan : NULL;
    int prev_group = pr ? pr->group : 1;
    const uint32_t *prev_start = pr ? pr->start : NULL;
    c5_image mw_img = {0}, ct_img = {0};
    c5_board_stats mw;
    int g = row->group;
    c5_board_opts o = {.tree = &trees[0], .tree_group = {g, g, g}, .schedule_group = {prev_group, prev_group, prev_group},
                       .time_tree = 1}; /* the report's build host_s */
    c5_camera cam = c5_motion_camera(&s->camera, &a->mv.m, f);
    if (a->mv.given)
        o.camera = &cam;
    int ncells = a->cells[0] * a->cells[1] * a->cells[2];
    /* Packets tagged with each node of this frame's tree, for its replay (the run whose tree
     * is scheduled fills it last); only this frame's plan needs them. */
    uint32_t *node_rays = calloc(C5_TREE_SLOTS, sizeof *node_rays);
    if (!(row->start = calloc((size_t)ncells, sizeof *row->start)) || !node_rays) {
        free(node_rays);
        return c5_fail(err, "out of memory");
    }
    c5_board_out keep = {.start_counts = row->start, .node_rays = node_rays};
    memcpy(o.cells, a->cells, sizeof o.cells);
    c5_progress_frame pf = {prog, f, f};
    o.progress = c5_progress_board;
    o.progress_ctx = &pf;
    /* The fetches of the render whose tree the DSP schedules: a schedule of that tree, for the
     * window rule to start from (a tree over cells only: the log holds cells). */
    int *log = g > 1 ? NULL : malloc(sizeof *log * FETCH_LOG_MAX);
    keep.fetch_log = log;
    keep.fetch_log_cap = log ? FETCH_LOG_MAX : 0;
    c5_ctree_init(&trees[0], (uint32_t)a->tree_nodes);
    int rc = -1;
    /* The tree in the DSP's SDRAM: each run builds its own; the last run's is scheduled. */
    c5_sdram_tree *sdt = row->sdram ? malloc(sizeof *sdt) : NULL;
    if (row->sdram && (!sdt || c5_sdram_tree_init(sdt, 0) != 0)) {
        free(sdt);
        sdt = NULL;
        c5_fail(err, "out of memory for the Cell Tree in SDRAM");
        goto done;
    }
    o.sdram_tree = sdt;
    if (model(a, s, sv, f, &o, &keep, &mw_img, &mw, row->mb_mw, err) != 0)
        goto done;
    if (row->mb_ct)
        *row->mb_ct = *row->mb_mw;
    c5_ctree *tree = &trees[0];
    row->ct = mw;
    row->followed = maxwork_reason(f, prev);
    if (prev && prev->next.len > 0) {
        o.sched = C5_SCHED_EXTERNAL;
        o.schedule = prev->next.cells;
        o.schedule_len = prev->next.len;
        o.stale_check = a->stale_off ? -1 : 0;
        o.prev_start = prev_start;
        o.prev_start_len = prev_start ? ncells : 0;
        o.plan = prev_plan;
        o.sched_dep = pr ? pr->dep : NULL;
        keep.start_counts = NULL;
        o.tree = tree = &trees[1];
        c5_ctree_init(tree, (uint32_t)a->tree_nodes);
        if (sdt) {
            c5_sdram_tree_free(sdt);
            if (c5_sdram_tree_init(sdt, 0) != 0) {
                c5_fail(err, "out of memory for the Cell Tree in SDRAM");
                goto done;
            }
        }
        if (model(a, s, sv, f, &o, &keep, &ct_img, &row->ct, row->mb_ct, err) != 0)
            goto done;
        if (!same_bits(&mw_img, &ct_img)) {
            c5_fail(err, "frame %d: the image under the Cell Tree schedule differs from Max Work's (a model bug)", f);
            goto done;
        }
        row->followed = row->ct.sched_switches ? "celltree, with max work's shadow (certificate)"
                        : prev->overflow                        ? "partial celltree, then maxwork"
                        : row->ct.sched_fallback                ? "celltree, then maxwork"
                                                                : "celltree";
    }
    /* Several boards, the plan across boards: their pooled tree. A ray's cells do not depend on
     * the boards or the order of loads, so the tree the boards' DSPs pool between frames is the
     * tree one board builds of the frame: each rank builds it so (docs/multi-board.md). */
    static c5_ctree pool;
    /* on chip, and under an assignment known before the frame (the tree and load rules make the
     * next frame's from this one's traffic) */
    int pooled = a->bd.given && a->bd.t.size > 1 && !a->own_trees && g == 1 && !row->sdram &&
                 a->bd.mo.assign != C5_ASSIGN_TREE && a->bd.mo.assign != C5_ASSIGN_LOAD;
    if (pooled) {
        c5_board_opts o1 = o;
        o1.sched = 0;
        o1.schedule = NULL;
        o1.schedule_len = 0;
        o1.plan = NULL;
        o1.sched_dep = NULL;
        o1.link = NULL;
        o1.sdram_tree = NULL;
        o1.progress = NULL;
        o1.tree = &pool;
        c5_ctree_init(&pool, (uint32_t)a->tree_nodes);
        c5_image im1;
        c5_board_stats st1;
        if (c5_board_render_keep(s, sv, f, &o1, &keep, &im1, &st1, err) != 0)
            goto done;
        c5_image_free(&im1);
        tree = &pool;
    }
    row->jump = c5_motion_jumps_at(&a->mv.m, f);
    row->rays = rays_of(&mw);
    row->fetches_maxwork = mw.fetches;
    row->fetches_celltree = row->ct.fetches;
    row->board_s_maxwork = mw.board_s;
    rc = schedule_tree(a, pr, row, tree, sdt, log, g, err);
    if (rc == 0 && a->bd.given)
        rc = gather_bounds(a, row, err);
    const int *lag = o.sched == C5_SCHED_EXTERNAL && prev_group == 1 ? o.schedule : NULL;
    int lag_len = o.sched == C5_SCHED_EXTERNAL ? o.schedule_len : 0;
    if (rc == 0 && sdt)
        rc = keep_tree(sdt, row, err);
    if (rc == 0 && g == 1)
        rc = sdt ? c5_stale_plan_make_sdram(sdt, row->sch.next.cells, row->sch.next.len, lag, lag_len, &row->plan, err)
                 : c5_stale_plan_make(tree, node_rays, row->sch.next.cells, row->sch.next.len, lag, lag_len,
                                      &row->plan, err);
    if (rc == 0)
        c5_stale_plan_settle(&row->plan, prev_plan, row->ct.fetches, row->ct.frame_key);
    if (rc == 0 && pooled && !pool.overflow && row->sch.next.len > 0) /* what each entry waits for */
        rc = plan_deps(a, &pool, row, err);
done:
    if (sdt)
        c5_sdram_tree_free(sdt);
    free(sdt);
    free(log);
    free(node_rays);
    c5_image_free(&mw_img);
    c5_image_free(&ct_img);
    return rc;
}

int c5_cmd_schedule(int argc, char **argv)
{
    if (c5_opt_help(&c5_spec_schedule, argc, argv))
        return 0;
    sched_args a;
    c5_err err;
    static c5_scene s;
    static c5_ctree trees[2];
    char label[1100];
    c5_supervol sv = {0};
    frame_row *rows = NULL;
    int frames = 0, rc = C5_EXIT_INPUT;
    if (parse_args(argc, argv, &a, &err) != 0 ||
        c5_cli_scene_setup(a.scene_arg, &a.volumes, a.size[0], a.size[1], &s, label, sizeof label, &err) != 0)
        goto fail;
    int moving = a.mv.given;
    if (a.still || moving) { /* the path's first camera: the still view, or the motion's base */
        s.camera = c5_scene_camera_at(&s, 0);
        s.path.n_keys = 0;
    }
    frames = a.frames ? (int)a.frames : moving ? 8 : c5_scene_frames(&s) > 1 ? c5_scene_frames(&s) : 2;
    if (moving && c5_motion_check_frames(&a.mv, &s, frames, label, &err) != 0)
        goto fail;
    if (s.path.n_keys > 0)
        s.path.frames = frames;
    if (c5_scene_check_path(&s, label, &err) != 0)
        goto fail;
    if (c5_cli_model_grid(&s, a.cells, label, &sv, &err) != 0)
        goto fail;
    if (a.bd.loopback) {
        c5_fail(&err, "--loopback: schedule runs its boards as MPI ranks ('mpirun -np N cube5 schedule ... --boards N'); "
                      "--loopback is for render and compare");
        goto fail;
    }
    if (c5_boards_begin(&a.bd, &err) != 0)
        goto fail;
    rc = C5_EXIT_RUNTIME;
    rows = calloc((size_t)frames, sizeof *rows);
    for (int f = 0; rows && a.bd.given && f < frames; f++)
        if (!(rows[f].mb_mw = calloc(2, sizeof *rows[f].mb_mw)))
            break;
        else
            rows[f].mb_ct = rows[f].mb_mw + 1;
    if (!rows || (a.bd.given && !rows[frames - 1].mb_mw)) {
        c5_fail(&err, "out of memory for %d frames", frames);
        goto fail;
    }
    c5_progress prog;
    c5_progress_begin(&prog, "schedule", frames);
    if (!c5_boards_leader(&a.bd))
        prog.mode = 0;
    for (int f = 0; f < frames; f++) {
        int ncells = a.cells[0] * a.cells[1] * a.cells[2];
        const frame_row *pr = f ? &rows[f - 1] : NULL;
        rows[f].sdram = a.tree_ram == TREE_RAM_SDRAM   ? 1
                        : a.tree_ram == TREE_RAM_ONCHIP ? 0
                                                        : c5_dsp_tree_in_sdram(ncells, f, pr && pr->sdram, pr && pr->sch.overflow);
        /* Groups grow after an overflow of the RAM the tree stays in (auto: of the SDRAM). */
        int grow = pr && pr->sch.overflow && (pr->sdram || a.tree_ram == TREE_RAM_ONCHIP);
        rows[f].group = a.group ? (int)a.group : f == 0 ? 1 : c5_dsp_next_group(pr->group, grow, a.cells);
        int rf = run_frame(&a, &s, &sv, f, pr, trees, &rows[f], &prog, &err);
        if (f)
            drop_tree(&rows[f - 1]);
        if (rf != 0) {
            c5_progress_end(&prog);
            if (a.bd.mpi) /* the other boards wait in a collective: end them all */
                c5_mpi_fail(&a.bd.t, err.msg, C5_EXIT_RUNTIME);
            goto fail;
        }
        c5_progress_step(&prog, f + 1, "frame %d: %s", f, rows[f].followed);
    }
    c5_progress_end(&prog);
    if (!c5_boards_leader(&a.bd))
        ;
    else if (a.json)
        print_json(&a, &s, rows, frames);
    else
        print_text(label, &a, &s, rows, frames);
    rc = 0;
fail:
    if (rows)
        for (int f = 0; f < frames; f++)
            c5_dsp_sched_free(&rows[f].sch), free(rows[f].start), c5_stale_plan_free(&rows[f].plan), free(rows[f].dep),
                free(rows[f].mb_mw), drop_tree(&rows[f]), c5_schedule_free(&rows[f].refined);
    free(rows);
    c5_supervol_free(&sv);
    c5_boards_end(&a.bd);
    if (rc)
        fprintf(stderr, "cube5: error: %s\n", err.msg);
    return rc;
}
