/* The grid's spacing rule (docs/scene-format.md, "Spacing"): the scene's grid.spacing when
 * given, else the volume files' own spacing (which must agree), else 1 1 1. */
#include <stdio.h>
#include <string.h>

#include "harness.h"
#include "scene.h"
#include "supervol.h"

static int write_nrrd(const char *name, const char *spacing_line)
{
    FILE *f = fopen(c5t_path(0, name), "wb");
    if (!f)
        return -1;
    fprintf(f, "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\n%sencoding: raw\n\n", spacing_line);
    fwrite("\1\2\3\4\5\6\7\10", 1, 8, f);
    return fclose(f);
}

/* Builds the super volume of a scene with these volumes and grid; 0 or -1 (err). */
static int build(const char *volumes, const char *grid, c5_supervol *sv, c5_err *err)
{
    char json[1024];
    snprintf(json, sizeof json,
             "{'volumes': [%s], 'grid': {%s}, 'transfer_function': {'opacity': [[0,0],[255,1]], "
             "'color': [[0,1,1,1]]}, 'camera': {'eye': [30,30,30], 'target': [1,1,1], 'width': 4, 'height': 4}}",
             volumes, grid);
    c5_scene s;
    if (c5_scene_parse(c5t_json(json), c5t_tmpdir(), "spacing.json", &s, err) != 0)
        return -1;
    return c5_supervol_build(&s, sv, err);
}

TEST(spacing_from_the_file_unless_the_scene_gives_one)
{
    CHECK(write_nrrd("aniso.nrrd", "spacings: 1 1 3\n") == 0);
    c5_supervol sv;
    c5_err e = {{0}};
    CHECK_MSG(build("{'file': 'aniso.nrrd'}", "", &sv, &e) == 0, "%s", e.msg);
    CHECK_NEAR(sv.spacing.x, 1, 0);
    CHECK_NEAR(sv.spacing.z, 3, 0);
    CHECK(strcmp(sv.spacing_source, "file aniso.nrrd") == 0);
    c5_supervol_free(&sv);
    /* grid.size scales the file's spacing uniformly: the aspect stays */
    CHECK_MSG(build("{'file': 'aniso.nrrd'}", "'size': 12", &sv, &e) == 0, "%s", e.msg);
    CHECK_NEAR(sv.spacing.z / sv.spacing.x, 3, 1e-12);
    CHECK_NEAR(sv.dims[2] * sv.spacing.z, 12, 1e-9);
    c5_supervol_free(&sv);
    /* the scene's grid.spacing, when given, wins over the file's */
    CHECK_MSG(build("{'file': 'aniso.nrrd'}", "'spacing': [2, 2, 2]", &sv, &e) == 0, "%s", e.msg);
    CHECK_NEAR(sv.spacing.z, 2, 0);
    CHECK(strcmp(sv.spacing_source, "scene") == 0);
    c5_supervol_free(&sv);
}

TEST(spacing_default_and_disagreeing_files)
{
    CHECK(write_nrrd("plain.nrrd", "") == 0);
    CHECK(write_nrrd("a.nrrd", "spacings: 1 1 3\n") == 0);
    CHECK(write_nrrd("b.nrrd", "spacings: 1 1 2\n") == 0);
    c5_supervol sv;
    c5_err e = {{0}};
    CHECK_MSG(build("{'file': 'plain.nrrd'}", "", &sv, &e) == 0, "%s", e.msg);
    CHECK_NEAR(sv.spacing.z, 1, 0);
    CHECK(strcmp(sv.spacing_source, "default") == 0);
    c5_supervol_free(&sv);
    /* a file without spacing next to one with: the one that states it */
    CHECK_MSG(build("{'file': 'plain.nrrd'}, {'file': 'a.nrrd', 'offset': [2, 0, 0]}", "", &sv, &e) == 0, "%s",
              e.msg);
    CHECK(strcmp(sv.spacing_source, "file a.nrrd") == 0);
    c5_supervol_free(&sv);
    CHECK(build("{'file': 'a.nrrd'}, {'file': 'b.nrrd', 'offset': [2, 0, 0]}", "", &sv, &e) == -1);
    CHECK_HAS(e.msg, "b.nrrd: spacing 1 1 2 differs from ");
    CHECK_HAS(e.msg, "a.nrrd's 1 1 3: the grid has one spacing (give grid.spacing in the scene)");
    /* and grid.spacing settles it */
    CHECK_MSG(build("{'file': 'a.nrrd'}, {'file': 'b.nrrd', 'offset': [2, 0, 0]}", "'spacing': [1, 1, 1]", &sv,
                    &e) == 0, "%s", e.msg);
    c5_supervol_free(&sv);
}
