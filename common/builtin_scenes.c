#include "builtin_scenes.h"

#include <string.h>

const char *c5_builtin_scene_json(const char *name)
{
    for (const c5_builtin_scene *b = c5_builtin_scenes; b->name; b++)
        if (strcmp(b->name, name) == 0)
            return b->json;
    return NULL;
}
