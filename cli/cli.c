#include "cli.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "builtin_scenes.h"

int c5_cli_int(const char *opt, const char *s, long lo, long hi, long *out, c5_err *err)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (!*s || *end || errno || v < lo || v > hi)
        return c5_fail(err, "%s: expected an integer in [%ld, %ld], got '%s'", opt, lo, hi, s);
    *out = v;
    return 0;
}

int c5_cli_double(const char *opt, const char *s, double lo, double hi, double *out, c5_err *err)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (!*s || *end || errno || !isfinite(v) || v < lo || v > hi)
        return c5_fail(err, "%s: expected a number in [%g, %g], got '%s'", opt, lo, hi, s);
    *out = v;
    return 0;
}

int c5_cli_size(const char *opt, const char *s, int *w, int *h, c5_err *err)
{
    char buf[64];
    const char *x = strchr(s, 'x');
    long a, b;
    if (!x) { /* N: a square N x N */
        if (c5_cli_int(opt, s, 1, C5_MAX_IMAGE_DIM, &a, err) != 0)
            return c5_fail(err, "%s: expected N or WxH, got '%s'", opt, s);
        *w = *h = (int)a;
        return 0;
    }
    if ((size_t)(x - s) >= sizeof buf)
        return c5_fail(err, "%s: expected N or WxH, got '%s'", opt, s);
    memcpy(buf, s, (size_t)(x - s));
    buf[x - s] = 0;
    if (c5_cli_int(opt, buf, 1, C5_MAX_IMAGE_DIM, &a, err) || c5_cli_int(opt, x + 1, 1, C5_MAX_IMAGE_DIM, &b, err))
        return -1;
    *w = (int)a;
    *h = (int)b;
    return 0;
}

int c5_cli_load_scene(const char *arg, c5_scene *s, char *label, size_t label_len, c5_err *err)
{
    const char *json = c5_builtin_scene_json(arg);
    if (json) {
        snprintf(label, label_len, "built-in scene %s", arg);
        return c5_scene_parse(json, NULL, label, s, err);
    }
    size_t n = strlen(arg);
    if (n < 5 || strcmp(arg + n - 5, ".json") != 0)
        return c5_fail(err, "'%s' is neither a built-in scene (see 'cube5 scenes') nor a .json file", arg);
    snprintf(label, label_len, "%s", arg);
    return c5_scene_load_file(arg, s, err);
}

int c5_cli_replace_volume(c5_scene *s, const char *arg, c5_err *err)
{
    long idx = 0;
    const char *path = arg, *eq = strchr(arg, '=');
    if (eq && eq > arg && eq - arg < 4) {
        char num[4] = {0};
        memcpy(num, arg, (size_t)(eq - arg));
        if (c5_cli_int("--volume", num, 0, C5_MAX_VOLUMES - 1, &idx, err) != 0)
            return -1;
        path = eq + 1;
    }
    if (idx >= s->n_volumes)
        return c5_fail(err, "--volume: the scene has %d volume(s), no volume %ld", s->n_volumes, idx);
    if (strlen(path) >= sizeof s->volumes[0].path)
        return c5_fail(err, "--volume: path too long");
    c5_volume_desc *d = &s->volumes[idx];
    long off[3] = {d->offset[0], d->offset[1], d->offset[2]};
    memset(d, 0, sizeof *d);
    d->kind = C5_SRC_FILE;
    strcpy(d->path, path);
    memcpy(d->offset, off, sizeof off);
    return 0;
}

void c5_cli_frame_path(const char *out, int i, int n, char *buf, size_t len)
{
    if (n <= 1) {
        snprintf(buf, len, "%s", out);
        return;
    }
    const char *dot = strrchr(out, '.'), *slash = strrchr(out, '/');
    if (!dot || (slash && dot < slash))
        dot = out + strlen(out);
    snprintf(buf, len, "%.*s_%04d%s", (int)(dot - out), out, i, dot);
}

int c5_cli_cells(const char *opt, const char *s, int cells[3], c5_err *err)
{
    char part[3][16];
    int n = 0;
    const char *p = s;
    for (;;) {
        const char *x = strchr(p, 'x');
        size_t len = x ? (size_t)(x - p) : strlen(p);
        if (n == 3 || len >= sizeof part[0])
            goto bad;
        memcpy(part[n], p, len);
        part[n++][len] = 0;
        if (!x)
            break;
        p = x + 1;
    }
    if (n == 2)
        goto bad;
    for (int a = 0; a < 3; a++) {
        long v;
        if (c5_cli_int(opt, part[n == 1 ? 0 : a], 1, C5_CLI_MAX_CELLS, &v, err) != 0)
            goto bad;
        cells[a] = (int)v;
    }
    return 0;
bad:
    return c5_fail(err, "%s: expected N or NxMxK, cells per axis each in [1, %d], got '%s'", opt, C5_CLI_MAX_CELLS,
                   s);
}

int c5_cli_queue_key(const char *opt, const char *s, c5_queue_key *key, c5_err *err)
{
    if (!strcmp(s, "morton"))
        *key = C5_KEY_MORTON;
    else if (!strcmp(s, "fifo"))
        *key = C5_KEY_FIFO;
    else
        return c5_fail(err, "%s: expected morton or fifo, got '%s'", opt, s);
    return 0;
}

const char *c5_cli_queue_key_name(c5_queue_key key)
{
    return key == C5_KEY_FIFO ? "fifo" : "morton"; /* 0 means the default, Morton */
}

int c5_cli_check_cells(const int cells[3], const c5_supervol *sv, c5_err *err)
{
    if (c5_supervol_empty(sv))
        return 0;
    for (int a = 0; a < 3; a++)
        if ((size_t)cells[a] > sv->dims[a])
            return c5_fail(err, "--cells: %d cells along %c but the grid has only %zu voxels there", cells[a],
                           "xyz"[a], sv->dims[a]);
    return 0;
}

int c5_cli_grid(const c5_scene *s, const char *label, c5_supervol *sv, c5_err *err)
{
    if (c5_supervol_build(s, sv, err) == 0)
        return 0;
    size_t n = strlen(label);
    if (strncmp(err->msg, label, n) != 0) { /* the scene the refusal is about */
        char msg[sizeof err->msg];
        snprintf(msg, sizeof msg, "%s", err->msg);
        c5_fail(err, "%s: %s", label, msg);
    }
    return -1;
}

int c5_cli_model_grid(const c5_scene *s, int cells[3], const char *label, c5_supervol *sv, c5_err *err)
{
    if (c5_model_check_scene(s, cells, label, err) != 0 || c5_cli_grid(s, label, sv, err) != 0)
        return -1;
    c5_model_auto_split(sv->dims, cells);
    return c5_cli_check_cells(cells, sv, err) != 0 || c5_model_check_grid(s, sv, cells, label, err) != 0 ? -1 : 0;
}

json_t *c5_cli_board_json(const c5_board_stats *st)
{
    const c5_board_stages *g = &st->stages;
    json_t *stages = json_pack("{s:i, s:i, s:i, s:i, s:i}", "gradients", g->gradients, "shadow", g->shadow, "reflect",
                               g->reflect, "refract", g->refract, "scheduling", g->scheduling);
    json_t *o = json_object();
    /* Counters one by one: json_pack's format would be longer than the list. */
    const struct {
        const char *key;
        uint64_t v;
    } n[] = {
        {"cycles", st->cycles},           {"cycles_process", st->cycles_process},
        {"cycles_fetch", st->cycles_fetch}, {"fetches", st->fetches},
        {"fetch_bytes", st->fetch_bytes}, {"bus_packets", st->bus_packets},
        {"spills", st->spills},           {"queue_pops", st->queue_pops},
        {"queue_max", st->queue_max},     {"cache_hits", st->cache_hits},
        {"cache_misses", st->cache_misses}, {"saturations", st->saturations},
        {"samples_leaped", st->samples_leaped}, {"tree_nodes", st->tree_nodes},
        {"tree_slots", st->tree_slots},   {"tree_tags", st->tree_tags},
        {"tree_demand_nodes", st->tree_demand_nodes}, {"tree_demand_slots", st->tree_demand_slots},
        {"tree_demand_slots6", st->tree_demand_slots6}, {"lower_bound_demand", st->tree_demand_sum_maxgen},
        {"tree_reads", st->tree_reads},   {"tree_writes", st->tree_writes},
        {"host_helper_runs", st->helper_runs},
        {"host_helper_wakes", st->helper_wakes},
    };
    for (size_t i = 0; i < sizeof n / sizeof n[0]; i++)
        json_object_set_new(o, n[i].key, json_integer((json_int_t)n[i].v));
    json_object_set_new(o, "board_s", json_real(st->board_s));
    json_object_set_new(o, "cells", json_integer(st->cells));
    json_object_set_new(o, "tree_overflow", json_boolean(st->tree_overflow));
    json_object_set_new(o, "stages", stages);
    return o;
}

void c5_cli_stages_text(const c5_board_stages *st, char *buf, size_t len)
{
    const struct {
        const char *name;
        int on;
    } s[] = {{"gradients", st->gradients}, {"shadow", st->shadow},         {"reflect", st->reflect},
             {"refract", st->refract},     {"scheduling", st->scheduling}};
    size_t at = 0;
    buf[0] = 0;
    for (size_t i = 0; i < sizeof s / sizeof s[0]; i++)
        if (s[i].on && at < len)
            at += (size_t)snprintf(buf + at, len - at, "%s%s", at ? " " : "", s[i].name);
    if (!at)
        snprintf(buf, len, "eye rays only");
}

int c5_cli_scene_setup(const char *arg, const c5_cli_volumes *volumes, int w, int h, c5_scene *s, char *label,
                       size_t label_len, c5_err *err)
{
    if (c5_cli_load_scene(arg, s, label, label_len, err) != 0)
        return -1;
    for (int i = 0; volumes && i < volumes->n; i++)
        if (c5_cli_replace_volume(s, volumes->path[i], err) != 0)
            return -1;
    if (w) {
        s->render.width = w;
        s->render.height = h;
    }
    return 0;
}
