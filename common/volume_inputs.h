/* The files a volume reads: the file a scene or --volume names and, for a NRRD header, the
 * detached data files the header names. A command refuses an output path that is one of
 * them (nothing the user gave is overwritten). */
#ifndef C5_VOLUME_INPUTS_H
#define C5_VOLUME_INPUTS_H

#include <stddef.h>

#include "err.h"
#include "scene.h"

/* A list of input paths, each with what it is for messages ("volume 0", "the data file of
 * vol.nhdr"). */
typedef struct {
    char **path, **what;
    size_t n, cap;
} c5_file_list;

int c5_file_list_add(c5_file_list *l, const char *path, const char *what, c5_err *err);
void c5_file_list_free(c5_file_list *l);
/* The entry that `path` is the same file as (device and inode: through any name, symbolic or
 * hard link), or -1; a path or an entry that does not exist matches nothing. */
long c5_file_list_find(const c5_file_list *l, const char *path);

/* Adds `path` (described as `what`) and, when it is a .nrrd/.nhdr, the detached data file its
 * header names, resolved against the header's folder as Teem resolves it. The header goes
 * through c5_nrrd_header_info (never Teem): a header it refuses is refused here with its
 * message, as the volume load would refuse it, before any output is written. */
int c5_volume_input_files(const char *path, const char *what, c5_file_list *l, c5_err *err);

/* The scene file (scene_path; NULL for a built-in scene) and each file volume's files. */
int c5_scene_input_files(const char *scene_path, const c5_scene *s, c5_file_list *l, c5_err *err);

#endif
