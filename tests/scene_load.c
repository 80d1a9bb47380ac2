#include "scene_load.h"

#include <stdio.h>

#include "builtin_scenes.h"

int c5t_load_scene(const char *json_or_name, int size, c5_scene *s, c5_supervol *sv)
{
    c5_err err;
    const char *json = c5_builtin_scene_json(json_or_name);
    if (c5_scene_parse(json ? json : json_or_name, NULL, "test", s, &err) != 0 ||
        c5_supervol_build(s, sv, &err) != 0) {
        fprintf(stderr, "load: %s\n", err.msg);
        return -1;
    }
    if (size > 0)
        s->render.width = s->render.height = size;
    return 0;
}
