/* cube5 render: one scene through cref or the board model, a summary on stdout (text or --json). */
#include <jansson.h>
#include <zlib.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "board.h"
#include "boards_cli.h"
#include "motion_cli.h"
#include "cli.h"
#include "cref.h"
#include "frame_vcd.h"
#include "progress.h"

typedef struct {
    const char *scene_arg, *out;
    long threads, frames;
    int size[2], json;
    c5_cli_volumes volumes;
    int rtl;                 /* --model rtl */
    int cells[3], have_cells;
    c5_queue_key key;
    int have_key;
    double host_mbs, host_ms; /* --host-bw, --host-latency; 0: the model's defaults */
    int have_host;
    c5_boards_args bd;       /* --boards and the link */
    c5_motion_args mv;       /* --orbit, --jumps, --dolly */
    const char *vcd;         /* --vcd FILE */
    long vcd_cycles, vcd_from;
    int have_vcd_window;     /* --vcd-cycles or --vcd-from given */
} render_args;

#define VCD_CYCLES_DEFAULT 1000000

static int model_opt(const c5_opt *o, const char *v, void *field, c5_err *err)
{
    static const char *const names[] = {"cref", "rtl", NULL};
    return c5_opt_pick(o, v, names, 0, field, err);
}

#define SEEN(f) C5_SEEN(render_args, f)
static const c5_opt opts[] = {
    {"-o", "OUT", c5_opt_str, offsetof(render_args, out), 0, 0, 0,
     "write the image: .png (8-bit, clamped) or .exr (float); with several frames, OUT_0000.png, OUT_0001.png, ..."},
    {"--threads", "N", c5_opt_long, offsetof(render_args, threads), 1, 256, 0,
     "host threads (default: one per CPU; with --boards, one a board); the image, and the board model's every "
     "counter and cycle, are the same for any N"},
    {"--frames", "N", c5_opt_long, offsetof(render_args, frames), 1, C5_MAX_FRAMES, 0,
     "frames along the scene's camera path (default: the scene's, or 8 with a camera motion)"},
    {"--size", "N|WxH", c5_opt_size, offsetof(render_args, size), 0, 0, 0, "image size instead of the scene's (N: NxN)"},
    {"--volume", "[I=]FILE", c5_opt_volume, offsetof(render_args, volumes), 0, 0, 0,
     "replace volume I (default 0) by a raw or NRRD file"},
    {"--model", "cref|rtl", model_opt, offsetof(render_args, rtl), 0, 0, 0,
     "cref (default), the double-precision reference renderer, or rtl: the board model (rtl_model/board.h), which "
     "also reports board cycles, fetches and the stages that ran"},
    {"--cells", "N|NxMxK", c5_opt_cells, offsetof(render_args, cells), 0, 0, SEEN(have_cells),
     "rtl only: split the grid into NxNxN (or NxMxK) cells (default 1, or the fewest that keep a cell within 256 "
     "voxels a side)"},
    {"--queue-key", "morton|fifo", c5_opt_queue_key, offsetof(render_args, key), 0, 0, SEEN(have_key),
     "rtl only: order of the ray queue (default morton)"},
    {"--host-bw", "MB/S", c5_opt_double, offsetof(render_args, host_mbs), 0.001, 1e6, SEEN(have_host),
     "rtl only: host/disk -> RDRAM bandwidth of a cell fetch (default 132)"},
    {"--host-latency", "MS", c5_opt_double, offsetof(render_args, host_ms), 0, 1e5, SEEN(have_host),
     "rtl only: latency of a cell fetch in ms (default 1)"},
    {"--vcd", "FILE", c5_opt_str, offsetof(render_args, vcd), 0, 0, 0,
     "rtl only, one frame, one board: the waveform of the frame's cycle-level parts, scopes ray_queue (the eDRAM "
     "sorter, ports of fpga/rtl/ray_queue.vhd) and ray_bus (packets between processor and DSP), on the "
     "testbenches' 10 ns clock, to load beside GHDL's --vcd in GTKWave (docs/vectors.md)"},
    /* 10^9 cycles is 10 s of the board: far beyond a frame, and the times stay within 64 bits in fs. */
    {"--vcd-cycles", "N", c5_opt_long, offsetof(render_args, vcd_cycles), 1, 1000000000L, SEEN(have_vcd_window),
     "the sorter's cycles in FILE (default 1000000); a longer frame is cut there (said on stderr and in FILE's "
     "header)"},
    {"--vcd-from", "C", c5_opt_long, offsetof(render_args, vcd_from), 0, 1000000000L, SEEN(have_vcd_window),
     "FILE starts at the sorter's cycle C (default 0)"},
    {"--json", NULL, c5_opt_flag, offsetof(render_args, json), 0, 0, 0,
     "print one JSON object instead of the text summary; each frame has \"crc32\", a CRC-32 of its float RGB "
     "pixels, and with rtl \"board\", the model's counters"},
    {0},
};
#undef SEEN

const c5_cmd_spec c5_spec_render = {
    "render", "[SCENE|FILE.json]",
    "Renders a built-in scene (default: 'default'; see 'cube5 scenes') or a scene file with cref, the "
    "double-precision reference renderer, or with the bit-accurate board model.",
    {{opts, 0}, {c5_motion_opts, offsetof(render_args, mv)}, {c5_boards_opts, offsetof(render_args, bd)},
     {c5_progress_opts, 0}},
};

static int parse_args(int argc, char **argv, render_args *a, c5_err *err)
{
    memset(a, 0, sizeof *a);
    a->scene_arg = "default";
    a->cells[0] = a->cells[1] = a->cells[2] = 0; /* the automatic split */
    a->key = C5_KEY_MORTON;
    a->host_ms = -1;
    a->vcd_cycles = VCD_CYCLES_DEFAULT;
    if (c5_opt_parse(&c5_spec_render, argc, argv, a, &a->scene_arg, err) != 0)
        return -1;
    /* Options of the other model are refused rather than ignored: a run that silently did
     * not do what was asked is worse than an error. */
    if (!a->rtl && (a->have_cells || a->have_key || a->have_host || a->bd.given))
        return c5_fail(err, "%s: only with --model rtl",
                       a->have_cells ? "--cells" : a->have_key ? "--queue-key" : a->have_host ? "--host-bw/--host-latency"
                       : "--boards/--assign/--link-bw/--link-latency");
    if (a->have_vcd_window && !a->vcd)
        return c5_fail(err, "--vcd-cycles/--vcd-from: only with --vcd FILE");
    if (a->vcd && !a->rtl)
        return c5_fail(err, "--vcd: only with --model rtl (the waveform is of the board model's parts)");
    if (a->vcd && a->bd.given)
        return c5_fail(err, "--vcd: one board only (the waveform is of one board's parts)");
    if (a->bd.given && a->threads)
        return c5_fail(err, "--threads: not with --boards (each board is a thread or a process of its own)");
    return 0;
}

static void add_stats(c5_cref_stats *sum, const c5_cref_stats *f)
{
    for (int t = 0; t < C5_RAY_TYPES; t++)
        sum->rays[t] += f->rays[t];
    for (int e = 0; e < C5_END_KINDS; e++)
        sum->ends[e] += f->ends[e];
    sum->samples += f->samples;
    sum->wall_s += f->wall_s;
}

/* The board's totals over the frames: counters add, queue_max and the Cell Tree's size are
 * the largest frame's, the stages are those of any frame and the cell count is the split's. */
static void add_board(c5_board_stats *sum, const c5_board_stats *f)
{
    sum->cycles += f->cycles;
    sum->cycles_process += f->cycles_process;
    sum->cycles_fetch += f->cycles_fetch;
    sum->board_s += f->board_s;
    sum->fetches += f->fetches;
    sum->fetch_bytes += f->fetch_bytes;
    sum->bus_packets += f->bus_packets;
    sum->spills += f->spills;
    sum->queue_pops += f->queue_pops;
    sum->queue_max = f->queue_max > sum->queue_max ? f->queue_max : sum->queue_max;
    sum->cache_hits += f->cache_hits;
    sum->cache_misses += f->cache_misses;
    sum->saturations += f->saturations;
    sum->samples_leaped += f->samples_leaped;
    sum->tree_nodes = f->tree_nodes > sum->tree_nodes ? f->tree_nodes : sum->tree_nodes;
    sum->tree_slots = f->tree_slots > sum->tree_slots ? f->tree_slots : sum->tree_slots;
    sum->tree_overflow |= f->tree_overflow;
#define C5_MAX_INTO(x) sum->x = f->x > sum->x ? f->x : sum->x
    C5_MAX_INTO(tree_demand_nodes);
    C5_MAX_INTO(tree_demand_slots);
    C5_MAX_INTO(tree_demand_slots6);
    C5_MAX_INTO(tree_demand_sum_maxgen);
#undef C5_MAX_INTO
    sum->tree_tags += f->tree_tags;
    sum->tree_reads += f->tree_reads;
    sum->tree_writes += f->tree_writes;
    sum->tree_wall_s += f->tree_wall_s;
    sum->stages.gradients |= f->stages.gradients;
    sum->stages.shadow |= f->stages.shadow;
    sum->stages.reflect |= f->stages.reflect;
    sum->stages.refract |= f->stages.refract;
    sum->stages.scheduling |= f->stages.scheduling;
    sum->cells = f->cells;
    sum->wall_s += f->wall_s;
    sum->helper_runs += f->helper_runs;
    sum->helper_wakes += f->helper_wakes;
}

/* The part of the board's statistics that cref also reports, so both models print the same
 * rays/samples/ends/wall_s keys. */
static c5_cref_stats board_base(const c5_board_stats *b)
{
    c5_cref_stats st = {0};
    memcpy(st.rays, b->rays, sizeof st.rays);
    memcpy(st.ends, b->ends, sizeof st.ends);
    st.samples = b->samples;
    st.wall_s = b->wall_s;
    return st;
}

static json_t *stats_json(const c5_cref_stats *st)
{
    json_t *rays = json_object(), *ends = json_object();
    for (int t = 0; t < C5_RAY_TYPES; t++)
        json_object_set_new(rays, c5_ray_type_name(t), json_integer((json_int_t)st->rays[t]));
    for (int e = 0; e < C5_END_KINDS; e++)
        json_object_set_new(ends, c5_end_kind_name(e), json_integer((json_int_t)st->ends[e]));
    return json_pack("{s:o, s:I, s:o, s:f}", "rays", rays, "samples", (json_int_t)st->samples, "ends", ends,
                     "wall_s", st->wall_s);
}

static void print_board(const render_args *a, const c5_board_stats *b)
{
    char stages[128];
    c5_cli_stages_text(&b->stages, stages, sizeof stages);
    printf("  stages   %s\n", stages);
    printf("  board    %llu cycles (process %llu, fetch stall %llu), %.6f s at 100 MHz\n",
           (unsigned long long)b->cycles, (unsigned long long)b->cycles_process, (unsigned long long)b->cycles_fetch,
           b->board_s);
    printf("  cells    %d (%dx%dx%d), %llu fetch(es), %llu bytes\n", b->cells, a->cells[0], a->cells[1], a->cells[2],
           (unsigned long long)b->fetches, (unsigned long long)b->fetch_bytes);
    printf("  queue    %s key, %llu pops, max %u, %llu spills, %llu bus packets\n", c5_cli_queue_key_name(a->key),
           (unsigned long long)b->queue_pops, (unsigned)b->queue_max, (unsigned long long)b->spills,
           (unsigned long long)b->bus_packets);
    printf("  cache    %llu hits, %llu misses\n", (unsigned long long)b->cache_hits,
           (unsigned long long)b->cache_misses);
    printf("  leaped   %llu sample positions (empty blocks and cells)\n", (unsigned long long)b->samples_leaped);
    printf("  saturate %llu datapath result(s) clamped\n", (unsigned long long)b->saturations);
    printf("  tree     %u Cell Tree nodes (%u slots of 12 bytes)%s, %llu packets tagged, %llu node reads, "
           "%llu writes\n", (unsigned)b->tree_nodes, (unsigned)b->tree_slots,
           b->tree_overflow ? ", OVERFLOWED the 96 KB DSP RAM" : "", (unsigned long long)b->tree_tags,
           (unsigned long long)b->tree_reads, (unsigned long long)b->tree_writes);
}

/* The memory budget the grid was built under (C5_MEM_BUDGET, read when the grid was built:
 * valid by then). */
static size_t mem_budget(void)
{
    size_t budget = 0;
    c5_err ignored;
    c5_mem_budget(&budget, &ignored);
    return budget;
}

static void print_text(const char *label, const c5_scene *s, const c5_supervol *sv, int frames, int threads,
                       const render_args *a, const c5_cref_stats *st, const c5_board_stats *board, const json_t *outputs)
{
    printf("cube5 render: %s, %dx%d, %d frame(s), ", label, s->render.width, s->render.height, frames);
    printf("%s, %d thread(s)\n", a->rtl ? "rtl (bit-accurate board model)" : "cref (double)", threads);
    if (c5_supervol_empty(sv)) {
        printf("  volume   none\n");
    } else {
        for (int i = 0; i < sv->n_sources; i++)
            printf("  volume   %s\n", sv->source_label[i]);
        printf("  grid     %zux%zux%zu voxels, spacing %g %g %g (%s%s), step %g\n", sv->dims[0], sv->dims[1],
               sv->dims[2], sv->spacing.x, sv->spacing.y, sv->spacing.z, sv->spacing_source,
               s->grid.size > 0 ? ", scaled to grid.size" : "", c5_render_step(s, sv));
        if (sv->store) /* the reason a render is slower than its size suggests */
            printf("  memory   out of core: the grid (%.1f MiB) is above the memory budget (C5_MEM_BUDGET, %.1f "
                   "MiB); voxels read through a brick cache (docs/out-of-core.md)\n",
                   (double)sv->dims[0] * (double)sv->dims[1] * (double)sv->dims[2] / 1048576.0,
                   (double)mem_budget() / 1048576.0);
    }
    printf("  scene    %d surface(s), %d light(s), max %d bounce(s)\n", s->n_surfaces, s->n_lights,
           s->render.max_bounces);
    printf("  rays     eye %llu, shadow %llu, reflect %llu, refract %llu\n", (unsigned long long)st->rays[0],
           (unsigned long long)st->rays[1], (unsigned long long)st->rays[2], (unsigned long long)st->rays[3]);
    printf("  samples  %llu\n  ends    ", (unsigned long long)st->samples);
    for (int e = 0; e < C5_END_KINDS; e++)
        printf(" %s %llu%s", c5_end_kind_name(e), (unsigned long long)st->ends[e], e + 1 < C5_END_KINDS ? "," : "\n");
    if (board)
        print_board(a, board);
    printf("  time     %.3f s%s\n", st->wall_s, board ? " (host)" : "");
    /* The files written: each one, or with many frames the first and the last. */
    size_t n = json_array_size(outputs);
    if (n == 0)
        printf("  image    not written (give -o OUT)\n");
    else if (n <= 4)
        for (size_t i = 0; i < n; i++)
            printf("  image    %s\n", json_string_value(json_array_get(outputs, i)));
    else
        printf("  images   %zu files, %s ... %s\n", n, json_string_value(json_array_get(outputs, 0)),
               json_string_value(json_array_get(outputs, n - 1)));
}

/* One frame through the chosen model: the image, the cref-shaped statistics and, for rtl,
 * the board's. */
static int render_at(const render_args *a, const c5_scene *s, const c5_supervol *sv, int f, c5_image *img,
                     c5_cref_stats *st, c5_board_stats *board, c5_mb_stats *mb, c5_progress *prog, const c5_taps *taps,
                     c5_err *err);

static int render_frame(const render_args *a, const c5_scene *s, const c5_supervol *sv, int f, c5_image *img,
                        c5_cref_stats *st, c5_board_stats *board, c5_mb_stats *mb, c5_progress *prog,
                        const c5_taps *taps, c5_err *err)
{
    if (!a->mv.given)
        return render_at(a, s, sv, f, img, st, board, mb, prog, taps, err);
    /* a camera motion: the scene with frame f's camera (a shallow copy: it shares the volumes) */
    c5_scene *moved = malloc(sizeof *moved);
    if (!moved)
        return c5_fail(err, "out of memory");
    *moved = *s;
    moved->camera = c5_motion_camera(&s->camera, &a->mv.m, f);
    moved->path.n_keys = 0;
    int rc = render_at(a, moved, sv, f, img, st, board, mb, prog, taps, err);
    free(moved);
    return rc;
}

/* The board model's host threads: one a board with --boards (each a thread or process of its
 * own), else --threads or one per CPU. */
static int model_threads(const render_args *a) { return a->bd.given ? 1 : c5_cref_thread_count((int)a->threads); }

static int render_at(const render_args *a, const c5_scene *s, const c5_supervol *sv, int f, c5_image *img,
                     c5_cref_stats *st, c5_board_stats *board, c5_mb_stats *mb, c5_progress *prog, const c5_taps *taps,
                     c5_err *err)
{
    if (!a->rtl) {
        c5_progress_frame pf = {prog, f, f};
        c5_cref_opts opts = {.threads = (int)a->threads, .progress = c5_progress_cref, .progress_ctx = &pf};
        return c5_cref_render(s, sv, f, &opts, img, st, err);
    }
    c5_board_opts opts = {.key = a->key, .host_bw = a->host_mbs * 1e6};
    /* -1: not given (the model's default); 0 given: explicitly no latency. */
    opts.host_latency_s = a->host_ms < 0 ? 0 : a->host_ms == 0 ? -1 : a->host_ms * 1e-3;
    memcpy(opts.cells, a->cells, sizeof opts.cells);
    opts.taps = taps;
    opts.threads = model_threads(a);
    c5_progress_frame pf = {prog, f, f};
    opts.progress = c5_boards_leader(&a->bd) ? c5_progress_board : NULL;
    opts.progress_ctx = &pf;
    if (a->bd.given) {
        if (c5_boards_render(&a->bd, s, sv, f, &opts, NULL, img, mb, err) != 0)
            return -1;
        *board = mb->sum;
    } else if (c5_board_render(s, sv, f, &opts, img, board, err) != 0) {
        return -1;
    }
    *st = board_base(board);
    return 0;
}

/* The run before its first frame, in the order that refuses early: options, scene, frames,
 * outputs, grid, boards, the waveform's file. 0, or -1 with err set. */
static int setup(int argc, char **argv, render_args *a, c5_scene *s, char *label, size_t label_len, c5_supervol *sv,
                 c5_frame_vcd **wave, c5_err *err)
{
    *wave = NULL;
    if (parse_args(argc, argv, a, err) != 0 ||
        c5_cli_scene_setup(a->scene_arg, &a->volumes, a->size[0], a->size[1], s, label, label_len, err) != 0)
        return -1;
    if (a->mv.given) { /* the motion from the path's first camera; render_frame sets each frame's */
        int n = a->frames ? (int)a->frames : 8;
        if (c5_motion_check_frames(&a->mv, s, n, label, err) != 0)
            return -1;
        s->path.n_keys = 1;
        s->path.keys[0] = s->camera;
        s->path.frames = n;
    } else if (a->frames) {
        s->path.frames = (int)a->frames;
        if (s->path.n_keys == 0 && a->frames > 1)
            return c5_fail(err, "--frames: the scene has no camera_path (or give a camera motion: --orbit, --jumps, "
                                "--dolly)");
        if (c5_scene_check_path(s, label, err) != 0)
            return -1;
    }
    int frames = c5_scene_frames(s);
    if (a->out && c5_cli_check_scene_image_out(a->out, frames, a->scene_arg, s, err) != 0)
        return -1;
    if (a->vcd && frames != 1)
        return c5_fail(err, "--vcd: the waveform is of one frame; the scene has several (give --frames 1)");
    if (a->out && a->vcd && c5_cli_check_distinct_frames(a->out, frames, "-o", a->vcd, "--vcd", err) != 0)
        return -1;
    /* opened while the grid is read or generated; not with --boards, whose ranks but the
     * first never write an image and are not known yet (MPI starts below) */
    if (a->out && !a->bd.given)
        c5_image_preload();
    if (a->rtl ? c5_cli_model_grid(s, a->cells, label, sv, err) != 0 : c5_cli_grid(s, label, sv, err) != 0)
        return -1;
    if (a->rtl && c5_boards_begin(&a->bd, err) != 0)
        return -1;
    if (a->vcd) {
        char about[1400];
        snprintf(about, sizeof about,
                 "%s, %dx%d, cells %dx%dx%d, queue key %s: the ray queue's cycles %ld to %ld of the frame "
                 "(--vcd-from, --vcd-cycles; a longer frame is cut there) and the ray bus's packets among them",
                 label, s->render.width, s->render.height, a->cells[0], a->cells[1], a->cells[2],
                 c5_cli_queue_key_name(a->key), a->vcd_from, a->vcd_from + a->vcd_cycles - 1);
        if (!(*wave = c5_frame_vcd_open(a->vcd, (uint64_t)a->vcd_from, (uint64_t)a->vcd_cycles, about, err)))
            return -1;
    }
    return 0;
}

/* What the frames of a run add up to. */
typedef struct {
    c5_mb_stats *mb, *mb_total; /* a frame's, the run's (with --boards) */
    c5_cref_stats total;
    c5_board_stats board_total;
    json_t *per_frame, *outputs;
    c5_frame_vcd_stats ws;      /* the waveform's (with --vcd) */
} render_run;

/* Every frame: rendered, added up, written (board 0 writes). 0, or C5_EXIT_RUNTIME with err. */
static int run_frames(const render_args *a, const c5_scene *s, const c5_supervol *sv, c5_frame_vcd *wave, int lead,
                      render_run *r, c5_err *err)
{
    int frames = c5_scene_frames(s), rc = 0;
    c5_image_preload_wait(); /* not beside the frames: their wall_s is theirs alone */
    c5_progress prog;
    c5_progress_begin(&prog, "render", frames);
    if (!lead)
        prog.mode = 0; /* board 0 reports */
    for (int f = 0; f < frames && rc == 0; f++) {
        c5_image img;
        c5_cref_stats st;
        c5_board_stats bst;
        if (!r->mb || render_frame(a, s, sv, f, &img, &st, &bst, r->mb, &prog, wave ? c5_frame_vcd_taps(wave) : NULL,
                                   err) != 0) {
            if (!r->mb)
                *err = (c5_err){"out of memory"};
            if (a->bd.mpi) /* the other boards wait in a collective: end them all */
                c5_mpi_fail(&a->bd.t, err->msg, C5_EXIT_RUNTIME);
            rc = C5_EXIT_RUNTIME;
            break;
        }
        add_stats(&r->total, &st);
        json_t *fj = stats_json(&st);
        if (a->rtl) {
            add_board(&r->board_total, &bst);
            json_object_set_new(fj, "board", c5_cli_board_json(&bst));
            if (a->bd.given) {
                c5_mb_add(r->mb_total, r->mb);
                json_object_set_new(fj, "multi_board", c5_cli_mb_json(r->mb));
            }
        }
        /* CRC-32 of the frame's float RGB bytes: a bit-exact fingerprint of the image. */
        uLong crc = crc32(0L, (const Bytef *)img.rgb, (uInt)(sizeof(float) * 3 * (size_t)img.w * img.h));
        json_object_set_new(fj, "crc32", json_sprintf("%08lx", (unsigned long)crc));
        json_array_append_new(r->per_frame, fj);
        if (a->out && lead) {
            char path[2048];
            c5_cli_frame_path(a->out, f, frames, path, sizeof path);
            if (c5_image_write(path, &img, err) != 0)
                rc = C5_EXIT_RUNTIME;
            else
                json_array_append_new(r->outputs, json_string(path));
        }
        c5_image_free(&img);
        if (rc == 0)
            c5_progress_step(&prog, f + 1, "frame %d%s%s", f, a->out ? ": " : "",
                             a->out ? json_string_value(json_array_get(r->outputs, (size_t)f)) : "");
    }
    c5_progress_end(&prog);
    return rc;
}

/* The waveform put in place (rc 0) or dropped (a failed frame has none: the file is as it
 * was), and its extent on stderr. The run's rc, or C5_EXIT_RUNTIME with err. */
static int close_wave(const render_args *a, c5_frame_vcd *wave, int rc, c5_frame_vcd_stats *ws, c5_err *err)
{
    if (rc != 0) {
        c5_frame_vcd_abort(wave);
        return rc;
    }
    if (c5_frame_vcd_close(wave, ws, err) != 0)
        return C5_EXIT_RUNTIME;
    uint64_t last = ws->written ? (uint64_t)a->vcd_from + ws->written - 1 : 0;
    if (ws->written)
        fprintf(stderr, "cube5: %s: the ray queue's cycles %ld to %llu of the frame's %llu", a->vcd, a->vcd_from,
                (unsigned long long)last, (unsigned long long)ws->cycles);
    else
        fprintf(stderr, "cube5: %s: none of the frame's %llu ray queue cycles (--vcd-from %ld)", a->vcd,
                (unsigned long long)ws->cycles, a->vcd_from);
    fprintf(stderr, "%s; ray bus: %llu packets to the DSP, %llu from it in the frame\n",
            ws->cut ? " (cut: --vcd-cycles)" : "", (unsigned long long)ws->to_dsp, (unsigned long long)ws->from_dsp);
    return 0;
}

/* The run as one JSON object on stdout (takes r's per-frame and outputs arrays). */
static void print_json(const render_args *a, const c5_scene *s, const c5_supervol *sv, int threads, render_run *r)
{
    json_t *o = stats_json(&r->total);
    const char *model = a->rtl ? "rtl" : "cref";
    json_object_set_new(o, "renderer", json_string(model));
    json_object_set_new(o, "model", json_string(model));
    json_object_set_new(o, "scene", json_string(s->name));
    json_object_set_new(o, "width", json_integer(s->render.width));
    json_object_set_new(o, "height", json_integer(s->render.height));
    if (a->rtl) {
        const c5_frame_vcd_stats *ws = &r->ws;
        json_object_set_new(o, "cells_split", json_pack("[i, i, i]", a->cells[0], a->cells[1], a->cells[2]));
        json_object_set_new(o, "queue_key", json_string(c5_cli_queue_key_name(a->key)));
        json_object_set_new(o, "board", c5_cli_board_json(a->bd.given ? &r->mb_total->sum : &r->board_total));
        if (a->bd.given)
            json_object_set_new(o, "multi_board", c5_cli_mb_json(r->mb_total));
        if (a->vcd)
            json_object_set_new(o, "waveform",
                                json_pack("{s:s, s:I, s:I, s:I, s:b, s:I, s:I}", "file", a->vcd, "from",
                                          (json_int_t)a->vcd_from, "cycles_written", (json_int_t)ws->written,
                                          "cycles_frame", (json_int_t)ws->cycles, "cut", ws->cut, "bus_to_dsp",
                                          (json_int_t)ws->to_dsp, "bus_from_dsp", (json_int_t)ws->from_dsp));
    }
    json_object_set_new(o, "threads", json_integer(threads));
    if (!c5_supervol_empty(sv))
        json_object_set_new(o, "grid", json_pack("{s:[I, I, I], s:[f, f, f], s:s, s:b, s:I}", "dims",
                                                 (json_int_t)sv->dims[0], (json_int_t)sv->dims[1],
                                                 (json_int_t)sv->dims[2], "spacing", sv->spacing.x, sv->spacing.y,
                                                 sv->spacing.z, "spacing_from", sv->spacing_source, "out_of_core",
                                                 sv->store != NULL, "mem_budget", (json_int_t)mem_budget()));
    json_object_set_new(o, "frames", r->per_frame);
    json_object_set_new(o, "outputs", r->outputs);
    r->per_frame = r->outputs = NULL;
    char *text = json_dumps(o, JSON_COMPACT | JSON_REAL_PRECISION(9));
    puts(text);
    free(text);
    json_decref(o);
}

int c5_cmd_render(int argc, char **argv)
{
    if (c5_opt_help(&c5_spec_render, argc, argv))
        return 0;
    render_args a;
    c5_err err;
    static c5_scene s;
    char label[1100];
    c5_supervol sv = {0};
    c5_frame_vcd *wave;
    if (setup(argc, argv, &a, &s, label, sizeof label, &sv, &wave, &err) != 0) {
        c5_image_preload_wait();
        c5_supervol_free(&sv);
        fprintf(stderr, "cube5: error: %s\n", err.msg);
        return C5_EXIT_INPUT;
    }
    int lead = c5_boards_leader(&a.bd);
    render_run r = {.per_frame = json_array(), .outputs = json_array()};
    if ((r.mb = calloc(2, sizeof *r.mb)) != NULL)
        r.mb_total = r.mb + 1;
    int rc = run_frames(&a, &s, &sv, wave, lead, &r, &err);
    if (wave)
        rc = close_wave(&a, wave, rc, &r.ws, &err);
    if (rc == 0 && lead) {
        int threads = a.rtl ? model_threads(&a) : c5_cref_thread_count((int)a.threads);
        if (a.json) {
            print_json(&a, &s, &sv, threads, &r);
        } else {
            print_text(label, &s, &sv, c5_scene_frames(&s), threads, &a, &r.total,
                       a.rtl ? (a.bd.given ? &r.mb_total->sum : &r.board_total) : NULL, r.outputs);
            if (a.bd.given)
                c5_cli_mb_print(r.mb_total);
        }
    }
    free(r.mb);
    c5_boards_end(&a.bd);
    json_decref(r.per_frame);
    json_decref(r.outputs);
    c5_supervol_free(&sv);
    if (rc != 0)
        fprintf(stderr, "cube5: error: %s\n", err.msg);
    return rc;
}
