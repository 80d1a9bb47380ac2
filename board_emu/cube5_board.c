/* cube5-board: runs a program with an emulated cube5 board plugged in on a umockdev USB bus
 * (board_emu/README.md). The program is any unmodified libusb program: it gets umockdev's
 * preload library and $UMOCKDEV_DIR, and finds the board as 1209:0001. */
#include <errno.h>
#include <signal.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include "emu_board.h"
#include "tlp.h"
#include "usb_device.h"

extern char **environ;

#define PRELOAD "libumockdev-preload.so.0"

static const char usage[] =
    "usage: cube5-board run [--serial S] [--fault KIND[:TYPE[:NTH[:REPEAT]]]] -- PROGRAM [ARGS...]\n"
    "       cube5-board --help | --version\n";

static const char help[] =
    "Runs PROGRAM with an emulated cube5 board (VID:PID 1209:0001) on a umockdev USB bus.\n"
    "PROGRAM is any libusb program: it runs with umockdev's preload library appended to\n"
    "LD_PRELOAD (an existing LD_PRELOAD, e.g. ASan's runtime, stays first) and UMOCKDEV_DIR\n"
    "set. cube5-board exits with PROGRAM's exit status (128+N when signal N killed it).\n"
    "\n"
    "  --serial S     the board's USB serial number (default C5EMU0001)\n"
    "  --fault SPEC   inject one link fault (docs/host-protocol.md):\n"
    "                 KIND   stall | short | timeout | disconnect | corrupt\n"
    "                 TYPE   the packet type it hits: reg_completion, dma_read, dma_write,\n"
    "                        interrupt, ... or its number; 0 or any: every packet (default)\n"
    "                 NTH    the nth such packet the board sends, from 1 (default 1)\n"
    "                 REPEAT stall only: consecutive stalls (default 1)\n"
    "\n"
    "Exit status 2: usage error; 1: the board could not be set up; 127: PROGRAM not run.\n";

static volatile pid_t child = -1;

static void forward(int sig)
{
    if (child > 0)
        kill(child, sig);
}

static int parse_uint(const char *s, unsigned *v)
{
    char *end;
    errno = 0;
    unsigned long x = strtoul(s, &end, 10);
    if (!*s || *end || errno || x > 0xffffffffUL || s[0] == '-')
        return -1;
    *v = (unsigned)x;
    return 0;
}

static int parse_fault(const char *spec, c5_fault *f, char *why, size_t cap)
{
    static const char *const kinds[] = {"none", "stall", "short", "timeout", "disconnect", "corrupt"};
    char buf[128];
    if (strlen(spec) >= sizeof buf)
        return snprintf(why, cap, "--fault %s: too long", spec), -1;
    strcpy(buf, spec);
    char *field[5] = {0};
    int n = 0;
    for (char *p = buf; n < 5; n++) {
        field[n] = p;
        p = strchr(p, ':');
        if (!p) {
            n++;
            break;
        }
        *p++ = 0;
    }
    if (n > 4)
        return snprintf(why, cap, "--fault %s: at most KIND:TYPE:NTH:REPEAT", spec), -1;
    memset(f, 0, sizeof *f);
    for (unsigned k = 1; k < sizeof kinds / sizeof kinds[0]; k++)
        if (strcmp(field[0], kinds[k]) == 0)
            f->kind = (c5_fault_kind)k;
    if (f->kind == C5_FAULT_NONE)
        return snprintf(why, cap, "--fault %s: unknown kind \"%s\" (stall, short, timeout, disconnect, corrupt)",
                        spec, field[0]), -1;
    if (n > 1 && *field[1] && strcmp(field[1], "any") != 0) {
        unsigned t = 0;
        for (unsigned i = C5_TLP_REG_READ; i <= C5_TLP_INTERRUPT; i++)
            if (strcmp(field[1], c5_tlp_type_name(i)) == 0)
                t = i;
        if (!t && (parse_uint(field[1], &t) || t > C5_TLP_INTERRUPT))
            return snprintf(why, cap, "--fault %s: unknown packet type \"%s\"", spec, field[1]), -1;
        f->type = t;
    }
    if (n > 2 && *field[2] && (parse_uint(field[2], &f->nth) || f->nth == 0))
        return snprintf(why, cap, "--fault %s: NTH \"%s\" is not a count from 1", spec, field[2]), -1;
    if (n > 3 && *field[3] && parse_uint(field[3], &f->repeat))
        return snprintf(why, cap, "--fault %s: REPEAT \"%s\" is not a number", spec, field[3]), -1;
    if (n > 3 && f->kind != C5_FAULT_STALL)
        return snprintf(why, cap, "--fault %s: REPEAT applies to stall only", spec), -1;
    return 0;
}

/* One line, as every cube5 tool's errors (README "Conventions"). */
static int usage_error(const char *fmt, const char *arg)
{
    fprintf(stderr, "cube5-board: error: ");
    fprintf(stderr, fmt, arg);
    fprintf(stderr, " (see cube5-board --help)\n");
    return 2;
}

/* LD_PRELOAD for the child: the existing list first (ASan's runtime must lead), then
 * umockdev's preload. An ASan-built child without ASan in LD_PRELOAD would refuse to start
 * ("runtime does not come first"); verify_asan_link_order=0 lets it run. */
static int set_child_env(void)
{
    const char *pre = getenv("LD_PRELOAD");
    if (!pre || !strstr(pre, "umockdev")) {
        size_t n = (pre ? strlen(pre) : 0) + sizeof PRELOAD + 2;
        char *v = malloc(n);
        if (!v)
            return -1;
        snprintf(v, n, "%s%s%s", pre && *pre ? pre : "", pre && *pre ? ":" : "", PRELOAD);
        setenv("LD_PRELOAD", v, 1);
        free(v);
        pre = getenv("LD_PRELOAD");
    }
    const char *asan = getenv("ASAN_OPTIONS");
    if (!strstr(pre, "libasan") && (!asan || !strstr(asan, "verify_asan_link_order"))) {
        size_t n = (asan ? strlen(asan) : 0) + 40;
        char *v = malloc(n);
        if (!v)
            return -1;
        snprintf(v, n, "%s%sverify_asan_link_order=0", asan && *asan ? asan : "", asan && *asan ? ":" : "");
        setenv("ASAN_OPTIONS", v, 1);
        free(v);
    }
    return 0;
}

static int run(int argc, char **argv)
{
    const char *serial = NULL;
    c5_fault fault = {0};
    int have_fault = 0, i = 0;
    char why[256];
    for (; i < argc; i++) {
        if (strcmp(argv[i], "--") == 0) {
            i++;
            break;
        }
        if (strcmp(argv[i], "--serial") == 0 || strcmp(argv[i], "--fault") == 0) {
            if (i + 1 >= argc || strcmp(argv[i + 1], "--") == 0)
                return usage_error("%s needs a value", argv[i]);
            if (argv[i][2] == 's') {
                serial = argv[++i];
                if (!*serial || strlen(serial) > 126)
                    return usage_error("--serial \"%s\": 1 to 126 characters", serial);
            } else {
                if (parse_fault(argv[++i], &fault, why, sizeof why))
                    return usage_error("%s", why);
                have_fault = 1;
            }
        } else if (argv[i][0] == '-') {
            return usage_error("unknown option %s", argv[i]);
        } else {
            break; /* PROGRAM without "--" */
        }
    }
    if (i >= argc)
        return usage_error("%s", "run: no PROGRAM given");

    prctl(PR_SET_TIMERSLACK, 1UL); /* the preload sleeps after every emulated ioctl; inherited */
    if (set_child_env()) {
        fprintf(stderr, "cube5-board: error: out of memory\n");
        return 1;
    }
    c5_emu *board = c5_emu_new(serial);
    if (!board) {
        fprintf(stderr, "cube5-board: error: could not create the board\n");
        return 1;
    }
    if (have_fault)
        c5_emu_set_fault(board, &fault);
    c5_usb_device *usb = c5_usb_device_new(board, why, sizeof why);
    if (!usb) {
        fprintf(stderr, "cube5-board: error: %s\n", why);
        c5_emu_free(board);
        return 1;
    }

    struct sigaction sa = {0};
    sa.sa_handler = forward;
    sigemptyset(&sa.sa_mask);
    int sigs[] = {SIGINT, SIGTERM, SIGHUP, SIGQUIT};
    for (size_t s = 0; s < sizeof sigs / sizeof sigs[0]; s++)
        sigaction(sigs[s], &sa, NULL);

    pid_t pid;
    int status = 0, rc;
    int e = posix_spawnp(&pid, argv[i], NULL, NULL, argv + i, environ);
    if (e) {
        fprintf(stderr, "cube5-board: error: %s: %s\n", argv[i], strerror(e));
        rc = 127;
    } else {
        child = pid;
        while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
        }
        child = -1;
        rc = WIFEXITED(status) ? WEXITSTATUS(status) : WIFSIGNALED(status) ? 128 + WTERMSIG(status) : 1;
    }
    c5_usb_device_free(usb);
    c5_emu_free(board);
    return rc;
}

int main(int argc, char **argv)
{
    if (argc >= 2 && (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0)) {
        fputs(usage, stdout);
        fputs("\n", stdout);
        fputs(help, stdout);
        return 0;
    }
    if (argc >= 2 && strcmp(argv[1], "--version") == 0) {
        printf("cube5-board %s\n", C5_VERSION);
        return 0;
    }
    if (argc < 2) { /* nothing asked: the usage, as cube5 gives it */
        fputs(usage, stderr);
        return 2;
    }
    if (strcmp(argv[1], "run") != 0)
        return usage_error("unknown command \"%s\"", argv[1]);
    return run(argc - 2, argv + 2);
}
