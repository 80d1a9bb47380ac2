/* cube5: the command-line tool. One subcommand per job; `cube5 help CMD` (or `cube5 CMD
 * --help`) for each. Conventions shared with cube5ctl and cube5-board (README, "Conventions"):
 * errors as "cube5: error: ...", exit 0 ok, 1 failure while running, 2 bad input or usage. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

static const struct {
    const char *name;
    c5_cmd_fn fn;
    const c5_cmd_spec *spec;
    const char *summary;
} cmds[] = {
    {"cast", c5_cmd_cast, &c5_spec_cast, "the streaming-model volume ray caster over the peer benchmark's views (fps)"},
    {"compare", c5_cmd_compare, &c5_spec_compare, "render a frame with cref and the board model and compare the images"},
    {"render", c5_cmd_render, &c5_spec_render, "render a scene with cref or the board model (--model rtl)"},
    {"schedule", c5_cmd_schedule, &c5_spec_schedule, "the Cell Tree scheduler against Max Work over a scene's frames"},
    {"scenes", c5_cmd_scenes, &c5_spec_scenes, "list the built-in scenes"},
    {"sweep", c5_cmd_sweep, &c5_spec_sweep,
     "error against time over step, early termination, bounces, widths, the caster's k"},
    {"vectors", c5_cmd_vectors, &c5_spec_vectors, "golden vectors of every block for the VHDL testbenches"},
};
#define N_CMDS (sizeof cmds / sizeof cmds[0])

static void usage(FILE *f)
{
    fprintf(f, "usage: cube5 COMMAND [ARGS]\n       cube5 help [COMMAND] | --man | --version\n\ncommands:\n");
    for (size_t i = 0; i < N_CMDS; i++)
        fprintf(f, "  %-8s %s\n", cmds[i].name, cmds[i].summary);
    fprintf(f, "  %-8s %s\n", "help", "this text; 'cube5 help COMMAND' (or 'cube5 COMMAND --help') for a command;");
    fprintf(f, "  %-8s %s\n", "", "'cube5 help --man': the commands' section of the manual page, in roff");
    fprintf(f, "\nEvery command but scenes shows its progress on stderr when stderr is a terminal, and\n"
               "with --progress one line per step (never on stdout). Exit status: 0 ok, 1 a failure\n"
               "while running, 2 bad input or usage; errors read 'cube5: error: ...'.\n");
}

static long find_cmd(const char *name)
{
    for (size_t i = 0; i < N_CMDS; i++)
        if (!strcmp(name, cmds[i].name))
            return (long)i;
    return -1;
}

/* Several MPI ranks (mpirun -np N, N > 1): their count, or 1. Open MPI and MPICH's names. */
static int mpi_ranks(void)
{
    const char *names[] = {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"};
    for (int i = 0; i < 2; i++) {
        const char *v = getenv(names[i]);
        if (v && atoi(v) > 1)
            return atoi(v);
    }
    return 1;
}

/* Under several ranks only render, compare and schedule with --boards run (as several boards);
 * any other start would run the command once per rank into the same outputs. */
static int ranks_refused(const char *cmd, int argc, char **argv)
{
    int ranks = mpi_ranks();
    if (ranks < 2)
        return 0;
    int boards_cmd = !strcmp(cmd, "render") || !strcmp(cmd, "compare") || !strcmp(cmd, "schedule");
    for (int i = 2; boards_cmd && i < argc; i++)
        if (!strcmp(argv[i], "--boards"))
            return 0; /* its own check: the ranks must be its boards (docs/multi-board.md) */
    fprintf(stderr,
            "cube5: error: %s: started as %d MPI ranks; only render, compare and schedule run as several boards, "
            "with --boards %d (docs/multi-board.md); run %s once, without mpirun\n",
            cmd, ranks, ranks, cmd);
    return 1;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        usage(stderr);
        return C5_EXIT_INPUT;
    }
    if (!strcmp(argv[1], "--version")) {
        printf("cube5 %s\n", C5_VERSION);
        return 0;
    }
    if (!strcmp(argv[1], "help") || !strcmp(argv[1], "--help") || !strcmp(argv[1], "-h")) {
        if (argc == 2 || strcmp(argv[1], "help")) {
            usage(stdout);
            return 0;
        }
        if (!strcmp(argv[2], "--man") && argc == 3) { /* man/cube5.1's COMMANDS, from the tables */
            for (size_t i = 0; i < N_CMDS; i++)
                c5_opt_man(cmds[i].spec, stdout);
            return 0;
        }
        long c = find_cmd(argv[2]);
        if (c < 0 || argc > 3) {
            fprintf(stderr, "cube5: error: %s '%s' (see 'cube5 help')\n", c < 0 ? "unknown command" : "unexpected argument",
                    argv[c < 0 ? 2 : 3]);
            return C5_EXIT_INPUT;
        }
        char help[] = "--help", *sub[] = {argv[2], help, NULL};
        return cmds[c].fn(2, sub);
    }
    long c = find_cmd(argv[1]);
    if (c < 0) {
        fprintf(stderr, "cube5: error: unknown command '%s' (see 'cube5 help')\n", argv[1]);
        return C5_EXIT_INPUT;
    }
    if (ranks_refused(argv[1], argc, argv))
        return C5_EXIT_INPUT;
    int rc = cmds[c].fn(argc - 1, argv + 1);
    /* The summary or the --json object is an output too: written whole, or the run failed. */
    errno = 0;
    if (fflush(stdout) != 0 || ferror(stdout)) {
        fprintf(stderr, "cube5: error: standard output: cannot write: %s\n", strerror(errno ? errno : EIO));
        return rc ? rc : C5_EXIT_RUNTIME;
    }
    return rc;
}
