#include "volume_inputs.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include "nrrd_precheck.h"

int c5_file_list_add(c5_file_list *l, const char *path, const char *what, c5_err *err)
{
    if (l->n == l->cap) {
        size_t cap = l->cap ? 2 * l->cap : 8;
        char **p = realloc(l->path, cap * sizeof *p);
        if (p)
            l->path = p;
        char **w = realloc(l->what, cap * sizeof *w);
        if (w)
            l->what = w;
        if (!p || !w)
            return c5_fail(err, "out of memory listing the input files");
        l->cap = cap;
    }
    char *ps = strdup(path), *ws = strdup(what);
    if (!ps || !ws) {
        free(ps);
        free(ws);
        return c5_fail(err, "out of memory listing the input files");
    }
    l->path[l->n] = ps;
    l->what[l->n++] = ws;
    return 0;
}

void c5_file_list_free(c5_file_list *l)
{
    for (size_t i = 0; i < l->n; i++) {
        free(l->path[i]);
        free(l->what[i]);
    }
    free(l->path);
    free(l->what);
    memset(l, 0, sizeof *l);
}

long c5_file_list_find(const c5_file_list *l, const char *path)
{
    struct stat so, si;
    if (stat(path, &so) != 0)
        return -1;
    for (size_t i = 0; i < l->n; i++)
        if (stat(l->path[i], &si) == 0 && si.st_dev == so.st_dev && si.st_ino == so.st_ino)
            return (long)i;
    return -1;
}

static int is_nrrd_name(const char *path)
{
    const char *base = strrchr(path, '/');
    const char *dot = strrchr(base ? base + 1 : path, '.');
    return dot && (!strcasecmp(dot, ".nrrd") || !strcasecmp(dot, ".nhdr"));
}

int c5_volume_input_files(const char *path, const char *what, c5_file_list *l, c5_err *err)
{
    if (c5_file_list_add(l, path, what, err) != 0)
        return -1;
    if (!is_nrrd_name(path))
        return 0;
    /* The precheck's header rules, without Teem and without reading the data (the load
     * checks it): they refuse several data files, so a header names at most one here. */
    c5_nrrd_header h;
    if (c5_nrrd_header_info(path, &h, err) != 0)
        return -1;
    if (!h.detached)
        return 0;
    char dwhat[1200];
    snprintf(dwhat, sizeof dwhat, "the data file of %s", path);
    return c5_file_list_add(l, h.data_path, dwhat, err);
}

int c5_scene_input_files(const char *scene_path, const c5_scene *s, c5_file_list *l, c5_err *err)
{
    if (scene_path && c5_file_list_add(l, scene_path, "the scene file", err) != 0)
        return -1;
    for (int i = 0; i < s->n_volumes; i++) {
        char what[32];
        snprintf(what, sizeof what, "volume %d", i);
        if (s->volumes[i].kind == C5_SRC_FILE && c5_volume_input_files(s->volumes[i].path, what, l, err) != 0)
            return -1;
    }
    return 0;
}
