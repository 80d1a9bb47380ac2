/* cube5 vectors: golden vectors of every block for the VHDL (docs/vectors.md). */
#include <jansson.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "blocks.h"
#include "builtin_scenes.h"
#include "cli.h"
#include "progress.h"

#define MAX_SCENES 32

typedef struct {
    const char *out;
    const char *scenes[MAX_SCENES];
    int n_scenes, no_scenes, size[2], cells[3], vcd;
    long count, seed;
} vec_args;

/* --scene S, repeatable; 'none': directed vectors only. */
static int scene_opt(const c5_opt *o, const char *v, void *field, c5_err *err)
{
    vec_args *a = field;
    if (!strcmp(v, "none"))
        a->no_scenes = 1;
    else if (a->n_scenes == MAX_SCENES)
        return c5_fail(err, "%s: at most %d scenes", o->name, MAX_SCENES);
    else
        a->scenes[a->n_scenes++] = v;
    return 0;
}

static const c5_opt opts[] = {
    {"--out", "DIR", c5_opt_str, offsetof(vec_args, out), 0, 0, 0,
     "output directory: created, or an earlier vector set replaced (its files only); a non-empty directory that "
     "holds no vector set is refused (default out/vectors)"},
    {"--scene", "S", scene_opt, 0, 0, 0, 0,
     "a built-in scene or scene file to tap, repeatable (default: every built-in scene); 'none': directed vectors "
     "only"},
    {"--count", "N", c5_opt_long, offsetof(vec_args, count), 1, 1000000, 0,
     "vectors per block and source (random directed cases, scene samples, first cycles of a trace); default 256"},
    {"--seed", "N", c5_opt_long, offsetof(vec_args, seed), 0, 0x7fffffffL, 0,
     "seed of the random cases and samples (default 1)"},
    {"--size", "N|WxH", c5_opt_size, offsetof(vec_args, size), 0, 0, 0,
     "image size of the scenes (N: NxN; default 64x64)"},
    {"--cells", "N|NxMxK", c5_opt_cells, offsetof(vec_args, cells), 0, 0, 0,
     "cell split of the scenes (default 2: 8 cells)"},
    {"--vcd", NULL, c5_opt_flag, offsetof(vec_args, vcd), 0, 0, 0,
     "also each vector file's waveform, BLOCK.SOURCE.vcd: one clock cycle a vector on the testbenches' 10 ns "
     "clock, the fields as signals, to load beside GHDL's --vcd of the testbench in GTKWave (docs/vectors.md)"},
    {0},
};

const c5_cmd_spec c5_spec_vectors = {
    "vectors", NULL,
    "Writes input and expected-output vectors for every block of the board model into DIR: BLOCK.SOURCE.hex files "
    "(hex text, one vector per line, fixed columns) and manifest.json (each file's block, fields, widths, count, "
    "seed, scene and CRC-32; per scene the CRC-32s of its frame buffer, packet trace and DSP RAM). SOURCE is "
    "'directed' (corner cases) or a scene's name (taps on the model while it renders). The same options give the "
    "same bits on every run and machine. docs/vectors.md.",
    {{opts, 0}, {c5_progress_opts, 0}},
};

static int parse_args(int argc, char **argv, vec_args *a, c5_err *err)
{
    memset(a, 0, sizeof *a);
    a->out = "out/vectors";
    a->count = 256;
    a->seed = 1;
    a->size[0] = a->size[1] = 64;
    a->cells[0] = a->cells[1] = a->cells[2] = 2;
    if (c5_opt_parse(&c5_spec_vectors, argc, argv, a, NULL, err) != 0)
        return -1;
    if (a->no_scenes && a->n_scenes)
        return c5_fail(err, "--scene none cannot be combined with scenes");
    if (!a->no_scenes && !a->n_scenes)
        for (const c5_builtin_scene *b = c5_builtin_scenes; b->name && a->n_scenes < MAX_SCENES; b++)
            a->scenes[a->n_scenes++] = b->name;
    return 0;
}

/* The scene's name as a file name part: its built-in name, or the file's base name
 * without .json, with anything but [A-Za-z0-9_-] replaced by '_'. */
static void source_name(const char *arg, char *buf, size_t len)
{
    const char *base = strrchr(arg, '/');
    base = base ? base + 1 : arg;
    size_t n = 0;
    for (; base[n] && n + 1 < len; n++) {
        char c = base[n];
        buf[n] = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '_'
                     ? c
                     : '_';
    }
    buf[n] = 0;
    if (n > 5 && !strcmp(buf + n - 5, "_json"))
        buf[n - 5] = 0;
}

static json_t *run_scene(c5_vset *set, const vec_args *a, const char *arg, c5_err *err)
{
    static c5_scene s;
    c5_supervol sv = {0};
    char label[512], name[128];
    int cells[3] = {a->cells[0], a->cells[1], a->cells[2]};
    if (c5_cli_scene_setup(arg, NULL, a->size[0], a->size[1], &s, label, sizeof label, err) != 0 ||
        c5_cli_model_grid(&s, cells, label, &sv, err) != 0) {
        c5_supervol_free(&sv);
        return NULL;
    }
    source_name(arg, name, sizeof name);
    json_t *rec = c5_vec_scene(set, name, &s, &sv, cells);
    c5_supervol_free(&sv);
    return rec;
}

/* DIR is cleared of an earlier set and filled with files named here: none of its entries may
 * be a file the scenes read. Checked before the folder is touched. */
static int check_out_dir(const vec_args *a, c5_err *err)
{
    static c5_scene s;
    c5_file_list in = {0};
    char label[512];
    int rc = 0;
    for (int i = 0; i < a->n_scenes && !rc; i++)
        rc = c5_cli_load_scene(a->scenes[i], &s, label, sizeof label, err) != 0 ||
             c5_cli_scene_inputs(a->scenes[i], &s, &in, err) != 0;
    rc = rc || c5_cli_check_dir_out(a->out, &in, err) != 0;
    c5_file_list_free(&in);
    return rc ? -1 : 0;
}

int c5_cmd_vectors(int argc, char **argv)
{
    if (c5_opt_help(&c5_spec_vectors, argc, argv))
        return 0;
    c5_err err;
    vec_args a;
    c5_vset set;
    if (parse_args(argc, argv, &a, &err) != 0 || check_out_dir(&a, &err) != 0 || c5_vset_init(&set, a.out, (uint64_t)a.seed, a.count, &err) != 0) {
        fprintf(stderr, "cube5: error: %s\n", err.msg);
        return C5_EXIT_INPUT;
    }
    set.vcd = a.vcd;
    int rc = 0;
    c5_progress prog;
    c5_progress_begin(&prog, "vectors", c5_n_vblock_gens + a.n_scenes);
    for (int i = 0; i < c5_n_vblock_gens && rc == 0; i++) {
        rc = c5_vblock_gens[i]->directed(&set);
        c5_progress_step(&prog, i + 1, "%s: directed", c5_vblock_gens[i]->name);
    }
    json_t *scenes = json_array();
    for (int i = 0; i < a.n_scenes && rc == 0; i++) {
        json_t *rec = run_scene(&set, &a, a.scenes[i], &err);
        if (!rec)
            rc = -1;
        else
            json_array_append_new(scenes, rec);
        c5_progress_step(&prog, c5_n_vblock_gens + i + 1, "scene %s", a.scenes[i]);
    }
    c5_progress_end(&prog);
    if (rc != 0 || set.failed) {
        json_decref(scenes);
        c5_vset_abort(&set);
        fprintf(stderr, "cube5: error: %s\n", err.msg);
        return set.failed ? C5_EXIT_RUNTIME : C5_EXIT_INPUT;
    }
    json_t *params = json_pack("{s:[i,i], s:[i,i,i], s:o}", "size", a.size[0], a.size[1], "cells", a.cells[0], a.cells[1],
                               a.cells[2], "scenes", scenes);
    int n_files = (int)json_array_size(set.files);
    if (c5_vset_finish(&set, params) != 0) {
        fprintf(stderr, "cube5: error: %s\n", err.msg);
        return C5_EXIT_RUNTIME;
    }
    printf("cube5 vectors: %d files and manifest.json in %s (%d scene(s), seed %ld, count %ld)\n", n_files, a.out,
           a.n_scenes, a.seed, a.count);
    return 0;
}
