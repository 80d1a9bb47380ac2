/* cube5: the command-line tool. One subcommand per job; `cube5 CMD --help` for each. */
#include <stdio.h>
#include <string.h>

#include "cli.h"

static const struct {
    const char *name;
    c5_cmd_fn fn;
    const char *summary;
} cmds[] = {
    {"cast", c5_cmd_cast, "the streaming-model volume ray caster over the peer benchmark's views (fps)"},
    {"compare", c5_cmd_compare, "render a frame with cref and the board model and compare the images"},
    {"render", c5_cmd_render, "render a scene with cref or the board model (--model rtl)"},
    {"schedule", c5_cmd_schedule, "the Cell Tree scheduler against Max Work over a scene's frames"},
    {"scenes", c5_cmd_scenes, "list the built-in scenes"},
    {"sweep", c5_cmd_sweep, "error against time over step, early termination, bounces, widths, the caster's k"},
    {"vectors", c5_cmd_vectors, "golden vectors of every block for the VHDL testbenches"},
};

static void usage(FILE *f)
{
    fprintf(f, "usage: cube5 COMMAND [ARGS]\n\ncommands:\n");
    for (size_t i = 0; i < sizeof cmds / sizeof cmds[0]; i++)
        fprintf(f, "  %-8s %s\n", cmds[i].name, cmds[i].summary);
    fprintf(f, "  %-8s %s\n", "help", "this text; 'cube5 COMMAND --help' for a command");
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        usage(stderr);
        return 2;
    }
    if (!strcmp(argv[1], "help") || !strcmp(argv[1], "--help") || !strcmp(argv[1], "-h")) {
        usage(stdout);
        return 0;
    }
    for (size_t i = 0; i < sizeof cmds / sizeof cmds[0]; i++)
        if (!strcmp(argv[1], cmds[i].name))
            return cmds[i].fn(argc - 1, argv + 1);
    fprintf(stderr, "cube5: error: unknown command '%s' (see 'cube5 help')\n", argv[1]);
    return 2;
}
