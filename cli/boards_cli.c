/* --boards and friends; the per-board report. */
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "boards_cli.h"
#include "cli.h"
#include "mb_loopback.h"

static int assign_opt(const c5_opt *o, const char *v, void *field, c5_err *err)
{
    c5_mb_opts *mo = field;
    if (!(mo->assign = c5_assign_parse(v)))
        return c5_fail(err, "%s: expected kd, slab, mod, tree or load, got '%s'", o->name, v);
    return 0;
}

static int mode_opt(const c5_opt *o, const char *v, void *field, c5_err *err)
{
    c5_mb_opts *mo = field;
    if (!(mo->mode = c5_mb_mode_parse(v)))
        return c5_fail(err, "%s: expected async or rounds, got '%s'", o->name, v);
    return 0;
}

static int link_opt(const c5_opt *o, const char *v, void *field, c5_err *err)
{
    if (!(*(const c5_link_preset **)field = c5_link_preset_find(v)))
        return c5_fail(err, "%s: expected 1gbe, 10gbe or pcie4x16, got '%s'", o->name, v);
    return 0;
}

static int link_bw_opt(const c5_opt *o, const char *v, void *field, c5_err *err)
{
    double x;
    if (c5_cli_double(o->name, v, 0.001, 1e9, &x, err))
        return -1;
    ((c5_mb_opts *)field)->link_bw = x * 1e6;
    return 0;
}

static int link_latency_opt(const c5_opt *o, const char *v, void *field, c5_err *err)
{
    double x;
    if (c5_cli_double(o->name, v, 0, 1e9, &x, err))
        return -1;
    ((c5_mb_opts *)field)->link_latency_s = x > 0 ? x * 1e-6 : -1;
    return 0;
}

#define GIVEN C5_SEEN(c5_boards_args, given)
const c5_opt c5_boards_opts[] = {
    {"--boards", "N", c5_opt_long, offsetof(c5_boards_args, boards), 1, C5_MB_MAX_BOARDS, GIVEN,
     "rtl only: N boards share the super volume, one MPI rank each: run as 'mpirun -np N cube5 ... --boards N' "
     "(docs/multi-board.md); the image is the same bits for any N"},
    {"--assign", "R", assign_opt, offsetof(c5_boards_args, mo), 0, 0, GIVEN,
     "how cells go to boards: kd (default, a k-d split), slab, mod (scattered), tree (from the previous frame's "
     "rays between cells; kd in frame 0), or load (a k-d split balancing the board cycles each cell took in the "
     "previous frame; kd in frame 0)"},
    {"--exchange", "M", mode_opt, offsetof(c5_boards_args, mo), 0, 0, GIVEN,
     "how rays move between boards: async (default: each board on its own clock, a packet sent as soon as it is "
     "handed on, the frame's end found by credit recovery) or rounds (bulk-synchronous: work off every queue, "
     "then all exchange)"},
    {"--loopback", NULL, c5_opt_flag, offsetof(c5_boards_args, loopback), 0, 0, GIVEN,
     "render, compare: run the N boards as threads of this one process instead of MPI ranks (no mpirun; the same "
     "figures and image as N ranks)"},
    {"--link", "NAME", link_opt, offsetof(c5_boards_args, link), 0, 0, GIVEN,
     "the link between boards: 1gbe (default: 125 MB/s, 50 us), 10gbe (1250 MB/s, 15 us) or pcie4x16 (31500 MB/s, "
     "1 us); --link-bw and --link-latency set either part"},
    {"--link-bw", "MB/S", link_bw_opt, offsetof(c5_boards_args, mo), 0, 0, GIVEN,
     "inter-board link bandwidth each way per board (default 125: Gigabit Ethernet)"},
    {"--link-latency", "US", link_latency_opt, offsetof(c5_boards_args, mo), 0, 0, GIVEN,
     "inter-board latency in us (default 50): a packet's time through the switch, or a round's exchange"},
    {0},
};
#undef GIVEN

/* One board: the collectives of a job of one. */
static int one_alltoall(void *ctx, const uint8_t (*out)[C5_PACKET_BYTES], const uint16_t *dest, size_t n_out,
                        const uint8_t (**in)[C5_PACKET_BYTES], size_t *n_in, c5_err *err)
{
    (void)ctx, (void)out, (void)dest;
    *in = NULL;
    *n_in = 0;
    return n_out ? c5_fail(err, "one board sent packets to another") : 0;
}

static int one_allgather(void *ctx, const void *mine, size_t bytes, void *all, c5_err *err)
{
    (void)ctx, (void)err;
    memcpy(all, mine, bytes);
    return 0;
}

static int one_sum(void *ctx, uint64_t *v, size_t n, c5_err *err)
{
    (void)ctx, (void)v, (void)n, (void)err;
    return 0;
}

int c5_boards_begin(c5_boards_args *b, c5_err *err)
{
    if (b->boards < 1)
        b->boards = 1;
    b->mo.history = &b->hist;
    if (b->link && b->mo.link_bw == 0)
        b->mo.link_bw = b->link->bw;
    if (b->link && b->mo.link_latency_s == 0)
        b->mo.link_latency_s = b->link->latency_s;
    if (b->loopback && b->boards > 1) {
        if (!(b->hist_lb = calloc((size_t)b->boards, sizeof *b->hist_lb)))
            return c5_fail(err, "out of memory for %ld boards", b->boards);
        b->t = (c5_mb_transport){NULL, 0, (int)b->boards, one_alltoall, one_allgather, one_sum};
        return 0;
    }
    if (b->boards == 1) {
        b->t = (c5_mb_transport){NULL, 0, 1, one_alltoall, one_allgather, one_sum};
        return 0;
    }
    if (c5_mpi_begin((int)b->boards, &b->t, err) != 0)
        return -1;
    b->mpi = 1;
    return 0;
}

int c5_boards_leader(const c5_boards_args *b) { return !b->mpi || b->t.rank == 0; }

int c5_boards_render(const c5_boards_args *b, const c5_scene *s, const c5_supervol *sv, int f, const c5_board_opts *o,
                     const c5_board_out *keep, c5_image *img, c5_mb_stats *ms, c5_err *err)
{
    if (b->hist_lb)
        return c5_mb_render_loopback(s, sv, f, o, keep, &b->mo, (int)b->boards, b->hist_lb, img, ms, err);
    return c5_mb_render(s, sv, f, o, keep, &b->mo, &b->t, img, ms, err);
}

void c5_boards_end(c5_boards_args *b)
{
    for (long k = 0; b->hist_lb && k < b->boards; k++)
        c5_mb_history_free(&b->hist_lb[k]);
    free(b->hist_lb);
    b->hist_lb = NULL;
    c5_mb_history_free(&b->hist);
    if (b->mpi)
        c5_mpi_end();
    b->mpi = 0;
}

json_t *c5_cli_mb_json(const c5_mb_stats *ms)
{
    json_t *per = json_array();
    for (int k = 0; k < ms->boards; k++) {
        const c5_mb_board *b = &ms->board[k];
        json_t *o = json_object();
        const struct {
            const char *key;
            uint64_t v;
        } n[] = {
            {"board", (uint64_t)k},           {"cells", (uint64_t)b->cells},
            {"fetches", b->fetches},          {"fetch_bytes", b->fetch_bytes},
            {"packets_sent", b->packets_sent}, {"packets_received", b->packets_received},
            {"bytes_sent", b->packets_sent * C5_PACKET_BYTES},
            {"bytes_received", b->packets_received * C5_PACKET_BYTES},
            {"busy_cycles", b->busy_cycles},  {"link_cycles", b->link_cycles},
            {"idle_cycles", b->idle_cycles},  {"rays_processed", b->rays_processed},
            {"resident_loads", b->resident_loads},
        };
        for (size_t i = 0; i < sizeof n / sizeof n[0]; i++)
            json_object_set_new(o, n[i].key, json_integer((json_int_t)n[i].v));
        json_array_append_new(per, o);
    }
    return json_pack("{s:i, s:s, s:s, s:f, s:f, s:I, s:I, s:I, s:f, s:I, s:I, s:f, s:o}", "boards", ms->boards,
                     "exchange", c5_mb_mode_name(ms->mode), "assign", c5_assign_name(ms->assign), "link_bw",
                     ms->link_bw, "link_latency_s", ms->link_latency_s, "rounds", (json_int_t)ms->rounds,
                     "sim_exchanges", (json_int_t)ms->exchanges, "frame_cycles", (json_int_t)ms->frame_cycles, "frame_s",
                     ms->frame_s, "link_packets", (json_int_t)ms->link_packets, "link_bytes",
                     (json_int_t)ms->link_bytes, "balance", ms->balance, "per_board", per);
}

void c5_cli_mb_print(const c5_mb_stats *ms)
{
    if (ms->mode == C5_MB_ROUNDS)
        printf("  boards   %d (%s assignment, rounds), frame %llu cycles = %.6f s at 100 MHz (the slowest board's), "
               "%llu round(s)\n", ms->boards, c5_assign_name(ms->assign), (unsigned long long)ms->frame_cycles,
               ms->frame_s, (unsigned long long)ms->rounds);
    else
        printf("  boards   %d (%s assignment, async), frame %llu cycles = %.6f s at 100 MHz (the last board's "
               "end and its detection)\n", ms->boards, c5_assign_name(ms->assign),
               (unsigned long long)ms->frame_cycles, ms->frame_s);
    printf("  link     %.0f MB/s, %.0f us latency; %llu packets = %llu bytes between boards; balance %.3f\n",
           ms->link_bw / 1e6, ms->link_latency_s * 1e6, (unsigned long long)ms->link_packets,
           (unsigned long long)ms->link_bytes, ms->balance);
    printf("  %-6s %6s %8s %12s %10s %10s %12s %12s %12s\n", "board", "cells", "fetches", "rays", "sent", "received",
           "busy cyc", "link cyc", "idle cyc");
    for (int k = 0; k < ms->boards; k++) {
        const c5_mb_board *b = &ms->board[k];
        printf("  %-6d %6d %8llu %12llu %10llu %10llu %12llu %12llu %12llu\n", k, b->cells,
               (unsigned long long)b->fetches, (unsigned long long)b->rays_processed,
               (unsigned long long)b->packets_sent, (unsigned long long)b->packets_received,
               (unsigned long long)b->busy_cycles, (unsigned long long)b->link_cycles,
               (unsigned long long)b->idle_cycles);
    }
}
