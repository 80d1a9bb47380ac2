/* The files a volume reads: the file a scene or --volume names and, for a NRRD header, the
 * detached data files the header names. A command refuses an output path that is one of
 * them (nothing the user gave is overwritten). */
#ifndef C5_VOLUME_INPUTS_H
#define C5_VOLUME_INPUTS_H

#include <stddef.h>

#include "err.h"
#include "scene.h"

/* More data files than this in one header is refused: a 3-D volume within the loader's
 * limits never needs them, and the list is built before any voxel is read. */
#define C5_NRRD_MAX_DATA_FILES 65536

/* A list of input paths, each with what it is for messages ("volume 0", "a data file of
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

/* Adds `path` (described as `what`) and, when it is a .nrrd/.nhdr, every data file its header
 * names: the single "data file:", each name of "data file: LIST", and each number of the
 * printf-style "data file: NAME%d MIN MAX STEP" form, relative names resolved against the
 * header's folder as Teem resolves them. The header is read by Teem without its data. A
 * header Teem cannot read adds no data files: the volume load that follows refuses it, with
 * Teem's reason, before any output is written. */
int c5_volume_input_files(const char *path, const char *what, c5_file_list *l, c5_err *err);

/* The scene file (scene_path; NULL for a built-in scene) and each file volume's files. */
int c5_scene_input_files(const char *scene_path, const c5_scene *s, c5_file_list *l, c5_err *err);

#endif
