/* Harness: the scene parser (common/scene_parse.c) on any text. Promise: 0, or -1 with a
 * one-line message; a parsed scene's camera path can be evaluated at every frame. */
#include "fuzz.h"
#include "scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = malloc(size + 1);
    if (!text)
        return 0;
    memcpy(text, data, size);
    text[size] = 0;
    /* file volumes resolve against a folder that does not exist: parsing reads no file */
    static c5_scene s;
    c5_err err = {{0}};
    int rc = c5_scene_parse(text, "/nonexistent-fuzz-dir", "fuzz.json", &s, &err);
    c5_fuzz_expect(rc == 0 || rc == -1, "c5_scene_parse returns 0 or -1");
    if (rc != 0) {
        c5_fuzz_expect(c5_fuzz_one_line(err.msg, sizeof err.msg), "a one-line error message");
    } else {
        int frames = c5_scene_frames(&s);
        c5_fuzz_expect(frames >= 1, "a scene has at least one frame");
        for (int f = 0; f < frames && f < 64; f++)
            (void)c5_scene_camera_at(&s, f);
    }
    free(text);
    return 0;
}
