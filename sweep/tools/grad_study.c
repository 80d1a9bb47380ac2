/* grad-study: the gradient study (sweep/grad_study.h, docs/accuracy.md "Gradients") on
 * built-in scenes or scene files. Prints one line per scene and renderer; --out DIR also
 * writes each scene's images (NAME_reference.png, NAME_central.png, NAME_spline.png,
 * NAME_board.png); --size N renders N x N. Deterministic: the same figures on any machine.
 * Usage: grad-study [--size N] [--out DIR] SCENE... */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "atomic_file.h"
#include "builtin_scenes.h"
#include "grad_study.h"
#include "supervol.h"

static const char *const NAMES[C5_GS_N] = {"central", "spline", "board"};

static int load(const char *arg, c5_scene *s, c5_err *err)
{
    const char *json = c5_builtin_scene_json(arg);
    if (json)
        return c5_scene_parse(json, NULL, arg, s, err);
    return c5_scene_load_file(arg, s, err);
}

static int write_images(const char *dir, const char *name, const c5_grad_study *r, c5_err *err)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/%s_reference.png", dir, name);
    if (c5_image_write(path, &r->ref, err) != 0)
        return -1;
    for (int i = 0; i < C5_GS_N; i++) {
        snprintf(path, sizeof path, "%s/%s_%s.png", dir, name, NAMES[i]);
        if (c5_image_write(path, &r->img[i], err) != 0)
            return -1;
    }
    return 0;
}

int main(int argc, char **argv)
{
    int size = 0, first = 1;
    const char *out = NULL;
    c5_err err = {0};
    while (first < argc && strncmp(argv[first], "--", 2) == 0) {
        if (strcmp(argv[first], "--size") == 0 && first + 1 < argc) {
            size = atoi(argv[first + 1]);
            if (size < 8 || size > 4096) {
                fprintf(stderr, "grad-study: error: --size: expected 8..4096, got '%s'\n", argv[first + 1]);
                return 2;
            }
        } else if (strcmp(argv[first], "--out") == 0 && first + 1 < argc) {
            out = argv[first + 1];
            if (c5_output_dir(out, &err) != 0) {
                fprintf(stderr, "grad-study: error: %s\n", err.msg);
                return 2;
            }
        } else {
            fprintf(stderr, "grad-study: error: unknown option '%s'\nusage: grad-study [--size N] [--out DIR] SCENE...\n",
                    argv[first]);
            return 2;
        }
        first += 2;
    }
    if (first >= argc) {
        fprintf(stderr, "usage: grad-study [--size N] [--out DIR] SCENE...\n");
        return 2;
    }
    printf("%-16s %-8s %9s %11s\n", "scene", "gradient", "PSNR dB", "fine error");
    for (int i = first; i < argc; i++) {
        static c5_scene s;
        c5_supervol sv;
        c5_grad_study r;
        if (load(argv[i], &s, &err) != 0) {
            fprintf(stderr, "grad-study: error: %s\n", err.msg);
            return 2;
        }
        if (size)
            s.render.width = s.render.height = size;
        if (c5_supervol_build(&s, &sv, &err) != 0 || c5_grad_study_run(&s, &sv, out != NULL, &r, &err) != 0) {
            fprintf(stderr, "grad-study: error: %s: %s\n", argv[i], err.msg);
            return 1;
        }
        for (int k = 0; k < C5_GS_N; k++)
            printf("%-16s %-8s %9.2f %11.5f\n", s.name, NAMES[k], r.psnr_db[k], r.fine[k]);
        if (out && write_images(out, s.name, &r, &err) != 0) {
            fprintf(stderr, "grad-study: error: %s\n", err.msg);
            return 1;
        }
        c5_grad_study_free(&r);
        c5_supervol_free(&sv);
    }
    return 0;
}
