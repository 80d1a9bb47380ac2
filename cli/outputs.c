/* Output safety: nothing the user gave is overwritten. A command lists the files it reads
 * (the scene file, each volume file, the data files a NRRD header names) and checks every
 * path it will write against them before it writes anything. */
#include <dirent.h>
#include <limits.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>

#include "atomic_file.h"
#include "builtin_scenes.h"
#include "cli.h"

int c5_cli_scene_inputs(const char *scene_arg, const c5_scene *s, c5_file_list *in, c5_err *err)
{
    return c5_scene_input_files(c5_builtin_scene_json(scene_arg) ? NULL : scene_arg, s, in, err);
}

int c5_cli_check_not_input(const char *out, const c5_file_list *in, c5_err *err)
{
    long i = c5_file_list_find(in, out);
    if (i >= 0)
        return c5_fail(err, "%s: is %s (%s); refusing to overwrite an input", out, in->what[i], in->path[i]);
    return 0;
}

int c5_cli_check_image_out(const char *out, const c5_file_list *in, c5_err *err)
{
    return c5_cli_check_not_input(out, in, err) != 0 ? -1 : c5_image_check_out(out, err);
}

int c5_cli_check_frames_out(const char *out, int n, const c5_file_list *in, c5_err *err)
{
    /* the files written: OUT itself for one frame, OUT_0000.EXT ... for several */
    for (int f = 0; f < (n > 1 ? n : 1); f++) {
        char path[2048];
        c5_cli_frame_path(out, f, n, path, sizeof path);
        if (c5_cli_check_image_out(path, in, err) != 0)
            return -1;
    }
    return 0;
}

int c5_cli_check_dir_out(const char *dir, const c5_file_list *in, c5_err *err)
{
    DIR *d = opendir(dir);
    if (!d)
        return 0; /* not there yet: it holds nothing; anything else is reported on writing */
    int rc = 0;
    for (struct dirent *e; rc == 0 && (e = readdir(d)) != NULL;) {
        char path[4200];
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        long i = strcmp(e->d_name, ".") && strcmp(e->d_name, "..") ? c5_file_list_find(in, path) : -1;
        if (i >= 0)
            rc = c5_fail(err, "%s: holds %s (%s); refusing to write into a folder with an input", dir, in->what[i],
                         in->path[i]);
    }
    closedir(d);
    return rc;
}

/* The file a path names, resolved through links: the path itself when it exists, else its
 * folder's real path and its name. Empty when neither resolves (the write reports it). */
static void canonical(const char *given, char *out, size_t len)
{
    char real[PATH_MAX], path[PATH_MAX];
    out[0] = 0;
    if (c5_output_target(given, path, sizeof path) != 0)
        return;
    if (realpath(path, real)) {
        snprintf(out, len, "%s", real);
        return;
    }
    const char *slash = strrchr(path, '/');
    char dir[PATH_MAX];
    snprintf(dir, sizeof dir, "%.*s", slash ? (int)(slash - path) + (slash == path) : 1, slash ? path : ".");
    if (realpath(dir, real))
        snprintf(out, len, "%s/%s", real, slash ? slash + 1 : path);
}

int c5_cli_check_distinct_frames(const char *out, int n, const char *out_opt, const char *other, const char *other_opt,
                                 c5_err *err)
{
    char b[2 * PATH_MAX + 8];
    canonical(other, b, sizeof b);
    for (int f = 0; b[0] && f < n; f++) {
        char path[2048], a[2 * PATH_MAX + 8];
        c5_cli_frame_path(out, f, n, path, sizeof path);
        canonical(path, a, sizeof a);
        if (!strcmp(a, b))
            return c5_fail(err, "%s %s: names the same file as %s %s; give two different files", other_opt, other,
                           out_opt, path);
    }
    return 0;
}

int c5_cli_check_scene_image_out(const char *out, int n, const char *scene_arg, const c5_scene *s, c5_err *err)
{
    c5_file_list in = {0};
    int rc = c5_cli_scene_inputs(scene_arg, s, &in, err) != 0 || c5_cli_check_frames_out(out, n, &in, err) != 0;
    c5_file_list_free(&in);
    return rc ? -1 : 0;
}
