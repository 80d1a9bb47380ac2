/* A built-in scene (by name) or a scene's JSON text, parsed and its volumes built, at a
 * square image size: the set-up of the tests that render the board model. */
#ifndef C5_TEST_SCENE_LOAD_H
#define C5_TEST_SCENE_LOAD_H

#include "scene.h"
#include "supervol.h"

/* 0, or -1 after printing the error; size <= 0 keeps the scene's image size. */
int c5t_load_scene(const char *json_or_name, int size, c5_scene *s, c5_supervol *sv);

#endif
