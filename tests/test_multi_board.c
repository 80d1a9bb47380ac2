/* Several boards on one super volume (rtl_model/multi_board.h), over the in-process loopback
 * transport (mb_loopback.h): the assignment rules, the image bit-identical to one board's for
 * any number of boards, any assignment and either exchange (rounds, async), every ray ending
 * exactly once across the boards, the packets and the modelled link.
 * tests/mpi_test.sh runs the same over real MPI ranks. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "board.h"
#include "harness.h"
#include "mb_loopback.h"
#include "multi_board.h"
#include "scene_load.h"

typedef struct {
    c5_scene s;
    c5_supervol sv;
} loaded;

static int same_image(const c5_image *a, const c5_image *b)
{
    return a->w == b->w && a->h == b->h && !memcmp(a->rgb, b->rgb, sizeof(float) * 3 * (size_t)a->w * a->h);
}

/* The loopback render, its error printed. */
static int mb_render_hist(const c5_scene *s, const c5_supervol *sv, int frame, const c5_board_opts *o,
                          const c5_mb_opts *mo, int boards, c5_mb_history *hist, c5_image *img, c5_mb_stats *ms)
{
    c5_err err;
    int rc = c5_mb_render_loopback(s, sv, frame, o, NULL, mo, boards, hist, img, ms, &err);
    if (rc != 0)
        fprintf(stderr, "loopback: %s\n", err.msg);
    return rc;
}

static int mb_render(const c5_scene *s, const c5_supervol *sv, int frame, const c5_board_opts *o,
                     const c5_mb_opts *mo, int boards, c5_image *img, c5_mb_stats *ms)
{
    return mb_render_hist(s, sv, frame, o, mo, boards, NULL, img, ms);
}

/* Every ray created on any board ends exactly once on some board. */
static int conserved(const c5_board_stats *st)
{
    uint64_t made = 0, ended = 0;
    for (int t = 0; t < C5_RAY_TYPES; t++)
        made += st->rays[t];
    for (int e = C5_END_OPACITY; e <= C5_END_BLOCKED; e++)
        ended += st->ends[e];
    return made == ended && made > 0;
}

TEST(mb_assign_every_rule_owns_every_cell)
{
    int splits[][3] = {{1, 1, 1}, {2, 2, 2}, {4, 4, 4}, {3, 1, 2}, {8, 2, 1}, {5, 7, 3}};
    c5_assign_rule rules[] = {C5_ASSIGN_SLAB, C5_ASSIGN_KD, C5_ASSIGN_MOD};
    for (size_t i = 0; i < sizeof splits / sizeof splits[0]; i++)
        for (int r = 0; r < 3; r++)
            for (int nb = 1; nb <= 9; nb++) {
                int *n = splits[i], count = n[0] * n[1] * n[2];
                uint16_t owner[512];
                int per[16] = {0};
                c5_err err;
                CHECK(c5_mb_assign(rules[r], n, nb, owner, &err) == 0);
                for (int c = 0; c < count; c++) {
                    CHECK(owner[c] < nb);
                    per[owner[c]]++;
                }
                int lo = count, hi = 0;
                for (int k = 0; k < nb; k++) {
                    lo = per[k] < lo ? per[k] : lo;
                    hi = per[k] > hi ? per[k] : hi;
                }
                if (count >= nb)
                    CHECK_MSG(lo >= 1, "%s %dx%dx%d, %d boards: a board owns no cell", c5_assign_name(rules[r]),
                              n[0], n[1], n[2], nb);
                /* slabs and scattering share cells out within one; the k-d split's halves
                 * round on each cut */
                if (rules[r] != C5_ASSIGN_KD)
                    CHECK_MSG(hi - lo <= 1, "%s %dx%dx%d, %d boards: %d..%d cells", c5_assign_name(rules[r]), n[0],
                              n[1], n[2], nb, lo, hi);
            }
    /* Slabs are contiguous along the longest axis: 8x2x1 over 2 boards splits x. */
    uint16_t owner[16];
    c5_err err;
    CHECK(c5_mb_assign(C5_ASSIGN_SLAB, (int[3]){8, 2, 1}, 2, owner, &err) == 0);
    for (int c = 0; c < 16; c++)
        CHECK_INT(owner[c], (c % 8) / 4);
    CHECK(c5_mb_assign(C5_ASSIGN_KD, (int[3]){2, 2, 2}, 0, owner, &err) != 0);
    CHECK(c5_mb_assign(C5_ASSIGN_KD, (int[3]){2, 2, 2}, C5_MB_MAX_BOARDS + 1, owner, &err) != 0);
}

/* The image is bit-identical to one board's and every ray ends once, for 2, 3, 4 and 8 boards
 * and every assignment; packets sent are packets received; the modelled frame is no shorter
 * than any board's work. */
TEST(mb_image_identical_and_rays_conserved_for_any_boards)
{
    const char *scenes[] = {"brain_mirrors", "clouds_lake"};
    c5_assign_rule rules[] = {C5_ASSIGN_SLAB, C5_ASSIGN_KD, C5_ASSIGN_MOD};
    int boards[] = {2, 3, 4, 8};
    for (int si = 0; si < 2; si++) {
        loaded l;
        CHECK(c5t_load_scene(scenes[si], 40, &l.s, &l.sv) == 0);
        c5_board_opts o = {.cells = {4, 4, 4}};
        c5_image ref;
        c5_board_stats one;
        c5_err err;
        CHECK(c5_board_render(&l.s, &l.sv, 0, &o, &ref, &one, &err) == 0);
        for (int r = 0; r < 6; r++)
            for (size_t bi = 0; bi < sizeof boards / sizeof boards[0]; bi++) {
                c5_mb_mode mode = r < 3 ? C5_MB_ROUNDS : C5_MB_ASYNC;
                c5_mb_opts mo = {.mode = mode, .assign = rules[r % 3]};
                c5_image img;
                c5_mb_stats ms;
                CHECK(mb_render(&l.s, &l.sv, 0, &o, &mo, boards[bi], &img, &ms) == 0);
                char rn[32];
                snprintf(rn, sizeof rn, "%s %s", c5_assign_name(rules[r % 3]), c5_mb_mode_name(mode));
                CHECK_MSG(same_image(&ref, &img), "%s %s %d boards: image differs", scenes[si], rn, boards[bi]);
                CHECK_MSG(conserved(&ms.sum), "%s %s %d boards: rays not conserved", scenes[si], rn, boards[bi]);
                for (int t = 0; t < C5_RAY_TYPES; t++)
                    CHECK_INT(ms.sum.rays[t], one.rays[t]);
                for (int e = 0; e < C5_END_KINDS; e++)
                    CHECK_INT(ms.sum.ends[e], one.ends[e]);
                CHECK_INT(ms.sum.samples + ms.sum.samples_leaped, one.samples + one.samples_leaped);
                CHECK_INT(ms.sum.saturations, one.saturations);
                uint64_t sent = 0, received = 0, most = 0;
                int cells = 0;
                for (int k = 0; k < boards[bi]; k++) {
                    sent += ms.board[k].packets_sent;
                    received += ms.board[k].packets_received;
                    cells += ms.board[k].cells;
                    most = ms.board[k].busy_cycles > most ? ms.board[k].busy_cycles : most;
                    if (mode == C5_MB_ROUNDS)
                        CHECK(ms.board[k].busy_cycles + ms.board[k].link_cycles <= ms.frame_cycles);
                    else /* the port works beside the board */
                        CHECK(ms.board[k].busy_cycles + ms.board[k].idle_cycles == ms.frame_cycles);
                }
                CHECK_INT(sent, received);
                CHECK_INT(sent, ms.link_packets);
                CHECK_INT(ms.sum.link_sent, sent);
                CHECK_INT(ms.sum.link_received, received);
                CHECK_INT(ms.link_bytes, sent * C5_PACKET_BYTES);
                CHECK_INT(cells, 64);
                CHECK_MSG(sent > 0, "%s %s %d boards: no ray crossed a board", scenes[si], rn, boards[bi]);
                CHECK(ms.frame_cycles > most && ms.balance > 0 && ms.balance <= 1);
                if (mode == C5_MB_ROUNDS) { /* one round that moves rays, and the last, which moves none */
                    CHECK(ms.rounds >= 2);
                } else { /* the end: the last board's last load, and two latencies to detect and announce it */
                    CHECK_INT(ms.rounds, 0);
                    CHECK(ms.exchanges >= 2);
                    CHECK_INT(ms.frame_cycles, ms.sum.last_end + 2 * 5000);
                }
                c5_image_free(&img);
            }
        c5_image_free(&ref);
        c5_supervol_free(&l.sv);
    }
}

/* One board through the layer is the board model unchanged: no link, the same cycles. */
TEST(mb_one_board_is_the_board)
{
    loaded l;
    CHECK(c5t_load_scene("brain_mirrors", 32, &l.s, &l.sv) == 0);
    c5_board_opts o = {.cells = {2, 2, 2}};
    c5_image ref, img;
    c5_board_stats one;
    c5_err err;
    CHECK(c5_board_render(&l.s, &l.sv, 0, &o, &ref, &one, &err) == 0);
    c5_mb_opts mo = {0};
    c5_mb_stats ms;
    CHECK(mb_render(&l.s, &l.sv, 0, &o, &mo, 1, &img, &ms) == 0);
    CHECK(same_image(&ref, &img));
    CHECK_INT(ms.frame_cycles, one.cycles);
    CHECK_INT(ms.sum.fetches, one.fetches);
    CHECK_INT(ms.rounds, 0);
    CHECK_INT(ms.link_packets, 0);
    CHECK(ms.balance == 1);
    c5_image_free(&ref);
    c5_image_free(&img);
    c5_supervol_free(&l.sv);
}

/* The link model in rounds: the frame grows by the latency once a round, and by the bytes of
 * the busiest port each round over the bandwidth; the work itself does not change. */
TEST(mb_link_model_latency_and_bandwidth)
{
    loaded l;
    CHECK(c5t_load_scene("brain_mirrors", 32, &l.s, &l.sv) == 0);
    c5_board_opts o = {.cells = {4, 4, 4}};
    c5_image a, b, c;
    c5_mb_stats fast, slow, narrow;
    c5_mb_opts mf = {.mode = C5_MB_ROUNDS, .link_latency_s = -1, .link_bw = 1e15},
               ms_ = {.mode = C5_MB_ROUNDS, .link_latency_s = 1e-3, .link_bw = 1e15},
               mn = {.mode = C5_MB_ROUNDS, .link_latency_s = -1, .link_bw = 1e6};
    CHECK(mb_render(&l.s, &l.sv, 0, &o, &mf, 3, &a, &fast) == 0);
    CHECK(mb_render(&l.s, &l.sv, 0, &o, &ms_, 3, &b, &slow) == 0);
    CHECK(mb_render(&l.s, &l.sv, 0, &o, &mn, 3, &c, &narrow) == 0);
    CHECK(same_image(&a, &b) && same_image(&a, &c));
    CHECK_INT(slow.rounds, fast.rounds);
    CHECK_INT(slow.link_packets, fast.link_packets);
    /* 1 ms = 100,000 cycles a round */
    CHECK_INT(slow.frame_cycles - fast.frame_cycles, slow.rounds * 100000);
    /* 1 MB/s: a packet is 32 us = 3,200 cycles; the busiest port of a round moves at least
     * the mean of the boards' packets (each port's time rounds up by less than a cycle) */
    CHECK(narrow.frame_cycles - fast.frame_cycles + narrow.rounds >= 3200 * narrow.link_packets / 3);
    CHECK(narrow.link_packets > 0);
    for (int k = 0; k < 3; k++)
        CHECK_INT(slow.board[k].busy_cycles, fast.board[k].busy_cycles);
    c5_image_free(&a);
    c5_image_free(&b);
    c5_image_free(&c);
    c5_supervol_free(&l.sv);
}

/* The tree rule on a made-up traffic table: cells 0 and 63 (opposite corners of 4x4x4) trade
 * more rays than any other two, so they end on one board; every board keeps a cell; no board's weight exceeds
 * the heaviest after the weighted split. */
TEST(mb_assign_tree_keeps_trading_cells_together)
{
    int n[3] = {4, 4, 4}, count = 64;
    uint64_t *m = calloc((size_t)count * count, sizeof *m);
    CHECK(m != NULL);
    for (int c = 0; c < count; c++) {
        m[(size_t)c * count + c] = 1000; /* set-up rays: equal work */
        if (c + 1 < count)
            m[(size_t)c * count + c + 1] = 5; /* a little traffic to the next cell */
    }
    m[0 * count + 63] = m[(size_t)63 * count + 0] = 300;
    for (int nb = 2; nb <= 4; nb *= 2) {
        uint16_t owner[64], plain[64];
        c5_err err;
        CHECK(c5_mb_assign_tree(n, nb, m, owner, &err) == 0);
        CHECK(c5_mb_assign(C5_ASSIGN_KD, n, nb, plain, &err) == 0);
        CHECK_MSG(plain[0] != plain[63], "%d boards: the k-d split already joins the corners", nb);
        CHECK_MSG(owner[0] == owner[63], "%d boards: cells 0 and 63 on boards %d and %d", nb, owner[0], owner[63]);
        int per[8] = {0};
        for (int c = 0; c < count; c++) {
            CHECK(owner[c] < nb);
            per[owner[c]]++;
        }
        for (int k = 0; k < nb; k++)
            CHECK(per[k] >= 1);
    }
    /* No traffic at all: the weights are equal, the split is the plain k-d split. */
    memset(m, 0, (size_t)count * count * sizeof *m);
    uint16_t owner[64], plain[64];
    c5_err err;
    CHECK(c5_mb_assign_tree(n, 4, m, owner, &err) == 0);
    CHECK(c5_mb_assign(C5_ASSIGN_KD, n, 4, plain, &err) == 0);
    CHECK(!memcmp(owner, plain, sizeof owner));
    free(m);
}

/* Two frames of brain_mirrors under the tree rule, each board with its own history: frame 0
 * is the k-d split, frame 1 the tree rule on frame 0's traffic of all boards (the same table
 * on every board), and both images and ray counts are one board's. */
TEST(mb_tree_rule_second_frame_same_image)
{
    loaded l;
    CHECK(c5t_load_scene("brain_mirrors", 40, &l.s, &l.sv) == 0);
    c5_board_opts o = {.cells = {4, 4, 4}};
    c5_mb_history hist[4];
    memset(hist, 0, sizeof hist);
    c5_mb_opts tree = {.assign = C5_ASSIGN_TREE}, kd = {.assign = C5_ASSIGN_KD};
    for (int f = 0; f < 2; f++) {
        c5_image ref, img, kimg;
        c5_board_stats one;
        c5_mb_stats ms, mk;
        c5_err err;
        int want[4] = {0};
        uint16_t owner[64];
        if (f == 1) { /* the assignment frame 1 must use */
            for (int k = 1; k < 4; k++)
                CHECK(!memcmp(hist[k].moves, hist[0].moves, 64 * 64 * sizeof *hist[0].moves));
            uint64_t off = 0;
            for (int i = 0; i < 64 * 64; i++)
                off += i / 64 != i % 64 ? hist[0].moves[i] : 0;
            CHECK(off > 0);
            CHECK(c5_mb_assign_tree((int[3]){4, 4, 4}, 4, hist[0].moves, owner, &err) == 0);
            for (int c = 0; c < 64; c++)
                want[owner[c]]++;
        }
        CHECK(c5_board_render(&l.s, &l.sv, f, &o, &ref, &one, &err) == 0);
        CHECK(mb_render_hist(&l.s, &l.sv, f, &o, &tree, 4, hist, &img, &ms) == 0);
        CHECK(mb_render(&l.s, &l.sv, f, &o, &kd, 4, &kimg, &mk) == 0);
        CHECK_MSG(same_image(&ref, &img), "frame %d: image differs", f);
        CHECK(conserved(&ms.sum));
        for (int t = 0; t < C5_RAY_TYPES; t++)
            CHECK_INT(ms.sum.rays[t], one.rays[t]);
        for (int k = 0; k < 4; k++) {
            CHECK_INT(hist[k].cells, 64);
            CHECK_INT(ms.board[k].cells, f == 0 ? mk.board[k].cells : want[k]);
        }
        if (f == 0) /* no previous frame: the k-d split */
            CHECK_INT(ms.frame_cycles, mk.frame_cycles);
        c5_image_free(&ref);
        c5_image_free(&img);
        c5_image_free(&kimg);
    }
    for (int k = 0; k < 4; k++)
        c5_mb_history_free(&hist[k]);
    c5_supervol_free(&l.sv);
}

/* The load rule on made-up cycles: a corner of 4x4x4 cells costs 50 times the rest, so the
 * boards holding it get fewer cells, and no board's cycles exceed the k-d split's. */
TEST(mb_assign_load_balances_measured_cycles)
{
    int n[3] = {4, 4, 4};
    uint64_t cost[64];
    for (int c = 0; c < 64; c++) {
        int x = c % 4, y = c / 4 % 4, z = c / 16;
        cost[c] = x < 2 && y < 2 && z < 2 ? 50000 : 1000;
    }
    uint16_t load[64], kd[64];
    c5_err err;
    CHECK(c5_mb_assign_load(n, 8, cost, load, &err) == 0);
    CHECK(c5_mb_assign(C5_ASSIGN_KD, n, 8, kd, &err) == 0);
    uint64_t wl[8] = {0}, wk[8] = {0}, most_l = 0, most_k = 0;
    int cells[8] = {0};
    for (int c = 0; c < 64; c++)
        wl[load[c]] += cost[c], wk[kd[c]] += cost[c], cells[load[c]]++;
    int fewest = 64, most = 0;
    for (int k = 0; k < 8; k++) {
        most_l = wl[k] > most_l ? wl[k] : most_l;
        most_k = wk[k] > most_k ? wk[k] : most_k;
        fewest = cells[k] < fewest ? cells[k] : fewest;
        most = cells[k] > most ? cells[k] : most;
        CHECK(cells[k] >= 1);
    }
    CHECK_MSG(most_l < most_k, "load rule's busiest board %llu, kd's %llu", (unsigned long long)most_l,
              (unsigned long long)most_k);
    CHECK(fewest < most);
}
