/* Harness: the volume loaders (common/volume.c, common/nrrd_precheck.c, Teem's reader) on
 * files the input describes. Byte 0 chooses the loader:
 *   0  raw, named by the Open SciVis rule: the next line is the file's base name
 *      (e.g. "v_4x4x2_uint8.raw"), the rest its contents;
 *   1  NRRD with an attached header: the rest is v.nrrd;
 *   2  NRRD with a detached header: the rest up to the line "--data--" is v.nhdr, what
 *      follows is v.raw (the header names its data file itself).
 * Files go to a fresh folder in /dev/shm (or /tmp). Promises: 0 with a volume whose size
 * is its dims, or -1 with a one-line message and an empty volume; never a disagreement
 * between the precheck and Teem (C5_NRRD_DISAGREE). The out-of-core opening of the same file
 * (c5_volume_open: read at the data's offset, gzip inflated to a temporary file) agrees with
 * the load: both fail, or both succeed with the same dims, type, spacing and voxels. */
#include <math.h>
#include <unistd.h>

#include "fuzz.h"
#include "nrrd_precheck.h"
#include "volume.h"

static char dir[256];

/* Every input's files are unlinked after it: the folder is empty at exit. */
static void remove_dir(void) { rmdir(dir); }

static void make_dir(void)
{
    if (dir[0])
        return;
    const char *base = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
    snprintf(dir, sizeof dir, "%s/c5fuzz-vol-XXXXXX", base);
    if (!mkdtemp(dir)) {
        perror("fuzz_volume: mkdtemp");
        abort();
    }
    atexit(remove_dir);
}

static void put(const char *path, const uint8_t *p, size_t n)
{
    FILE *f = fopen(path, "wb");
    if (!f || (n && fwrite(p, 1, n, f) != n) || fclose(f) != 0) {
        perror(path);
        abort();
    }
}

/* The base name on the first line: no '/', no NUL, at most 100 bytes; else "v.raw". */
static size_t raw_name(const uint8_t *p, size_t n, char *name, size_t cap)
{
    const uint8_t *nl = memchr(p, '\n', n < 101 ? n : 101);
    size_t len = nl ? (size_t)(nl - p) : 0;
    if (!nl || len == 0 || len >= cap || memchr(p, '/', len) || memchr(p, 0, len) ||
        (len <= 2 && p[0] == '.')) {
        snprintf(name, cap, "v.raw");
        return 0;
    }
    memcpy(name, p, len);
    name[len] = 0;
    return len + 1;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    make_dir();
    char path[512], data_path[512], name[128];
    const uint8_t *p = data + 1;
    size_t n = size - 1;
    data_path[0] = 0;
    switch (data[0] % 3) {
    case 0: {
        size_t used = raw_name(p, n, name, sizeof name);
        snprintf(path, sizeof path, "%s/%s", dir, name);
        put(path, p + used, n - used);
        break;
    }
    case 1:
        snprintf(path, sizeof path, "%s/v.nrrd", dir);
        put(path, p, n);
        break;
    default: {
        static const char sep[] = "\n--data--\n";
        const uint8_t *cut = NULL;
        for (size_t i = 0; i + sizeof sep - 1 <= n && !cut; i++)
            if (!memcmp(p + i, sep, sizeof sep - 1))
                cut = p + i;
        size_t head = cut ? (size_t)(cut - p) + 1 : n; /* the header keeps its last newline */
        snprintf(path, sizeof path, "%s/v.nhdr", dir);
        snprintf(data_path, sizeof data_path, "%s/v.raw", dir);
        put(path, p, head);
        if (cut)
            put(data_path, cut + sizeof sep - 1, n - (size_t)(cut - p) - (sizeof sep - 1));
        break;
    }
    }
    c5_volume v;
    c5_err err = {{0}};
    int rc = c5_volume_load(path, NULL, &v, &err);
    c5_fuzz_expect(rc == 0 || rc == -1, "c5_volume_load returns 0 or -1");
    if (rc != 0) {
        c5_fuzz_expect(c5_fuzz_one_line(err.msg, sizeof err.msg), "a one-line error message");
        char disagree[sizeof err.msg]; /* the exact message: a header can quote the words */
        snprintf(disagree, sizeof disagree, "%s: %s", path, C5_NRRD_DISAGREE);
        c5_fuzz_expect(strcmp(err.msg, disagree) != 0, "the precheck and Teem read the header alike");
        c5_fuzz_expect(v.data == NULL && v.dims[0] == 0, "a failed load leaves an empty volume");
    } else {
        size_t count;
        c5_fuzz_expect(c5_dims_product(v.dims, &count) == 0 && count == c5_volume_count(&v), "dims within limits");
        c5_fuzz_expect(v.type == C5_VOX_U8 || v.type == C5_VOX_U16, "uint8 or uint16");
        unsigned top = 0; /* every voxel read: ASan sees a buffer shorter than the dims */
        for (size_t i = 0; i < count; i++)
            top = c5_volume_at(&v, i) > top ? c5_volume_at(&v, i) : top;
        c5_fuzz_expect(top <= (v.type == C5_VOX_U8 ? 255u : 65535u), "voxel values fit the type");
        for (int a = 0; a < 3; a++)
            c5_fuzz_expect(v.spacing[a] >= 0 && isfinite(v.spacing[a]), "a spacing is finite and >= 0 (0: unknown)");
        c5_volume_free(&v);
    }
    c5_volume_file vf;
    c5_err err2 = {{0}};
    int rc2 = c5_volume_open(path, NULL, &vf, &err2);
    c5_fuzz_expect(rc2 == rc, "c5_volume_open fails exactly when c5_volume_load does");
    if (rc2 != 0)
        c5_fuzz_expect(c5_fuzz_one_line(err2.msg, sizeof err2.msg), "a one-line error message");
    if (rc2 == 0 && rc == 0) {
        c5_volume w;
        c5_fuzz_expect(c5_volume_load(path, NULL, &w, &err) == 0, "the load repeats");
        size_t vb = vf.type == C5_VOX_U16 ? 2 : 1, bytes = c5_volume_count(&w) * vb;
        c5_fuzz_expect(!memcmp(vf.dims, w.dims, sizeof vf.dims) && vf.type == w.type &&
                           !memcmp(vf.spacing, w.spacing, sizeof vf.spacing), "the same dims, type and spacing");
        uint8_t *buf = malloc(bytes ? bytes : 1);
        c5_fuzz_expect(buf && pread(vf.fd, buf, bytes, (off_t)vf.offset) == (ssize_t)bytes, "the voxels at the offset");
        for (size_t i = 0; i < c5_volume_count(&w); i++) {
            unsigned x = vb == 1 ? buf[i] : vf.big_endian ? (unsigned)(buf[2 * i] << 8 | buf[2 * i + 1])
                                                         : (unsigned)(buf[2 * i + 1] << 8 | buf[2 * i]);
            if (x != c5_volume_at(&w, i)) {
                c5_fuzz_expect(0, "the voxels read at the offset are the loaded ones");
                break;
            }
        }
        free(buf);
        c5_volume_free(&w);
    }
    if (rc2 == 0)
        close(vf.fd);
    unlink(path);
    if (data_path[0])
        unlink(data_path);
    return 0;
}
