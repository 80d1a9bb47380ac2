/* The committed golden vectors (vectors/golden/) replayed the way a VHDL testbench uses
 * them: only the input columns (and input images) are fed to the model's block, from
 * reset, and every output column and output image must come out as written. This checks
 * the files as stimuli (a trace thinned or cut wrongly, a column out of order, an image of
 * the wrong moment would fail), where tests/vectors_test.sh checks that the model still
 * makes the same files. */
#include <jansson.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "c5_layouts.h"
#include "cell_tree.h"
#include "dsp_sched.h"
#include "harness.h"
#include "ray_queue.h"
#include "sched_report.h"

#define GOLDEN "vectors/golden"
#define MAX_COLS 32

typedef struct {
    int n, cols;
    char (*line)[600];
} hexfile;

static int load_hex(const char *name, hexfile *h)
{
    char path[512];
    snprintf(path, sizeof path, GOLDEN "/%s", name);
    FILE *f = fopen(path, "r");
    memset(h, 0, sizeof *h);
    if (!f)
        return -1;
    int cap = 0;
    char buf[600];
    while (fgets(buf, sizeof buf, f)) {
        if (h->n == cap) {
            cap = cap ? 2 * cap : 1024;
            h->line = realloc(h->line, (size_t)cap * sizeof *h->line);
        }
        buf[strcspn(buf, "\n")] = 0;
        strcpy(h->line[h->n++], buf);
    }
    fclose(f);
    return 0;
}

/* Column k of line i as a number (columns of at most 64 bits). */
static uint64_t col(const hexfile *h, int i, int k)
{
    const char *p = h->line[i];
    for (int j = 0; j < k; j++)
        p = strchr(p, ' ') + 1;
    return strtoull(p, NULL, 16);
}

/* Column k of line i as little-endian bytes (wide columns). */
static void col_bytes(const hexfile *h, int i, int k, uint8_t *le, int nbytes)
{
    const char *p = h->line[i];
    for (int j = 0; j < k; j++)
        p = strchr(p, ' ') + 1;
    int digits = (int)strcspn(p, " ");
    memset(le, 0, (size_t)nbytes);
    for (int d = 0; d < digits; d++) {
        int pos = digits - 1 - d; /* nibble index from the least significant */
        char c = p[d];
        int v = c <= '9' ? c - '0' : c - 'a' + 10;
        le[pos / 2] |= (uint8_t)(v << (4 * (pos % 2)));
    }
}

/* The manifest's vector files of a block (names into *names, count returned). */
static int files_of(const char *block, char names[][128], int max)
{
    json_error_t je;
    json_t *m = json_load_file(GOLDEN "/manifest.json", 0, &je);
    int n = 0;
    size_t i;
    json_t *e;
    json_array_foreach(json_object_get(m, "files"), i, e) {
        if (n < max && !strcmp(json_string_value(json_object_get(e, "block")), block) &&
            !strcmp(json_string_value(json_object_get(e, "kind")), "vectors"))
            snprintf(names[n++], 128, "%s", json_string_value(json_object_get(e, "file")));
    }
    json_decref(m);
    return n;
}

/* Boolean key of a vector file's config in the manifest (0 when absent), or whether the
 * string key equals want. */
static int config_is(const char *file, const char *key, const char *want)
{
    json_error_t je;
    json_t *m = json_load_file(GOLDEN "/manifest.json", 0, &je), *e;
    size_t i;
    int is = 0;
    json_array_foreach(json_object_get(m, "files"), i, e) {
        if (strcmp(json_string_value(json_object_get(e, "file")), file))
            continue;
        json_t *v = json_object_get(json_object_get(e, "config"), key);
        is = want ? json_is_string(v) && !strcmp(json_string_value(v), want) : json_is_true(v);
    }
    json_decref(m);
    return is;
}

/* "cell_tree.default.hex" + "ram_final" -> "cell_tree.default.ram_final.hex" */
static void image_of(const char *file, const char *image, char *out)
{
    size_t n = strlen(file) - 4;
    sprintf(out, "%.*s.%s.hex", (int)n, file, image);
}

TEST(vectors_replay_packet)
{
    char names[16][128];
    int nf = files_of("packet", names, 16);
    CHECK(nf >= 2);
    for (int k = 0; k < nf; k++) {
        hexfile h;
        CHECK_MSG(load_hex(names[k], &h) == 0, "cannot read %s", names[k]);
        for (int i = 0; i < h.n; i++) {
            c5_ray_packet_t p;
            uint8_t want[C5_RAY_PACKET_BYTES], got[C5_RAY_PACKET_BYTES];
            int c = 0;
#define X(m, lsb, w, sgn) p.m = (__typeof__(p.m))((sgn) ? c5_lay_sext(col(&h, i, c), w) : (int64_t)col(&h, i, c)); c++;
            C5_RAY_PACKET_FIELDS(X)
#undef X
            col_bytes(&h, i, c, want, C5_RAY_PACKET_BYTES);
            c5_ray_packet_pack(&p, got);
            CHECK_MSG(!memcmp(want, got, sizeof got), "%s vector %d: pack differs", names[k], i);
            c5_ray_packet_t back;
            c5_ray_packet_unpack(want, &back);
            int same = 1; /* field by field: the struct has padding */
#define X(m, lsb, w, sgn) same &= back.m == p.m;
            C5_RAY_PACKET_FIELDS(X)
#undef X
            CHECK_MSG(same, "%s vector %d: unpack differs", names[k], i);
        }
        free(h.line);
    }
}

TEST(vectors_replay_ray_queue)
{
    char names[16][128];
    int nf = files_of("ray_queue", names, 16);
    CHECK(nf >= 2);
    for (int k = 0; k < nf; k++) {
        hexfile h;
        CHECK_MSG(load_hex(names[k], &h) == 0, "cannot read %s", names[k]);
        c5_rq q;
        c5_rq_cfg cfg = C5_RQ_CFG_DEFAULT;
        CHECK(c5_rq_init(&q, &cfg) == 0);
        int full_seen = 0, refused = 0;
        for (int i = 0; i < h.n; i++) {
            c5_rq_in in = {(int)col(&h, i, 0), (uint32_t)col(&h, i, 1), (uint32_t)col(&h, i, 2), (int)col(&h, i, 3)};
            c5_rq_out o;
            c5_rq_step(&q, &in, &o);
            uint64_t got[7] = {(uint64_t)o.pop_valid, o.pop_key, o.pop_payload, (uint64_t)o.insert_accepted,
                               (uint64_t)o.full, o.count, (uint64_t)o.empty};
            for (int c = 0; c < 7; c++)
                CHECK_MSG(got[c] == col(&h, i, 4 + c), "%s cycle %d: output column %d is %llu, file says %llu",
                          names[k], i, 4 + c, (unsigned long long)got[c], (unsigned long long)col(&h, i, 4 + c));
            full_seen |= o.full;
            refused += in.insert_valid && !o.insert_accepted;
        }
        if (strstr(names[k], ".directed."))
            CHECK_MSG(full_seen && refused >= 3, "%s: the directed trace lacks the full-queue spill case", names[k]);
        c5_rq_free(&q);
        free(h.line);
    }
}

/* Compares a tree's RAM slots and roots with the images written beside a trace. */
static int same_images(const char *file, const char *ram_name, const char *roots_name, const c5_ctree *t)
{
    char path[256];
    hexfile ram, roots;
    image_of(file, ram_name, path);
    if (load_hex(path, &ram) != 0 || ram.n != (int)t->used)
        return 0;
    int ok = 1;
    for (int i = 0; i < ram.n && ok; i++) {
        uint8_t le[C5_CELL_TREE_NODE_BYTES];
        col_bytes(&ram, i, 0, le, sizeof le);
        ok = !memcmp(le, t->ram + (size_t)i * C5_CELL_TREE_NODE_BYTES, sizeof le);
    }
    free(ram.line);
    if (roots_name) {
        image_of(file, roots_name, path);
        if (load_hex(path, &roots) != 0 || roots.n != C5_MAX_CELLS)
            return 0;
        for (int c = 0; c < C5_MAX_CELLS && ok; c++)
            ok = col(&roots, c, 0) == t->root[c];
        free(roots.line);
    }
    return ok;
}

TEST(vectors_replay_cell_tree)
{
    char names[16][128];
    int nf = files_of("cell_tree", names, 16);
    CHECK(nf >= 3);
    static c5_ctree t;
    for (int k = 0; k < nf; k++) {
        hexfile h;
        CHECK_MSG(load_hex(names[k], &h) == 0, "cannot read %s", names[k]);
        c5_ctree_init(&t, 0);
        for (int i = 0; i < h.n; i++) {
            uint32_t got = c5_ctree_tag(&t, (uint32_t)col(&h, i, 0), (int)col(&h, i, 1));
            CHECK_MSG(got == col(&h, i, 2), "%s vector %d: node %u, file says %llu", names[k], i, got,
                      (unsigned long long)col(&h, i, 2));
        }
        CHECK_MSG(same_images(names[k], "ram_final", "roots_final", &t), "%s: RAM or roots image differs",
                  names[k]);
        if (strstr(names[k], ".overflow."))
            CHECK(t.overflow);
        free(h.line);
    }
}

TEST(vectors_replay_sched)
{
    char names[16][128];
    int nf = files_of("sched", names, 16);
    CHECK(nf >= 3);
    static c5_ctree t;
    for (int k = 0; k < nf; k++) {
        char path[256];
        hexfile h, ram, roots;
        CHECK(load_hex(names[k], &h) == 0);
        image_of(names[k], "ram_in", path);
        CHECK(load_hex(path, &ram) == 0);
        image_of(names[k], "roots_in", path);
        CHECK(load_hex(path, &roots) == 0);
        /* The DSP RAM as the frame left it: the input images only. */
        c5_ctree_init(&t, 0);
        for (int i = 0; i < ram.n; i++) {
            col_bytes(&ram, i, 0, t.ram + (size_t)i * C5_CELL_TREE_NODE_BYTES, C5_CELL_TREE_NODE_BYTES);
            c5_cell_tree_node_t nd;
            c5_cell_tree_node_unpack(t.ram + (size_t)i * C5_CELL_TREE_NODE_BYTES, &nd);
            t.nodes += !nd.extension;
            t.extensions += nd.extension;
        }
        t.used = (uint32_t)ram.n;
        for (int c = 0; c < C5_MAX_CELLS; c++)
            t.root[c] = (uint16_t)col(&roots, c, 0);
        /* The tagging unit's overflow flag and the DSP's choice for such a tree, from the
         * config: the RAM image alone cannot tell a full tree from a frozen one. */
        t.overflow = config_is(names[k], "overflow", NULL);
        c5_dsp_sched_opts o = {.report = c5_dsp_sched_report, .rule = C5_SPLIT_MOST_LEAVES, .partial = config_is(names[k], "on_overflow", "partial")};
        c5_dsp_sched_result r;
        c5_err err;
        CHECK_MSG(c5_dsp_schedule(&t, &o, &r, &err) == 0, "%s", err.msg);
        CHECK_MSG(r.next.len == h.n, "%s: schedule of %d loads, file has %d", names[k], r.next.len, h.n);
        for (int i = 0; i < h.n; i++)
            CHECK_MSG(col(&h, i, 0) == (uint64_t)i && col(&h, i, 1) == (uint64_t)r.next.cells[i],
                      "%s step %d: cell %d, file says %llu", names[k], i, r.next.cells[i],
                      (unsigned long long)col(&h, i, 1));
        c5_dsp_sched_free(&r);
        CHECK_MSG(same_images(names[k], "ram_out", NULL, &t), "%s: RAM written back differs", names[k]);
        free(h.line);
        free(ram.line);
        free(roots.line);
    }
}
