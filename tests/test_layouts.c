/* Bit layouts (build/gen/c5_layouts.h, generated from spec/layouts.toml): random and
 * extreme round trips, every field's bits checked against a reading written here from its
 * LSB/WIDTH macros alone (bit i is bit i % 8 of byte i / 8), byte order against hand-worked
 * bytes, reserved bits, and the declared formats' widths. Every test runs over both
 * layouts through the table LAYOUTS, so a new layout only needs a row there. */
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "c5_layouts.h"
#include "fixed.h"
#include "harness.h"
#include "rng.h"

/* ---- the layouts as data, from the header's X-macros -------------------------------- */

typedef struct {
    const char *name;
    int lsb, width, is_signed;
} fdesc;

#define DESC(m, lsb, w, s) {#m, (lsb), (w), (s)},
#define RDESC(lsb, w) {"reserved", (lsb), (w), 0},
static const fdesc RP_FIELDS[] = {C5_RAY_PACKET_FIELDS(DESC)};
static const fdesc RP_RESERVED[] = {C5_RAY_PACKET_RESERVED(RDESC)};
static const fdesc CT_FIELDS[] = {C5_CELL_TREE_NODE_FIELDS(DESC)};
static const fdesc CT_RESERVED[] = {C5_CELL_TREE_NODE_RESERVED(RDESC)};
static const fdesc TH_FIELDS[] = {C5_TLP_HEADER_FIELDS(DESC)};
static const fdesc TH_RESERVED[] = {C5_TLP_HEADER_RESERVED(RDESC)};
static const fdesc SD_FIELDS[] = {C5_SCENE_DESCRIPTOR_FIELDS(DESC)};
static const fdesc SD_RESERVED[] = {C5_SCENE_DESCRIPTOR_RESERVED(RDESC)};
#define COUNT(a) ((int)(sizeof(a) / sizeof((a)[0])))

/* Any layout's struct fits here; the wrappers below give every layout one interface. */
typedef union {
    c5_ray_packet_t rp;
    c5_cell_tree_node_t ct;
    c5_tlp_header_t th;
    c5_scene_descriptor_t sd;
} any_fields;

#define MAX_BYTES 80

typedef struct {
    const char *name;
    int width, bytes;
    const fdesc *fields;
    int nfields;
    const fdesc *reserved;
    int nreserved;
    void (*set)(any_fields *s, int k, int64_t v); /* field k (X-macro order) = v */
    int64_t (*get)(const any_fields *s, int k);
    void (*pack)(const any_fields *s, uint8_t *out);
    void (*unpack)(const uint8_t *in, any_fields *s);
    int (*reserved_zero)(const uint8_t *in);
} layout;

#define SET_K(m, lsb, w, s) if (i++ == k) f->m = v;
#define GET_K(m, lsb, w, s) if (i++ == k) return (int64_t)f->m;
#define WRAPPERS(L, U, member)                                                                 \
    static void L##_set(any_fields *s, int k, int64_t v)                                       \
    {                                                                                          \
        c5_##L##_t *f = &s->member;                                                            \
        int i = 0;                                                                             \
        U##_FIELDS(SET_K)                                                                      \
    }                                                                                          \
    static int64_t L##_get(const any_fields *s, int k)                                         \
    {                                                                                          \
        const c5_##L##_t *f = &s->member;                                                      \
        int i = 0;                                                                             \
        U##_FIELDS(GET_K)                                                                      \
        return 0;                                                                              \
    }                                                                                          \
    static void L##_pack_any(const any_fields *s, uint8_t *out) { c5_##L##_pack(&s->member, out); } \
    static void L##_unpack_any(const uint8_t *in, any_fields *s) { c5_##L##_unpack(in, &s->member); }
WRAPPERS(ray_packet, C5_RAY_PACKET, rp)
WRAPPERS(cell_tree_node, C5_CELL_TREE_NODE, ct)
WRAPPERS(tlp_header, C5_TLP_HEADER, th)
WRAPPERS(scene_descriptor, C5_SCENE_DESCRIPTOR, sd)

static const layout LAYOUTS[] = {
    {"ray_packet", C5_RAY_PACKET_WIDTH, C5_RAY_PACKET_BYTES, RP_FIELDS, COUNT(RP_FIELDS), RP_RESERVED,
     COUNT(RP_RESERVED), ray_packet_set, ray_packet_get, ray_packet_pack_any, ray_packet_unpack_any,
     c5_ray_packet_reserved_zero},
    {"cell_tree_node", C5_CELL_TREE_NODE_WIDTH, C5_CELL_TREE_NODE_BYTES, CT_FIELDS, COUNT(CT_FIELDS),
     CT_RESERVED, COUNT(CT_RESERVED), cell_tree_node_set, cell_tree_node_get, cell_tree_node_pack_any,
     cell_tree_node_unpack_any, c5_cell_tree_node_reserved_zero},
    {"tlp_header", C5_TLP_HEADER_WIDTH, C5_TLP_HEADER_BYTES, TH_FIELDS, COUNT(TH_FIELDS), TH_RESERVED,
     COUNT(TH_RESERVED), tlp_header_set, tlp_header_get, tlp_header_pack_any, tlp_header_unpack_any,
     c5_tlp_header_reserved_zero},
    {"scene_descriptor", C5_SCENE_DESCRIPTOR_WIDTH, C5_SCENE_DESCRIPTOR_BYTES, SD_FIELDS, COUNT(SD_FIELDS),
     SD_RESERVED, COUNT(SD_RESERVED), scene_descriptor_set, scene_descriptor_get, scene_descriptor_pack_any,
     scene_descriptor_unpack_any, c5_scene_descriptor_reserved_zero},
};
#define N_LAYOUTS COUNT(LAYOUTS)

/* ---- independent bit helpers ----------------------------------------------------------- */

static int bit_of(const uint8_t *buf, int i) { return (buf[i / 8] >> (i % 8)) & 1; }
static void set_bit(uint8_t *buf, int i) { buf[i / 8] = (uint8_t)(buf[i / 8] | (1u << (i % 8))); }

static int64_t max_raw(const fdesc *d)
{
    return d->is_signed ? ((int64_t)1 << (d->width - 1)) - 1 : ((int64_t)1 << d->width) - 1;
}
static int64_t min_raw(const fdesc *d) { return d->is_signed ? -((int64_t)1 << (d->width - 1)) : 0; }

/* Field d read back bit by bit, sign-extended by arithmetic rather than bit tricks. */
static int64_t read_field(const uint8_t *buf, const fdesc *d)
{
    int64_t v = 0;
    for (int b = 0; b < d->width; b++)
        v += (int64_t)bit_of(buf, d->lsb + b) << b;
    if (d->is_signed && v > max_raw(d))
        v -= (int64_t)1 << d->width;
    return v;
}

/* Uniform raw bits, with the extremes (min, max, 0, -1) one time in four: random bits alone
 * would almost never hit them. */
static int64_t rand_raw(uint64_t *rng, const fdesc *d)
{
    uint64_t r = c5_splitmix64(rng);
    switch (r & 15) {
    case 0: return min_raw(d);
    case 1: return max_raw(d);
    case 2: return 0;
    case 3: return d->is_signed ? -1 : max_raw(d);
    }
    int64_t v = (int64_t)((r >> 4) & (((uint64_t)1 << d->width) - 1));
    return v > max_raw(d) ? v - ((int64_t)1 << d->width) : v;
}

/* Every field of s against the buffer read independently and against want (if not NULL). */
static void check_fields(const layout *L, const any_fields *s, const uint8_t *buf, const any_fields *want)
{
    for (int k = 0; k < L->nfields; k++) {
        const fdesc *d = &L->fields[k];
        int64_t got = L->get(s, k);
        CHECK_MSG(read_field(buf, d) == got, "%s.%s: bits hold %lld, unpack gave %lld", L->name, d->name,
                  (long long)read_field(buf, d), (long long)got);
        if (want)
            CHECK_MSG(L->get(want, k) == got, "%s.%s: packed %lld, unpacked %lld", L->name, d->name,
                      (long long)L->get(want, k), (long long)got);
    }
    for (int k = 0; k < L->nreserved; k++)
        CHECK_MSG(read_field(buf, &L->reserved[k]) == 0, "%s: reserved bits %d:%d not zero", L->name,
                  L->reserved[k].lsb + L->reserved[k].width - 1, L->reserved[k].lsb);
    CHECK_MSG(L->reserved_zero(buf), "%s: reserved_zero() says a reserved bit is set", L->name);
}

/* pack, check the bytes, unpack, compare. */
static void round_trip(const layout *L, const any_fields *in)
{
    uint8_t buf[MAX_BYTES];
    any_fields out;
    memset(buf, 0xA5, sizeof buf); /* pack must write every byte */
    memset(&out, 0x5A, sizeof out);
    L->pack(in, buf);
    L->unpack(buf, &out);
    check_fields(L, &out, buf, in);
}

/* ---- sizes and formats ----------------------------------------------------------------- */

TEST(layouts_sizes)
{
    CHECK_INT(C5_RAY_PACKET_BYTES, 32);
    CHECK_INT(C5_RAY_PACKET_WIDTH, 256);
    CHECK_INT(C5_CELL_TREE_NODE_BYTES, 12);
    CHECK_INT(C5_CELL_TREE_NODE_WIDTH, 96);
    for (int l = 0; l < N_LAYOUTS; l++) {
        const layout *L = &LAYOUTS[l];
        CHECK_INT(L->bytes * 8, L->width);
        int sum = 0;
        for (int k = 0; k < L->nfields; k++)
            sum += L->fields[k].width;
        for (int k = 0; k < L->nreserved; k++)
            sum += L->reserved[k].width;
        CHECK_MSG(sum == L->width, "%s: fields total %d bits, width %d", L->name, sum, L->width);
    }
}

TEST(layouts_fmt_widths)
{
    static const struct {
        c5_fx_fmt fmt;
        int width, is_signed;
    } F[] = {
        {C5_RAY_PACKET_POS_X_FMT, C5_RAY_PACKET_POS_X_WIDTH, 0},
        {C5_RAY_PACKET_POS_Y_FMT, C5_RAY_PACKET_POS_Y_WIDTH, 0},
        {C5_RAY_PACKET_POS_Z_FMT, C5_RAY_PACKET_POS_Z_WIDTH, 0},
        {C5_RAY_PACKET_DIR_X_FMT, C5_RAY_PACKET_DIR_X_WIDTH, 1},
        {C5_RAY_PACKET_DIR_Y_FMT, C5_RAY_PACKET_DIR_Y_WIDTH, 1},
        {C5_RAY_PACKET_DIR_Z_FMT, C5_RAY_PACKET_DIR_Z_WIDTH, 1},
        {C5_RAY_PACKET_CONTRIBUTION_FMT, C5_RAY_PACKET_CONTRIBUTION_WIDTH, 0},
        {C5_RAY_PACKET_OPACITY_FMT, C5_RAY_PACKET_OPACITY_WIDTH, 0},
        {C5_RAY_PACKET_RED_FMT, C5_RAY_PACKET_RED_WIDTH, 0},
        {C5_RAY_PACKET_GREEN_FMT, C5_RAY_PACKET_GREEN_WIDTH, 0},
        {C5_RAY_PACKET_BLUE_FMT, C5_RAY_PACKET_BLUE_WIDTH, 0},
    };
    for (int i = 0; i < COUNT(F); i++) {
        CHECK_MSG(c5_fx_width(F[i].fmt) == F[i].width, "%s: format %d bits, field %d", F[i].fmt.name,
                  c5_fx_width(F[i].fmt), F[i].width);
        CHECK_MSG(F[i].fmt.is_signed == F[i].is_signed, "%s: signedness", F[i].fmt.name);
    }
    /* Every signal's format is one fixed.h accepts. */
    static const c5_fx_fmt SIG[] = {
        C5_SIG_STEP_K_FMT,  C5_SIG_STEP_VEC_FMT,   C5_SIG_VOXEL_FRAC_FMT, C5_SIG_SAMPLE_VALUE_FMT,
        C5_SIG_TF_RGBA_FMT, C5_SIG_GRADIENT_FMT,   C5_SIG_NORMAL_FMT,     C5_SIG_LIGHT_TERM_FMT,
        C5_SIG_SHADED_RGB_FMT, C5_SIG_SAMPLE_RGB_FMT, C5_SIG_FRAME_ACC_FMT, C5_SIG_GEOM_COORD_FMT,
        C5_SIG_GEOM_T_FMT,
    };
    for (int i = 0; i < COUNT(SIG); i++)
        CHECK_MSG(c5_fx_fmt_valid(SIG[i]), "signal %s: invalid format", SIG[i].name);
    /* The step vector's fraction equals the position's: the position advances by exact addition. */
    CHECK_INT(C5_SIG_STEP_VEC_FMT.frac_bits, C5_RAY_PACKET_POS_X_FMT.frac_bits);
    CHECK_INT(C5_SIG_FRAME_ACC_FMT.frac_bits, C5_RAY_PACKET_RED_FMT.frac_bits);
}

/* ---- round trips ----------------------------------------------------------------------- */

TEST(layouts_round_trip_random)
{
    for (int l = 0; l < N_LAYOUTS; l++) {
        const layout *L = &LAYOUTS[l];
        uint64_t rng = 0x1A70075ull + (uint64_t)l;
        for (int n = 0; n < 10000; n++) {
            any_fields in;
            memset(&in, 0, sizeof in);
            for (int k = 0; k < L->nfields; k++)
                L->set(&in, k, rand_raw(&rng, &L->fields[k]));
            round_trip(L, &in);
            if (c5t_failed_now())
                return;
        }
    }
}

TEST(layouts_round_trip_extremes)
{
    for (int l = 0; l < N_LAYOUTS; l++) {
        const layout *L = &LAYOUTS[l];
        any_fields in;
        uint8_t buf[MAX_BYTES];

        memset(&in, 0, sizeof in); /* all zero: every byte zero */
        L->pack(&in, buf);
        for (int i = 0; i < L->bytes; i++)
            CHECK_MSG(buf[i] == 0, "%s: all-zero fields, byte %d = 0x%02x", L->name, i, buf[i]);
        round_trip(L, &in);

        for (int k = 0; k < L->nfields; k++) /* every field at its max */
            L->set(&in, k, max_raw(&L->fields[k]));
        round_trip(L, &in);
        for (int k = 0; k < L->nfields; k++) /* signed fields at their min, the rest at max */
            if (L->fields[k].is_signed)
                L->set(&in, k, min_raw(&L->fields[k]));
        round_trip(L, &in);
        for (int k = 0; k < L->nfields; k++) /* signed at min, unsigned at 0 */
            if (!L->fields[k].is_signed)
                L->set(&in, k, 0);
        round_trip(L, &in);
        for (int k = 0; k < L->nfields; k++) /* signed at -1: all ones, sign-extended back */
            if (L->fields[k].is_signed)
                L->set(&in, k, -1);
        round_trip(L, &in);
        if (c5t_failed_now())
            return;
    }
}

/* Any bytes at all: unpack then pack gives them back with the reserved bits cleared. */
TEST(layouts_unpack_pack_any_bytes)
{
    uint64_t rng = 0xB17E5ull;
    for (int l = 0; l < N_LAYOUTS; l++) {
        const layout *L = &LAYOUTS[l];
        for (int n = 0; n < 2000; n++) {
            uint8_t in[MAX_BYTES], want[MAX_BYTES], out[MAX_BYTES];
            for (int i = 0; i < L->bytes; i++)
                in[i] = (uint8_t)c5_splitmix64(&rng);
            memcpy(want, in, sizeof want);
            for (int r = 0; r < L->nreserved; r++)
                for (int b = 0; b < L->reserved[r].width; b++)
                    want[(L->reserved[r].lsb + b) / 8] &= (uint8_t)~(1u << ((L->reserved[r].lsb + b) % 8));
            any_fields s;
            L->unpack(in, &s);
            L->pack(&s, out);
            CHECK_MSG(memcmp(out, want, (size_t)L->bytes) == 0, "%s: unpack/pack changed the bytes", L->name);
        }
    }
}

/* ---- every field in its own bits -------------------------------------------------------- */

TEST(layouts_field_isolated)
{
    for (int l = 0; l < N_LAYOUTS; l++) {
        const layout *L = &LAYOUTS[l];
        for (int k = 0; k < L->nfields; k++) {
            const fdesc *d = &L->fields[k];
            any_fields in, out;
            uint8_t buf[MAX_BYTES], want[MAX_BYTES] = {0};
            memset(&in, 0, sizeof in);
            L->set(&in, k, d->is_signed ? -1 : max_raw(d)); /* all ones in the field's width */
            L->pack(&in, buf);
            for (int b = d->lsb; b < d->lsb + d->width; b++)
                set_bit(want, b);
            for (int i = 0; i < L->bytes; i++)
                CHECK_MSG(buf[i] == want[i], "%s.%s all ones: byte %d = 0x%02x, expected 0x%02x", L->name,
                          d->name, i, buf[i], want[i]);
            L->unpack(buf, &out);
            for (int j = 0; j < L->nfields; j++)
                CHECK_MSG(L->get(&out, j) == (j == k ? L->get(&in, k) : 0), "%s.%s: unpacked %s = %lld",
                          L->name, d->name, L->fields[j].name, (long long)L->get(&out, j));
        }
    }
}

/* Every field at all ones sets every bit but the reserved ones; a set reserved bit is seen
 * by reserved_zero() and dropped by the next unpack/pack. */
TEST(layouts_reserved_bits)
{
    for (int l = 0; l < N_LAYOUTS; l++) {
        const layout *L = &LAYOUTS[l];
        any_fields in, back;
        uint8_t buf[MAX_BYTES], again[MAX_BYTES];
        memset(&in, 0, sizeof in);
        for (int k = 0; k < L->nfields; k++)
            L->set(&in, k, L->fields[k].is_signed ? -1 : max_raw(&L->fields[k]));
        L->pack(&in, buf);
        for (int i = 0; i < L->width; i++) {
            int reserved = 0;
            for (int r = 0; r < L->nreserved; r++)
                reserved |= i >= L->reserved[r].lsb && i < L->reserved[r].lsb + L->reserved[r].width;
            CHECK_MSG(bit_of(buf, i) == !reserved, "%s: bit %d is %d with every field all ones", L->name, i,
                      bit_of(buf, i));
            if (!reserved)
                continue;
            CHECK(L->reserved_zero(buf));
            set_bit(buf, i);
            CHECK_MSG(!L->reserved_zero(buf), "%s: reserved bit %d set, reserved_zero() missed it", L->name, i);
            L->unpack(buf, &back);
            L->pack(&back, again);
            CHECK_MSG(!bit_of(again, i) && L->reserved_zero(again), "%s: reserved bit %d survived", L->name, i);
            buf[i / 8] = (uint8_t)(buf[i / 8] & ~(1u << (i % 8)));
        }
    }
}

/* ---- byte order, worked by hand: bit i is bit i % 8 of byte i / 8 --------------------- */

static void check_bytes(const char *what, const uint8_t *buf, int n, const int *idx, const uint8_t *val, int m)
{
    for (int i = 0; i < n; i++) {
        uint8_t want = 0;
        for (int j = 0; j < m; j++)
            if (idx[j] == i)
                want = val[j];
        CHECK_MSG(buf[i] == want, "%s: byte %d = 0x%02x, expected 0x%02x", what, i, buf[i], want);
    }
}

TEST(layouts_byte_order)
{
    c5_ray_packet_t p;
    uint8_t buf[C5_RAY_PACKET_BYTES];

    /* pos_x, bits 255:233: 0x2BCDEF << 1 = 0x579BDE in bytes 29..31, lowest byte first. */
    memset(&p, 0, sizeof p);
    p.pos_x = 0x2BCDEF;
    c5_ray_packet_pack(&p, buf);
    check_bytes("pos_x 0x2BCDEF", buf, 32, (const int[]){29, 30, 31}, (const uint8_t[]){0xDE, 0x9B, 0x57}, 3);
    if (c5t_failed_now())
        return;

    /* 1.5 voxels through the field's own format and rounding: raw 1.5 * 2^15 = 0x00C000,
     * shifted to bit 233: 0x018000 from byte 29. */
    p.pos_x = c5_fx_from_double(1.5, C5_RAY_PACKET_POS_X_FMT, C5_RAY_PACKET_POS_X_RND, NULL);
    CHECK_INT(p.pos_x, 0xC000);
    c5_ray_packet_pack(&p, buf);
    check_bytes("pos_x 1.5", buf, 32, (const int[]){30, 31}, (const uint8_t[]){0x80, 0x01}, 2);
    if (c5t_failed_now())
        return;

    /* dest_u = 511 straddles bytes: bits 130..135 (byte 16 from bit 2) and 136..138 (byte 17). */
    memset(&p, 0, sizeof p);
    p.dest_u = 511;
    c5_ray_packet_pack(&p, buf);
    check_bytes("dest_u 511", buf, 32, (const int[]){16, 17}, (const uint8_t[]){0xFC, 0x07}, 2);
    if (c5t_failed_now())
        return;

    /* dir_x = -2.0: raw -32768, 0x8000 in 16 bits at bit 171: its top bit is bit 186, byte 23's bit 2. */
    memset(&p, 0, sizeof p);
    p.dir_x = c5_fx_from_double(-2.0, C5_RAY_PACKET_DIR_X_FMT, C5_RAY_PACKET_DIR_X_RND, NULL);
    CHECK_INT(p.dir_x, -32768);
    c5_ray_packet_pack(&p, buf);
    check_bytes("dir_x -2", buf, 32, (const int[]){23}, (const uint8_t[]){0x04}, 1);
    if (c5t_failed_now())
        return;
    c5_ray_packet_t q;
    c5_ray_packet_unpack(buf, &q);
    CHECK_INT(q.dir_x, -32768);

    /* cell_tree_node child0 = 0x1ABC at bits 95:83: 0x1ABC << 3 = 0xD5E0 in bytes 10, 11. */
    c5_cell_tree_node_t c;
    uint8_t nb[C5_CELL_TREE_NODE_BYTES];
    memset(&c, 0, sizeof c);
    c.child0 = 0x1ABC;
    c5_cell_tree_node_pack(&c, nb);
    check_bytes("child0 0x1ABC", nb, 12, (const int[]){10, 11}, (const uint8_t[]){0xE0, 0xD5}, 2);
    if (c5t_failed_now())
        return;

    /* ready, bit 12 = byte 1, 0x10. */
    memset(&c, 0, sizeof c);
    c.ready = 1;
    c5_cell_tree_node_pack(&c, nb);
    check_bytes("ready", nb, 12, (const int[]){1}, (const uint8_t[]){0x10}, 1);
}

/* ---- pack refuses values that do not fit ------------------------------------------------ */

/* Packs field k = v in a child process; 1 if the child died of an assert (SIGABRT). */
static int pack_aborts(const layout *L, int k, int64_t v)
{
    fflush(stdout);
    pid_t pid = fork();
    if (pid == 0) {
        if (!freopen("/dev/null", "w", stderr))
            _exit(3);
        any_fields in;
        uint8_t buf[MAX_BYTES];
        memset(&in, 0, sizeof in);
        L->set(&in, k, v);
        L->pack(&in, buf);
        _exit(0);
    }
    int status = 0;
    if (pid < 0 || waitpid(pid, &status, 0) != pid)
        return -1;
    return WIFSIGNALED(status) && WTERMSIG(status) == SIGABRT;
}

TEST(layouts_pack_asserts_range)
{
#ifdef NDEBUG
    return; /* asserts compiled out */
#endif
    for (int l = 0; l < N_LAYOUTS; l++) {
        const layout *L = &LAYOUTS[l];
        for (int k = 0; k < L->nfields; k++) {
            const fdesc *d = &L->fields[k];
            CHECK_MSG(pack_aborts(L, k, max_raw(d)) == 0, "%s.%s: max refused", L->name, d->name);
            if (d->width < 32) /* max + 1 of a 32-bit uint does not fit its uint32_t member */
                CHECK_MSG(pack_aborts(L, k, max_raw(d) + 1) == 1, "%s.%s: max + 1 packed", L->name, d->name);
            if (d->is_signed)
                CHECK_MSG(pack_aborts(L, k, min_raw(d) - 1) == 1, "%s.%s: min - 1 packed", L->name, d->name);
        }
    }
}
