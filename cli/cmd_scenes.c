/* cube5 scenes: the built-in scenes, each parsed, so a broken one cannot ship unseen. */
#include <stdio.h>
#include <string.h>

#include "builtin_scenes.h"
#include "cli.h"
#include "generators.h"

static int count_kind(const c5_scene *s, c5_surface_kind k)
{
    int n = 0;
    for (int i = 0; i < s->n_surfaces; i++)
        n += s->surfaces[i].kind == k;
    return n;
}

const c5_cmd_spec c5_spec_scenes = {
    "scenes", NULL,
    "Lists the built-in scenes (the JSON files of scenes/, compiled in). Any of them can be given to 'cube5 "
    "render'; a scene's volume can be replaced by a real file with 'cube5 render SCENE --volume FILE'.",
    {{0}},
};

int c5_cmd_scenes(int argc, char **argv)
{
    c5_err err;
    if (c5_opt_help(&c5_spec_scenes, argc, argv))
        return 0;
    if (c5_opt_parse(&c5_spec_scenes, argc, argv, NULL, NULL, &err) != 0) {
        fprintf(stderr, "cube5: error: %s\n", err.msg);
        return C5_EXIT_INPUT;
    }
    int bad = 0;
    for (const c5_builtin_scene *b = c5_builtin_scenes; b->name; b++) {
        static c5_scene s;
        if (c5_scene_parse(b->json, NULL, b->name, &s, &err) != 0) {
            fprintf(stderr, "cube5: error: %s\n", err.msg);
            bad = 1;
            continue;
        }
        printf("%-16s %dx%d, %d frame(s); volumes:", b->name, s.render.width, s.render.height, c5_scene_frames(&s));
        for (int i = 0; i < s.n_volumes; i++)
            printf(" %s %zux%zux%zu", s.volumes[i].kind == C5_SRC_FILE ? "file" : c5_generator_name(s.volumes[i].generator), s.volumes[i].gen_dims[0],
                   s.volumes[i].gen_dims[1], s.volumes[i].gen_dims[2]);
        printf("; %d plane(s), %d rect(s), %d sphere(s), %d light(s)\n", count_kind(&s, C5_SURF_PLANE),
               count_kind(&s, C5_SURF_RECT), count_kind(&s, C5_SURF_SPHERE), s.n_lights);
    }
    return bad ? 1 : 0;
}
