#include "volume_inputs.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <teem/nrrd.h>


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

/* One data file name as Teem opens it: "-" is standard input (no file), an absolute name
 * stays, a relative one is taken from the header's folder (nio->path). */
static int add_data_file(const NrrdIoState *nio, const char *name, const char *header, c5_file_list *l,
                         c5_err *err)
{
    if (!strcmp(name, "-"))
        return 0;
    char full[4096], what[1200];
    int n = name[0] != '/' && nio->path && *nio->path ? snprintf(full, sizeof full, "%s/%s", nio->path, name)
                                                       : snprintf(full, sizeof full, "%s", name);
    if (n < 0 || (size_t)n >= sizeof full)
        return c5_fail(err, "%s: a data file name is too long", header);
    snprintf(what, sizeof what, "a data file of %s", header);
    return c5_file_list_add(l, full, what, err);
}

/* The format comes from the file and is passed to snprintf with one int: exactly one
 * conversion "%[0-9]*d", no other '%'. */
static int one_int_conversion(const char *f)
{
    int convs = 0;
    for (const char *p = strchr(f, '%'); p; p = strchr(p, '%')) {
        p += 1 + strspn(p + 1, "0123456789");
        if (*p != 'd')
            return 0;
        convs++;
    }
    return convs == 1;
}

/* The names of "data file: FORMAT MIN MAX STEP": MIN, MIN+STEP, ... up to MAX. */
static int add_numbered(const NrrdIoState *nio, const char *header, c5_file_list *l, c5_err *err)
{
    long min = nio->dataFNMin, max = nio->dataFNMax, step = nio->dataFNStep;
    if (!step || (step > 0 ? max < min : max > min))
        return 0; /* Teem refuses such a header when the volume is loaded */
    if (!one_int_conversion(nio->dataFNFormat))
        return c5_fail(err, "%s: data file format '%s' must hold one %%d and no other %%", header,
                       nio->dataFNFormat);
    if ((step > 0 ? max - min : min - max) / (step > 0 ? step : -step) >= C5_NRRD_MAX_DATA_FILES)
        return c5_fail(err, "%s: names more than %d data files", header, C5_NRRD_MAX_DATA_FILES);
    for (long i = min; step > 0 ? i <= max : i >= max; i += step) {
        char name[4096];
        int n = snprintf(name, sizeof name, nio->dataFNFormat, (int)i);
        if (n < 0 || (size_t)n >= sizeof name)
            return c5_fail(err, "%s: a data file name is too long", header);
        if (add_data_file(nio, name, header, l, err) != 0)
            return -1;
    }
    return 0;
}

int c5_volume_input_files(const char *path, const char *what, c5_file_list *l, c5_err *err)
{
    if (c5_file_list_add(l, path, what, err) != 0)
        return -1;
    if (!is_nrrd_name(path))
        return 0;
    /* ==== NRRD GUARD: c5_nrrd_precheck(path, err) (common/volume.c) must run here, before
     * Teem reads the user's file; it refuses the headers Teem crashes or hangs on. ==== */
    Nrrd *n = nrrdNew();
    NrrdIoState *nio = nrrdIoStateNew();
    int rc = 0;
    if (!n || !nio) {
        rc = c5_fail(err, "%s: out of memory", path);
    } else {
        nio->skipData = AIR_TRUE;
        if (nrrdLoad(n, path, nio) != 0) {
            free(biffGetDone(NRRD)); /* the load that follows reports it */
        } else if (nio->dataFNFormat) {
            rc = add_numbered(nio, path, l, err);
        } else {
            for (unsigned i = 0; i < nio->dataFNArr->len && rc == 0; i++)
                rc = add_data_file(nio, nio->dataFN[i], path, l, err);
        }
    }
    nrrdIoStateNix(nio);
    nrrdNuke(n);
    return rc;
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
