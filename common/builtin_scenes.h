/* The scenes compiled into the binary, from the JSON files in scenes/ (see scripts/embed-scenes.sh). */
#ifndef C5_BUILTIN_SCENES_H
#define C5_BUILTIN_SCENES_H

typedef struct {
    const char *name;
    const char *json;
} c5_builtin_scene;

/* Terminated by an entry whose name is NULL. */
extern const c5_builtin_scene c5_builtin_scenes[];

/* The scene's JSON text, or NULL when there is no built-in scene of that name. */
const char *c5_builtin_scene_json(const char *name);

#endif
