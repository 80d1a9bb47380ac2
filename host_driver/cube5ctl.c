/* cube5ctl: drives a cube5 board (real or emulated, it cannot tell) through the host driver.
 * Errors: one line "cube5ctl: error: <message>" on stderr; exit 2 for bad input or usage (an
 * option, the scene, an output over an input), 1 for a failure while running (the board, the
 * link, writing the image). */
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "builtin_scenes.h"
#include "c5drv.h"
#include "image.h"
#include "scene.h"
#include "tlp.h"
#include "volume_inputs.h"

#define EXIT_FAIL 1
#define EXIT_USAGE 2
#define DEFAULT_TIMEOUT_MS 120000u
#define MAX_CELLS 64 /* the model's split limit per axis is far lower; this only bounds parsing */

static const char usage[] =
    "usage: cube5ctl [--device VID:PID[:SERIAL]] [--timeout MS] COMMAND\n"
    "       cube5ctl --help | --version\n"
    "  info                         the board's id, register map version and serial number\n"
    "  render SCENE -o OUT [--frame N] [--cells N|NxMxK] [--size N|WxH] [--json]\n"
    "                               renders a frame of SCENE (a built-in scene name or a .json\n"
    "                               file) on the board into OUT (.png or .exr)\n"
    "  stats [--json]               the board's counters of its last frame\n"
    "options:\n"
    "  --device VID:PID[:SERIAL]    hex ids, default 1209:0001, the first board found\n"
    "  --timeout MS                 how long a frame may take, default 120000\n";

typedef struct {
    const char *cmd, *scene, *out, *serial;
    unsigned vid, pid, timeout_ms;
    int frame, have_frame, cells[3], have_cells, w, h, json;
} opts;

/* One error line; returns the exit status: fail() for a failure while running (1),
 * bad_input() for the scene or the output path (2). */
static int failure(int status, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static int failure(int status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "cube5ctl: error: ");
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    return status;
}
#define fail(...) failure(EXIT_FAIL, __VA_ARGS__)
#define bad_input(...) failure(EXIT_USAGE, __VA_ARGS__)

/* s as a JSON string body: quotes, backslashes and control characters dropped (a serial
 * number holds none of them). */
static void json_safe(const char *s)
{
    for (; *s; s++)
        if (*s != '"' && *s != '\\' && (unsigned char)*s >= 0x20)
            putchar(*s);
}

static int usage_err(const char *what, const char *arg)
{
    fprintf(stderr, "cube5ctl: error: %s%s%s (see cube5ctl --help)\n", what, arg ? " " : "", arg ? arg : "");
    return EXIT_USAGE;
}

/* A whole string as an unsigned number in [lo, hi] of the given base. */
static int parse_num(const char *s, int base, unsigned long lo, unsigned long hi, unsigned long *out)
{
    char *end;
    errno = 0;
    if (!*s || *s == '-' || *s == '+')
        return -1;
    unsigned long v = strtoul(s, &end, base);
    if (errno || *end || v < lo || v > hi)
        return -1;
    *out = v;
    return 0;
}

/* "N" or "NxMxK" (also "WxH" when n == 2). */
static int parse_dims(const char *s, int n_max, unsigned long hi, int *v, int *n)
{
    char buf[64];
    if (strlen(s) >= sizeof buf)
        return -1;
    strcpy(buf, s);
    *n = 0;
    for (char *p = buf, *x;; p = x + 1) {
        x = strchr(p, 'x');
        if (x)
            *x = '\0';
        unsigned long u;
        if (*n == n_max || parse_num(p, 10, 1, hi, &u) != 0)
            return -1;
        v[(*n)++] = (int)u;
        if (!x)
            return 0;
    }
}

static int parse_device(const char *s, opts *o)
{
    static char serial[128];
    char buf[128];
    if (strlen(s) >= sizeof buf)
        return -1;
    strcpy(buf, s);
    char *c1 = strchr(buf, ':');
    if (!c1)
        return -1;
    *c1 = '\0';
    char *pid = c1 + 1, *c2 = strchr(pid, ':');
    if (c2) {
        *c2 = '\0';
        if (!c2[1])
            return -1;
        snprintf(serial, sizeof serial, "%s", c2 + 1);
        o->serial = serial;
    }
    unsigned long v, p;
    if (parse_num(buf, 16, 0, 0xFFFF, &v) || parse_num(pid, 16, 0, 0xFFFF, &p))
        return -1;
    o->vid = (unsigned)v;
    o->pid = (unsigned)p;
    return 0;
}

/* Returns 0, or an exit status (usage errors) after printing. -1: --help or --version printed. */
static int parse_args(int argc, char **argv, opts *o)
{
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *val = i + 1 < argc ? argv[i + 1] : NULL;
        unsigned long u;
        int n;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(usage, stdout);
            return -1;
        } else if (!strcmp(a, "--version")) {
            printf("cube5ctl %s\n", C5_VERSION);
            return -1;
        } else if (!strcmp(a, "--json")) {
            o->json = 1;
        } else if (!strcmp(a, "--device") || !strcmp(a, "--timeout") || !strcmp(a, "-o") || !strcmp(a, "--frame") ||
                   !strcmp(a, "--cells") || !strcmp(a, "--size")) {
            if (!val)
                return usage_err("missing value after", a);
            i++;
            if (!strcmp(a, "--device")) {
                if (parse_device(val, o))
                    return usage_err("--device: expected VID:PID[:SERIAL] in hex, got", val);
            } else if (!strcmp(a, "--timeout")) {
                if (parse_num(val, 10, 1, 86400000, &u))
                    return usage_err("--timeout: expected milliseconds in 1..86400000, got", val);
                o->timeout_ms = (unsigned)u;
            } else if (!strcmp(a, "-o")) {
                o->out = val;
            } else if (!strcmp(a, "--frame")) {
                if (parse_num(val, 10, 0, 1000000, &u))
                    return usage_err("--frame: expected a frame number >= 0, got", val);
                o->frame = (int)u;
                o->have_frame = 1;
            } else if (!strcmp(a, "--cells")) {
                if (parse_dims(val, 3, MAX_CELLS, o->cells, &n) || n == 2)
                    return usage_err("--cells: expected N or NxMxK (each 1..64), got", val);
                if (n == 1)
                    o->cells[1] = o->cells[2] = o->cells[0];
                o->have_cells = 1;
            } else {
                int wh[2];
                if (parse_dims(val, 2, 512, wh, &n))
                    return usage_err("--size: expected N or WxH (each 1..512), got", val);
                if (n == 1)
                    wh[1] = wh[0];
                o->w = wh[0];
                o->h = wh[1];
            }
        } else if (a[0] == '-' && a[1]) {
            return usage_err("unknown option", a);
        } else if (!o->cmd) {
            o->cmd = a;
        } else if (!strcmp(o->cmd, "render") && !o->scene) {
            o->scene = a;
        } else {
            return usage_err("unexpected argument", a);
        }
    }
    if (!o->cmd)
        return usage_err("no command: info, render or stats", NULL);
    int render = !strcmp(o->cmd, "render");
    if (!render && strcmp(o->cmd, "info") && strcmp(o->cmd, "stats"))
        return usage_err("unknown command", o->cmd);
    if (render && (!o->scene || !o->out))
        return usage_err("render needs SCENE and -o OUT", NULL);
    if (!render && (o->out || o->have_cells || o->w || o->have_frame))
        return usage_err("-o, --frame, --cells and --size belong to render, not", o->cmd);
    return 0;
}

static char *read_file(const char *path, const char **why)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        *why = strerror(errno);
        return NULL;
    }
    size_t cap = 1 << 16, n = 0;
    char *buf = malloc(cap);
    for (size_t got; buf && (got = fread(buf + n, 1, cap - n - 1, f)) > 0;) {
        n += got;
        if (n + 1 == cap) {
            char *p = realloc(buf, cap *= 2);
            if (!p) {
                free(buf);
                buf = NULL;
            } else {
                buf = p;
            }
        }
    }
    int bad = ferror(f);
    fclose(f);
    if (!buf || bad) {
        free(buf);
        *why = buf ? "read error" : "out of memory";
        return NULL;
    }
    buf[n] = '\0';
    return buf;
}

/* The scene's JSON (built-in or file) and the folder its relative volume paths start from. */
static int scene_text(const char *arg, char **json, char *dir, size_t dcap)
{
    const char *builtin = c5_builtin_scene_json(arg);
    if (builtin) {
        *json = strdup(builtin);
        dir[0] = '\0';
        return *json ? 0 : fail("out of memory");
    }
    size_t n = strlen(arg);
    if (n < 5 || strcmp(arg + n - 5, ".json") != 0)
        return bad_input("'%s' is neither a built-in scene nor a .json file", arg);
    const char *why = "";
    if (!(*json = read_file(arg, &why)))
        return bad_input("%s: %s", arg, why);
    const char *slash = strrchr(arg, '/');
    snprintf(dir, dcap, "%.*s", slash ? (int)(slash - arg) + (slash == arg) : 1, slash ? arg : ".");
    return 0;
}

/* Refuses, before any work, an output that is not .png/.exr or is an input: the scene file, a
 * volume file or a data file a NRRD header names (common/volume_inputs.h). */
static int check_output(const opts *o, const char *json, const char *dir)
{
    c5_err err;
    if (c5_image_check_out(o->out, &err) != 0) /* the extension and the place, as cube5's */
        return bad_input("%s", err.msg);
    c5_scene *s = calloc(1, sizeof *s);
    c5_file_list in = {0};
    if (!s)
        return fail("out of memory");
    int rc = 0;
    if (dir[0] && c5_file_list_add(&in, o->scene, "the scene file", &err) != 0)
        rc = fail("%s", err.msg);
    /* a scene that does not parse is reported by the driver's load with its own message */
    else if (c5_scene_parse(json, dir[0] ? dir : NULL, o->scene, s, &err) == 0 &&
             c5_scene_input_files(NULL, s, &in, &err) != 0)
        rc = bad_input("%s", err.msg);
    long i = rc ? -1 : c5_file_list_find(&in, o->out);
    if (i >= 0)
        rc = bad_input("%s: is %s (%s); refusing to overwrite an input", o->out, in.what[i], in.path[i]);
    c5_file_list_free(&in);
    free(s);
    return rc;
}

static int drv_err(c5drv *d, int rc)
{
    /* the error's class first (what a script matches), then what happened; a scene the
     * driver cannot load (a bad file, a limit of the board's fields) is bad input */
    const char *m = c5drv_message(d);
    int status = rc == C5DRV_E_SCENE ? EXIT_USAGE : EXIT_FAIL;
    return m && m[0] ? failure(status, "%s: %s", c5drv_strerror(rc), m) : failure(status, "%s", c5drv_strerror(rc));
}

static void print_counters(const c5drv_counters *c, int json, int driver_side)
{
    double mbs = c->cell_upload_s > 0 ? (double)c->cell_bytes / c->cell_upload_s / 1e6 : 0;
    if (json) {
        printf("{\"board\": {\"fetches\": %u, \"cycles\": %llu, \"samples\": %llu, \"rays\": %u, "
               "\"bus_packets\": %u, \"spills\": %u}",
               (unsigned)c->fetches, (unsigned long long)c->cycles, (unsigned long long)c->samples,
               (unsigned)c->rays, (unsigned)c->bus_packets, (unsigned)c->spills);
        if (driver_side)
            printf(", \"driver\": {\"fetches_served\": %llu, \"dma_reads\": %llu, \"bytes_served\": %llu, "
                   "\"cell_bytes\": %llu, \"fb_bytes\": %llu, \"interrupts\": %llu, \"stall_retries\": %llu, "
                   "\"cell_upload_s\": %.6f, \"cell_upload_mb_s\": %.3f, \"frame_s\": %.6f}",
                   (unsigned long long)c->fetches_served, (unsigned long long)c->dma_reads,
                   (unsigned long long)c->bytes_served, (unsigned long long)c->cell_bytes,
                   (unsigned long long)c->fb_bytes, (unsigned long long)c->interrupts,
                   (unsigned long long)c->stall_retries, c->cell_upload_s, mbs, c->frame_s);
        printf("}\n");
        return;
    }
    if (driver_side)
        printf("%llu fetches served; ", (unsigned long long)c->fetches_served);
    printf("board: %u fetches, %llu cycles, %llu samples, %u rays, %u bus packets, %u spills",
           (unsigned)c->fetches, (unsigned long long)c->cycles, (unsigned long long)c->samples, (unsigned)c->rays,
           (unsigned)c->bus_packets, (unsigned)c->spills);
    if (driver_side)
        printf("; cell upload %.1f MB/s; frame %.3f s", mbs, c->frame_s);
    printf("\n");
}

static int cmd_render(c5drv *d, const opts *o, const char *json, const char *dir)
{
    int rc;
    if ((rc = c5drv_load_scene(d, json, dir[0] ? dir : NULL, o->scene, o->have_cells ? o->cells : NULL, o->w,
                               o->h)))
        return drv_err(d, rc);
    if ((rc = c5drv_start_frame(d, o->frame)) == C5DRV_E_ARG) /* a frame the scene does not have: bad input */
        return failure(EXIT_USAGE, "--frame: %s", c5drv_message(d));
    if (rc)
        return drv_err(d, rc);
    if ((rc = c5drv_wait_frame(d, o->timeout_ms))) {
        int status = drv_err(d, rc);
        if (rc != C5DRV_E_DISCONNECTED && rc != C5DRV_E_BOARD)
            c5drv_reset(d); /* best effort: leave no frame running on the board */
        return status;
    }
    c5drv_image frame = {0};
    c5drv_counters c;
    if ((rc = c5drv_read_frame(d, &frame)) || (rc = c5drv_read_counters(d, &c))) {
        c5drv_image_free(&frame);
        return drv_err(d, rc);
    }
    c5_err err;
    rc = c5_image_write(o->out, &(c5_image){frame.w, frame.h, frame.rgb}, &err);
    c5drv_image_free(&frame);
    if (rc != 0)
        return fail("%s", err.msg);
    print_counters(&c, o->json, 1);
    if (!o->json)
        printf("image %s\n", o->out);
    return 0;
}

int main(int argc, char **argv)
{
    opts o = {.vid = C5_USB_VID, .pid = C5_USB_PID, .timeout_ms = DEFAULT_TIMEOUT_MS};
    int rc = parse_args(argc, argv, &o);
    if (rc)
        return rc < 0 ? 0 : rc;
    char *json = NULL, dir[4096] = "";
    if (!strcmp(o.cmd, "render") &&
        ((rc = scene_text(o.scene, &json, dir, sizeof dir)) || (rc = check_output(&o, json, dir)))) {
        free(json);
        return rc;
    }
    char msg[512];
    c5drv *d = NULL;
    if ((rc = c5drv_open_usb((uint16_t)o.vid, (uint16_t)o.pid, o.serial, &d, msg, sizeof msg))) {
        free(json);
        return fail("%s", msg);
    }
    c5drv_info info;
    int status = 0;
    if ((rc = c5drv_identify(d, &info))) {
        status = drv_err(d, rc);
    } else if (!strcmp(o.cmd, "info")) {
        if (o.json)
        {
            printf("{\"id\": \"0x%08x\", \"major\": %u, \"minor\": %u, \"serial\": \"", (unsigned)info.id,
                   info.major, info.minor);
            json_safe(info.serial);
            printf("\"}\n");
        }
        else
            printf("id 0x%08x (cube5), register map %u.%u, serial %s\n", (unsigned)info.id, info.major, info.minor,
                   info.serial[0] ? info.serial : "(none)");
    } else if (!strcmp(o.cmd, "stats")) {
        c5drv_counters c;
        if ((rc = c5drv_read_counters(d, &c)))
            status = drv_err(d, rc);
        else
            print_counters(&c, o.json, 0);
    } else {
        status = cmd_render(d, &o, json, dir);
    }
    c5drv_close(d);
    free(json);
    return status;
}
