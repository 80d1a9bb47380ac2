/* Voxel sources read box by box (voxsrc.h). */
#include "voxsrc.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "generators.h"
#include "volume.h"

/* A mapped file cut short by another process faults (SIGBUS) where a read would have failed:
 * the run ends with the message a failed read gives, naming the file mapped last (composed
 * when it is mapped, written at once). */
static char map_msg[1200];

static void map_fault(int sig)
{
    (void)sig;
    ssize_t r = write(2, map_msg, strlen(map_msg));
    (void)r;
    _exit(C5_EXIT_INPUT);
}

void c5_map_guard(const char *path)
{
    snprintf(map_msg, sizeof map_msg, "cube5: error: %s: read failed: the file ends early (it changed after it was "
             "checked)\n", path);
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = map_fault;
    sigaction(SIGBUS, &sa, NULL);
}

/* Largest single pread: a scratch buffer of this size at most per read call. */
#define SCRATCH_MAX ((size_t)1 << 20)
/* A read of a span that holds rows the box does not need costs less than one system call per
 * row while the span is within this many bytes per row (a page's copy against a syscall). */
#define ROW_SYSCALL_BYTES 4096

struct c5_voxsrc {
    int is_gen;
    c5_volume_desc d;          /* generators: the description */
    c5_gen_state g;
    c5_volume_file f;          /* files: the open data */
    char path[1024];
    double wlo, wscale;        /* uint16: the window's low end and 255 / (hi - lo) */
    size_t dims[3];
    double spacing[3];
    char label[160];
};

static const char *base_name(const char *path)
{
    const char *b = strrchr(path, '/');
    return b ? b + 1 : path;
}

/* n bytes at offset `at`, or -1 with err: a short read means the file shrank after its check. */
static int pread_full(const c5_voxsrc *s, unsigned char *p, size_t n, long long at, c5_err *err)
{
    while (n > 0) {
        ssize_t r = pread(s->f.fd, p, n, (off_t)at);
        if (r < 0 && errno == EINTR)
            continue;
        if (r < 0)
            return c5_fail(err, "%s: read failed: %s", s->path, strerror(errno));
        if (r == 0)
            return c5_fail(err, "%s: read failed: the file ends early (it changed after it was checked)", s->path);
        p += r;
        n -= (size_t)r;
        at += r;
    }
    return 0;
}

static unsigned u16_at(const unsigned char *p, int big_endian)
{
    return big_endian ? (unsigned)(p[0] << 8 | p[1]) : (unsigned)(p[1] << 8 | p[0]);
}

/* uint16 -> uint8 through [lo, hi]: round((v - lo) * 255 / (hi - lo)), clamped. */
static uint8_t window_u8(const c5_voxsrc *s, unsigned v)
{
    double x = floor((v - s->wlo) * s->wscale + 0.5);
    return (uint8_t)(x < 0 ? 0 : x > 255 ? 255 : x);
}

static void convert_row(const c5_voxsrc *s, const unsigned char *in, size_t n, uint8_t *out)
{
    if (s->f.type == C5_VOX_U16)
        for (size_t i = 0; i < n; i++)
            out[i] = window_u8(s, u16_at(in + 2 * i, s->f.big_endian));
    else
        memcpy(out, in, n);
}

/* The file's min and max, in chunks of SCRATCH_MAX bytes. */
static int auto_window(c5_voxsrc *s, c5_err *err)
{
    size_t total = s->dims[0] * s->dims[1] * s->dims[2] * 2, chunk = SCRATCH_MAX;
    unsigned char *buf = malloc(chunk);
    if (!buf)
        return c5_fail(err, "%s: out of memory for the window pass", s->path);
    unsigned mn = 65535, mx = 0;
    for (size_t at = 0; at < total; at += chunk) {
        size_t n = total - at < chunk ? total - at : chunk;
        if (pread_full(s, buf, n, s->f.offset + (long long)at, err) != 0) {
            free(buf);
            return -1;
        }
        for (size_t i = 0; i < n; i += 2) {
            unsigned x = u16_at(buf + i, s->f.big_endian);
            mn = x < mn ? x : mn;
            mx = x > mx ? x : mx;
        }
    }
    free(buf);
    s->wlo = mn;
    s->wscale = 255.0 / ((mx > mn ? mx : mn + 1) - s->wlo);
    size_t used = strlen(s->label);
    snprintf(s->label + used, sizeof s->label - used, " window [%g, %g]", (double)mn,
             (double)(mx > mn ? mx : mn + 1));
    return 0;
}

int c5_voxsrc_open(const c5_volume_desc *d, c5_voxsrc **out, c5_err *err)
{
    *out = NULL;
    c5_voxsrc *s = calloc(1, sizeof *s);
    if (!s)
        return c5_fail(err, "out of memory for a volume source");
    s->f.fd = -1;
    if (d->kind == C5_SRC_GENERATOR) {
        size_t n;
        if (c5_dims_product(d->gen_dims, &n) != 0) {
            char what[64];
            snprintf(what, sizeof what, "generator %s", c5_generator_name(d->generator));
            c5_dims_fail(what, d->gen_dims, err); /* names the limit */
            free(s);
            return -1;
        }
        s->is_gen = 1;
        s->d = *d;
        c5_gen_prepare(d, &s->g);
        memcpy(s->dims, d->gen_dims, sizeof s->dims);
        snprintf(s->label, sizeof s->label, "generator %s %zux%zux%zu", c5_generator_name(d->generator), s->dims[0],
                 s->dims[1], s->dims[2]);
        *out = s;
        return 0;
    }
    snprintf(s->path, sizeof s->path, "%s", d->path);
    s->d = *d;
    if (c5_volume_probe(d->path, &d->raw, &s->f, err) != 0) {
        free(s);
        return -1;
    }
    memcpy(s->dims, s->f.dims, sizeof s->dims);
    snprintf(s->label, sizeof s->label, "file %.90s %zux%zux%zu %s", base_name(d->path), s->dims[0], s->dims[1],
             s->dims[2], s->f.type == C5_VOX_U16 ? "uint16" : "uint8");
    *out = s;
    return 0;
}

int c5_voxsrc_prepare(c5_voxsrc *s, c5_err *err)
{
    if (s->is_gen || s->f.fd >= 0)
        return 0;
    const c5_volume_desc *d = &s->d;
    if (c5_volume_open(d->path, &d->raw, &s->f, err) != 0)
        return -1;
    if (s->f.dims[0] != s->dims[0] || s->f.dims[1] != s->dims[1] || s->f.dims[2] != s->dims[2])
        return c5_fail(err, "%s: the file changed while it was read", s->path);
    if (s->f.spacing[0] > 0 && s->f.spacing[1] > 0 && s->f.spacing[2] > 0)
        memcpy(s->spacing, s->f.spacing, sizeof s->spacing);
    if (s->f.type == C5_VOX_U16) {
        if (d->has_window) {
            s->wlo = d->window[0];
            s->wscale = 255.0 / (d->window[1] - d->window[0]);
            size_t used = strlen(s->label);
            snprintf(s->label + used, sizeof s->label - used, " window [%g, %g]", d->window[0], d->window[1]);
        } else if (auto_window(s, err) != 0) {
            return -1;
        }
    }
    return 0;
}

void c5_voxsrc_close(c5_voxsrc *s)
{
    if (!s)
        return;
    if (s->f.fd >= 0)
        close(s->f.fd);
    free(s);
}

int c5_voxsrc_identity(const c5_voxsrc *s, char *buf, size_t n)
{
    struct stat st;
    if (s->is_gen) {
        const c5_volume_desc *d = &s->d;
        snprintf(buf, n, "generator %s dims %zu %zu %zu f_m %.17g alpha %.17g radius %.17g value %.17g count %d "
                 "axis %d seed %llu built %s", c5_generator_name(d->generator), s->dims[0], s->dims[1], s->dims[2],
                 d->f_m, d->alpha, d->radius, d->value, d->count, d->axis, (unsigned long long)d->seed,
                 c5_generators_build());
        return 0;
    }
    struct timespec now;
    if (s->f.fd < 0 || fstat(s->f.fd, &st) != 0 || clock_gettime(CLOCK_REALTIME, &now) != 0)
        return -1;
    /* A file written in the last 2 s could be written again within one tick of its clock and
     * keep its identity with other voxels (git's "racy" files): none until it has aged. */
    if (st.st_mtim.tv_sec > now.tv_sec - C5_IDENTITY_AGE_S)
        return -1;
    snprintf(buf, n, "dev %llu ino %llu size %lld mtime %lld.%09ld offset %lld type %d be %d window %.17g %.17g "
             "dims %zu %zu %zu", (unsigned long long)st.st_dev, (unsigned long long)st.st_ino,
             (long long)st.st_size, (long long)st.st_mtim.tv_sec, (long)st.st_mtim.tv_nsec, s->f.offset,
             (int)s->f.type, s->f.big_endian, s->wlo, s->wscale, s->dims[0], s->dims[1], s->dims[2]);
    return 0;
}

int c5_voxsrc_map(const c5_voxsrc *s, void **base, size_t *len, const uint8_t **data)
{
    if (s->is_gen || s->f.fd < 0 || s->f.type != C5_VOX_U8 || s->f.offset < 0)
        return -1;
    size_t n = (size_t)s->f.offset + s->dims[0] * s->dims[1] * s->dims[2];
    void *p = mmap(NULL, n, PROT_READ, MAP_PRIVATE, s->f.fd, 0);
    if (p == MAP_FAILED)
        return -1;
    c5_map_guard(s->path);
    *base = p;
    *len = n;
    *data = (const uint8_t *)p + s->f.offset;
    return 0;
}

const size_t *c5_voxsrc_dims(const c5_voxsrc *s) { return s->dims; }
int c5_voxsrc_is_generator(const c5_voxsrc *s) { return s->is_gen; }
const double *c5_voxsrc_spacing(const c5_voxsrc *s) { return s->spacing; }
const char *c5_voxsrc_label(const c5_voxsrc *s) { return s->label; }

int c5_voxsrc_read(const c5_voxsrc *s, const size_t lo[3], const size_t hi[3], uint8_t *out, size_t sy, size_t sz,
                   c5_err *err)
{
    if (s->is_gen) {
        c5_generate_box(&s->d, &s->g, lo, hi, out, sy, sz);
        return 0;
    }
    size_t vb = s->f.type == C5_VOX_U16 ? 2 : 1, nx = s->dims[0], ny = s->dims[1];
    size_t w = hi[0] - lo[0], row_bytes = w * vb, line = nx * vb;
    /* rows per read: a span of k rows is (k - 1) lines and one row */
    size_t k = row_bytes >= SCRATCH_MAX ? 1 : 1 + (SCRATCH_MAX - row_bytes) / line;
    size_t rows = hi[1] - lo[1];
    if (k > rows)
        k = rows;
    if (k > 1 && (k - 1) * line + row_bytes > k * (row_bytes + ROW_SYSCALL_BYTES))
        k = 1; /* the span would copy mostly bytes outside the box: one read per row */
    size_t span_max = (k - 1) * line + row_bytes;
    unsigned char *buf = NULL;
    int direct = vb == 1 && k == 1; /* uint8 row by row: straight into out */
    if (!direct && !(buf = malloc(span_max)))
        return c5_fail(err, "%s: out of memory for a read buffer (%zu bytes)", s->path, span_max);
    int rc = 0;
    for (size_t z = lo[2]; z < hi[2] && rc == 0; z++)
        for (size_t y = lo[1]; y < hi[1] && rc == 0; y += k) {
            size_t n = hi[1] - y < k ? hi[1] - y : k;
            long long at = s->f.offset + (long long)(((z * ny + y) * nx + lo[0]) * vb);
            uint8_t *dst = out + (z - lo[2]) * sz + (y - lo[1]) * sy;
            if (direct) {
                rc = pread_full(s, dst, row_bytes, at, err);
                continue;
            }
            if ((rc = pread_full(s, buf, (n - 1) * line + row_bytes, at, err)) != 0)
                break;
            for (size_t r = 0; r < n; r++)
                convert_row(s, buf + r * line, w, dst + r * sy);
        }
    free(buf);
    return rc;
}
