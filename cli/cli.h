/* Shared by the cube5 subcommands: option parsing, scene resolution, output safety. */
#ifndef C5_CLI_H
#define C5_CLI_H

#include <jansson.h>

#include "board.h"
#include "model_limits.h"
#include "opt_table.h"
#include "err.h"
#include "scene.h"
#include "supervol.h"
#include "volume_inputs.h"

/* Strict number parsing of option values: the whole string, in range, else an error
 * naming the option. */
int c5_cli_int(const char *opt, const char *s, long lo, long hi, long *out, c5_err *err);
int c5_cli_double(const char *opt, const char *s, double lo, double hi, double *out, c5_err *err);
/* "WxH" */
int c5_cli_size(const char *opt, const char *s, int *w, int *h, c5_err *err);

/* Cells per axis: a board's RDRAM holds one cell, and 64 per axis (262144 cells) is already
 * far past any split worth modelling; the option parser refuses more. */
#define C5_CLI_MAX_CELLS 64
/* "--cells N|NxMxK": N means NxNxN; each count in 1..C5_CLI_MAX_CELLS. */
int c5_cli_cells(const char *opt, const char *s, int cells[3], c5_err *err);
/* "--queue-key morton|fifo" */
int c5_cli_queue_key(const char *opt, const char *s, c5_queue_key *key, c5_err *err);
/* A split with more cells along an axis than the grid has voxels is refused (a cell must
 * hold at least one voxel); a scene without a volume takes any split. */
int c5_cli_check_cells(const int cells[3], const c5_supervol *sv, c5_err *err);
/* The scene's grid (c5_supervol_build), a refusal naming the scene (label). */
int c5_cli_grid(const c5_scene *s, const char *label, c5_supervol *sv, c5_err *err);
/* The grid the board model renders, in the order that refuses early: the model's field-width
 * limits before any volume is read or generated (c5_model_check_scene), the grid, the split
 * against it, then the limits that need the built grid (c5_model_check_grid). */
int c5_cli_model_grid(const c5_scene *s, int cells[3], const char *label, c5_supervol *sv, c5_err *err);
/* The board model's per-frame counters as the JSON object of 'render --json' and 'compare
 * --json'; the stages enabled as text ("gradients shadow ..." or "eye rays only"). */
json_t *c5_cli_board_json(const c5_board_stats *st);
void c5_cli_stages_text(const c5_board_stages *st, char *buf, size_t len);
const char *c5_cli_queue_key_name(c5_queue_key key);

/* A built-in scene name or a .json file. `label` receives "built-in scene NAME" or the path. */
int c5_cli_load_scene(const char *arg, c5_scene *s, char *label, size_t label_len, c5_err *err);
/* The "--volume [I=]FILE" options of a command, in order, for c5_cli_replace_volume. */
typedef struct {
    const char *path[C5_MAX_VOLUMES];
    int n;
} c5_cli_volumes;
/* "--volume [I=]FILE": replaces the source of volume I (default 0) with the file. */
int c5_cli_replace_volume(c5_scene *s, const char *arg, c5_err *err);
/* The scene a command works on: loaded, its volumes replaced, its image size w x h (0: the
 * scene's). */
int c5_cli_scene_setup(const char *arg, const c5_cli_volumes *volumes, int w, int h, c5_scene *s, char *label,
                       size_t label_len, c5_err *err);


/* Output safety (cli/outputs.c): every file a command reads, and the refusal, with exit 2
 * before anything is written, of an output that is one of them (by device and inode, so
 * through any name, link or hard link). */
/* Adds the scene file (not a built-in scene) and each volume's files (c5_volume_input_files). */
int c5_cli_scene_inputs(const char *scene_arg, const c5_scene *s, c5_file_list *in, c5_err *err);
int c5_cli_check_not_input(const char *out, const c5_file_list *in, c5_err *err);
/* An image output: .png or .exr, and no input. */
int c5_cli_check_image_out(const char *out, const c5_file_list *in, c5_err *err);
/* Every file `-o OUT` names over n frames (c5_cli_frame_path): .png or .exr, and no input. */
int c5_cli_check_frames_out(const char *out, int n, const c5_file_list *in, c5_err *err);
/* A folder a command writes files of its own naming into (and clears): none of its entries
 * may be an input. */
int c5_cli_check_dir_out(const char *dir, const c5_file_list *in, c5_err *err);
/* The scene's inputs, then c5_cli_check_frames_out: the images of render -o and compare --diff. */
int c5_cli_check_scene_image_out(const char *out, int n, const char *scene_arg, const c5_scene *s, c5_err *err);
/* Two outputs of one run that name one file (through links) are refused before any work:
 * `other` (option other_opt) against each file out_opt OUT names over n frames. */
int c5_cli_check_distinct_frames(const char *out, int n, const char *out_opt, const char *other, const char *other_opt,
                                 c5_err *err);
/* OUT for frame i of n: OUT itself when n == 1, else BASE_0007.EXT. */
void c5_cli_frame_path(const char *out, int i, int n, char *buf, size_t len);

/* The commands, and their option tables (for `cube5 help --man`). */
typedef int (*c5_cmd_fn)(int argc, char **argv);
extern const c5_cmd_spec c5_spec_cast, c5_spec_compare, c5_spec_render, c5_spec_schedule, c5_spec_scenes,
    c5_spec_sweep, c5_spec_vectors;
int c5_cmd_cast(int argc, char **argv);
int c5_cmd_compare(int argc, char **argv);
int c5_cmd_render(int argc, char **argv);
int c5_cmd_schedule(int argc, char **argv);
int c5_cmd_scenes(int argc, char **argv);
int c5_cmd_sweep(int argc, char **argv);
int c5_cmd_vectors(int argc, char **argv);

#endif
