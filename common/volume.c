/* Volume loading: raw files (explicit dims or an Open SciVis name) and NRRD via Teem.
 * Every failure leaves *out empty, frees what was taken and writes "PATH: problem". */
#include "volume.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <teem/nrrd.h>

#include "nrrd_precheck.h"
#include "voxel.h"

static size_t voxel_size(c5_voxel_type t) { return t == C5_VOX_U16 ? 2 : 1; }

static const char *type_name(c5_voxel_type t) { return t == C5_VOX_U16 ? "uint16" : "uint8"; }

/* ---- Open SciVis names ----------------------------------------------------------- */

/* Reads decimal digits in [s, end), saturating so that absurd values still reach the
 * dims check (and its message) instead of silently wrapping. */
static int parse_dim(const char *s, const char *end, size_t *v)
{
    if (s == end)
        return -1;
    size_t n = 0;
    for (; s < end; s++) {
        if (*s < '0' || *s > '9')
            return -1;
        unsigned d = (unsigned)(*s - '0');
        n = n > (SIZE_MAX - d) / 10 ? SIZE_MAX : n * 10 + d;
    }
    *v = n;
    return 0;
}

/* Matches NAME_XxYxZ_TYPE.raw (any TYPE), so that a known-but-unsupported type such as
 * int16 can be reported as such rather than as a name that does not fit. */
static int scivis_parse(const char *path, size_t dims[3], const char **type, size_t *type_len)
{
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    size_t len = strlen(base);
    if (len < 4 || strcmp(base + len - 4, ".raw") != 0)
        return -1;
    const char *end = base + len - 4;
    const char *us_type = end;
    while (us_type > base && us_type[-1] != '_')
        us_type--;
    if (us_type == base || us_type == end)
        return -1;
    const char *dims_end = us_type - 1;
    const char *dims_start = dims_end;
    while (dims_start > base && dims_start[-1] != '_')
        dims_start--;
    if (dims_start - 1 <= base) /* no '_' before the dims, or an empty NAME */
        return -1;
    const char *x1 = memchr(dims_start, 'x', (size_t)(dims_end - dims_start));
    const char *x2 = x1 ? memchr(x1 + 1, 'x', (size_t)(dims_end - x1 - 1)) : NULL;
    if (!x2 || parse_dim(dims_start, x1, &dims[0]) || parse_dim(x1 + 1, x2, &dims[1]) ||
        parse_dim(x2 + 1, dims_end, &dims[2]))
        return -1;
    *type = us_type;
    *type_len = (size_t)(end - us_type);
    return 0;
}

static c5_voxel_type type_from_name(const char *s, size_t len)
{
    if (len == 5 && memcmp(s, "uint8", 5) == 0)
        return C5_VOX_U8;
    if (len == 6 && memcmp(s, "uint16", 6) == 0)
        return C5_VOX_U16;
    return C5_VOX_NONE;
}

int c5_scivis_name(const char *path, size_t dims[3], c5_voxel_type *type)
{
    size_t d[3], tlen;
    const char *t;
    if (!path || scivis_parse(path, d, &t, &tlen) != 0)
        return -1;
    c5_voxel_type vt = type_from_name(t, tlen);
    if (vt == C5_VOX_NONE)
        return -1;
    memcpy(dims, d, sizeof d);
    *type = vt;
    return 0;
}

/* ---- raw ------------------------------------------------------------------------- */

static FILE *open_regular(const char *path, long long *size, c5_err *err)
{
    int fd = c5_open_regular(path, path, size, err);
    FILE *f = fd < 0 ? NULL : fdopen(fd, "rb");
    if (!f && fd >= 0) {
        c5_fail(err, "%s: cannot open: %s", path, strerror(errno));
        close(fd);
    }
    return f;
}

/* Settles dims and type from the spec or, when it gives neither, from the file name. */
static int raw_layout(const char *path, const c5_raw_spec *spec, size_t dims[3],
                      c5_voxel_type *type, c5_err *err)
{
    int has_dims = spec && (spec->dims[0] || spec->dims[1] || spec->dims[2]);
    int has_type = spec && spec->type != C5_VOX_NONE;
    if (has_dims && !has_type)
        return c5_fail(err, "%s: dims given without a voxel type: give both dims and type", path);
    if (has_type && !has_dims)
        return c5_fail(err, "%s: voxel type given without dims: give both dims and type", path);
    if (has_dims) {
        if (spec->type != C5_VOX_U8 && spec->type != C5_VOX_U16)
            return c5_fail(err, "%s: unsupported voxel type %d (uint8 or uint16 only)", path,
                           (int)spec->type);
        memcpy(dims, spec->dims, sizeof spec->dims);
        *type = spec->type;
        return 0;
    }
    const char *t;
    size_t tlen;
    if (scivis_parse(path, dims, &t, &tlen) != 0)
        return c5_fail(err, "%s: no dims and type given, and the name does not follow "
                            "NAME_XxYxZ_uint8.raw or NAME_XxYxZ_uint16.raw", path);
    *type = type_from_name(t, tlen);
    if (*type == C5_VOX_NONE)
        return c5_fail(err, "%s: unsupported voxel type '%.*s' (uint8 or uint16 only)", path,
                       (int)tlen, t);
    return 0;
}

/* Turns the file's byte order into host order in place, one voxel at a time through
 * memcpy so that it is correct on any host and free of aliasing or alignment tricks. */
static void u16_to_host(unsigned char *p, size_t count, int big_endian)
{
    for (size_t i = 0; i < count; i++, p += 2) {
        uint16_t v = big_endian ? (uint16_t)(p[0] << 8 | p[1]) : (uint16_t)(p[1] << 8 | p[0]);
        memcpy(p, &v, 2);
    }
}

int c5_volume_load_raw(const char *path, const c5_raw_spec *spec, c5_volume *out, c5_err *err)
{
    if (!out)
        return c5_fail(err, "%s: no output volume", path ? path : "(null)");
    memset(out, 0, sizeof *out);
    if (!path)
        return c5_fail(err, "(null): no file name");
    size_t dims[3], count, bytes;
    c5_voxel_type type;
    /* Opened first: a missing file is reported as missing, not as a name without dims. */
    long long size;
    FILE *f = open_regular(path, &size, err);
    if (!f)
        return -1;
    if (raw_layout(path, spec, dims, &type, err) != 0) {
        fclose(f);
        return -1;
    }
    if (c5_dims_product(dims, &count) != 0 || c5_mul_size(count, voxel_size(type), &bytes) != 0) {
        fclose(f);
        return c5_dims_fail(path, dims, err);
    }
    if ((unsigned long long)size != bytes) {
        char why[64] = "truncated";
        if ((unsigned long long)size > bytes)
            snprintf(why, sizeof why, "%llu extra bytes", (unsigned long long)size - bytes);
        fclose(f);
        return c5_fail(err, "%s: file is %lld bytes, expected %zu (%zux%zux%zu %s): %s", path, size,
                       bytes, dims[0], dims[1], dims[2], type_name(type), why);
    }
    unsigned char *data = malloc(bytes);
    if (!data) {
        fclose(f);
        return c5_fail(err, "%s: out of memory for %zu bytes", path, bytes);
    }
    size_t got = fread(data, 1, bytes, f);
    int read_errno = ferror(f) ? errno : 0;
    fclose(f);
    if (got != bytes) {
        free(data);
        if (read_errno)
            return c5_fail(err, "%s: read failed: %s", path, strerror(read_errno));
        return c5_fail(err, "%s: read only %zu of %zu bytes: truncated while reading", path, got,
                       bytes);
    }
    if (type == C5_VOX_U16)
        u16_to_host(data, count, spec && spec->big_endian);
    memcpy(out->dims, dims, sizeof dims);
    out->type = type;
    out->data = data;
    return 0;
}

/* ---- NRRD ------------------------------------------------------------------------ */

/* Teem stacks its messages outermost first ("nrrdLoad: trouble reading ..."), so the
 * useful cause is the last line; this returns it, inside `all`, without the
 * "[nrrd] function: " prefix that means nothing to a user. */
static const char *teem_cause(char *all)
{
    char *end = all + strlen(all);
    while (end > all && (end[-1] == '\n' || end[-1] == ' ' || end[-1] == '\t'))
        end--;
    *end = 0;
    char *s = strrchr(all, '\n');
    s = s ? s + 1 : all;
    char *bracket = *s == '[' ? strchr(s, ']') : NULL;
    if (bracket)
        s = bracket + 1;
    s += strspn(s, " \t");
    char *colon = strstr(s, ": ");
    if (colon && strspn(s, "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_") ==
                     (size_t)(colon - s))
        s = colon + 2;
    return s;
}

static int teem_fail(const char *path, c5_err *err)
{
    char *all = biffGetDone(NRRD);
    const char *cause = all ? teem_cause(all) : "";
    c5_fail(err, "%s: cannot read NRRD: %s", path, *cause ? cause : "unknown Teem error");
    free(all);
    return -1;
}

/* Checks what the loader accepts in Teem's reading (the precheck read the same header). */
static int nrrd_check(const char *path, const Nrrd *n, size_t dims[3], c5_voxel_type *type,
                      c5_err *err)
{
    if (n->type == nrrdTypeUChar)
        *type = C5_VOX_U8;
    else if (n->type == nrrdTypeUShort)
        *type = C5_VOX_U16;
    else
        return c5_fail(err, "%s: unsupported voxel type '%s' (uint8 or uint16 only)", path,
                       airEnumStr(nrrdType, n->type));
    if (n->dim != 3)
        return c5_fail(err, "%s: %u-D NRRD, only 3-D scalar volumes are supported", path,
                       n->dim);
    for (unsigned a = 0; a < 3; a++) {
        int k = n->axis[a].kind;
        /* A 3-D RGB image is 3-D too, but its colour axis is not space. */
        if (k != nrrdKindUnknown && !nrrdKindIsDomain(k))
            return c5_fail(err, "%s: axis %u has kind '%s', only 3-D scalar volumes are supported",
                           path, a, airEnumStr(nrrdKind, k));
        dims[a] = n->axis[a].size;
    }
    size_t count;
    if (c5_dims_product(dims, &count) != 0)
        return c5_dims_fail(path, dims, err);
    return 0;
}

/* Magnitude of the voxel step: axis spacing when set, else the length of the axis'
 * space direction; 0 when the header says neither. */
static double nrrd_spacing(const Nrrd *n, unsigned a)
{
    double s = n->axis[a].spacing;
    if (!airExists(s)) {
        double vec[NRRD_SPACE_DIM_MAX];
        if (nrrdSpacingCalculate(n, a, &s, vec) != nrrdSpacingStatusDirection)
            return 0;
    }
    return airExists(s) ? fabs(s) : 0;
}

/* Teem's reading of a header the precheck passed must be the precheck's: if they ever
 * disagreed, the sizes checked would not be the sizes Teem reads. */
static int same_reading(const Nrrd *n, const NrrdIoState *nio, const c5_nrrd_header *h)
{
    const NrrdEncoding *enc = h->encoding == C5_NRRD_GZIP ? nrrdEncodingGzip : nrrdEncodingRaw;
    int type = h->type == C5_VOX_U16 ? nrrdTypeUShort : nrrdTypeUChar;
    if (n->dim != 3 || n->type != type || nio->encoding != enc ||
        nio->dataFNArr->len != (h->detached ? 1u : 0u) || nio->dataFNFormat)
        return 0;
    for (unsigned a = 0; a < 3; a++)
        if (n->axis[a].size != h->dims[a])
            return 0;
    return 1;
}

/* Teem's reading of a prechecked header h: the data too, or (header_only) the header alone,
 * with the byte order it states in *endian. */
static int nrrd_teem(const char *path, const c5_nrrd_header *h, int header_only, Nrrd **n, int *endian, c5_err *err)
{
    *n = nrrdNew();
    NrrdIoState *nio = nrrdIoStateNew();
    if (!*n || !nio) {
        nrrdIoStateNix(nio);
        *n = nrrdNuke(*n);
        return c5_fail(err, "%s: out of memory", path);
    }
    nio->skipData = header_only ? AIR_TRUE : AIR_FALSE;
    int rc = nrrdLoad(*n, path, nio);
    int same = rc == 0 && same_reading(*n, nio, h);
    if (endian)
        *endian = nio->endian;
    nrrdIoStateNix(nio);
    if (rc != 0) {
        *n = nrrdNuke(*n);
        return teem_fail(path, err);
    }
    if (!same) {
        *n = nrrdNuke(*n);
        return c5_fail(err, "%s: " C5_NRRD_DISAGREE, path);
    }
    return 0;
}

/* The precheck, then Teem's full read (nothing else of Teem ever sees a user's file). */
static int nrrd_load(const char *path, Nrrd **n, c5_err *err)
{
    c5_nrrd_header h;
    *n = NULL;
    if (c5_nrrd_precheck_info(path, &h, err) != 0)
        return -1;
    return nrrd_teem(path, &h, 0, n, NULL, err);
}

int c5_volume_load_nrrd(const char *path, c5_volume *out, c5_err *err)
{
    if (!out)
        return c5_fail(err, "%s: no output volume", path ? path : "(null)");
    memset(out, 0, sizeof *out);
    if (!path)
        return c5_fail(err, "(null): no file name");
    Nrrd *n;
    size_t dims[3];
    c5_voxel_type type = C5_VOX_NONE;
    if (nrrd_load(path, &n, err) != 0)
        return -1;
    if (nrrd_check(path, n, dims, &type, err) != 0) {
        nrrdNuke(n);
        return -1;
    }
    if (!n->data) {
        nrrdNuke(n);
        return c5_fail(err, "%s: NRRD has no data", path);
    }
    for (unsigned a = 0; a < 3; a++)
        out->spacing[a] = nrrd_spacing(n, a);
    /* Teem's buffer is malloc'd (airFree is free): taken over rather than copied. */
    out->data = n->data;
    n->data = NULL;
    nrrdNuke(n);
    memcpy(out->dims, dims, sizeof dims);
    out->type = type;
    return 0;
}

static int has_ext(const char *path, const char *ext);

/* ---- opened for reads at an offset (c5_volume_open) -------------------------------- */

/* An unlinked temporary file in $TMPDIR (else /tmp): gone when closed, even after a crash. */
static int temp_file(const char *path, c5_err *err)
{
    const char *dir = getenv("TMPDIR");
    if (!dir || !*dir)
        dir = "/tmp";
    char name[4200];
    if (snprintf(name, sizeof name, "%s/cube5-inflate-XXXXXX", dir) >= (int)sizeof name)
        return c5_fail(err, "%s: TMPDIR is too long for a temporary file name", path);
    int fd = mkstemp(name);
    if (fd < 0)
        return c5_fail(err, "%s: cannot create a temporary file in %s for the inflated data: %s", path, dir,
                       strerror(errno));
    unlink(name);
    return fd;
}

static int nrrd_open(const char *path, c5_volume_file *out, c5_err *err)
{
    c5_nrrd_header h;
    int tmp = -1;
    if (c5_nrrd_header_info(path, &h, err) != 0)
        return -1;
    if (h.encoding == C5_NRRD_GZIP && (tmp = temp_file(path, err)) < 0)
        return -1;
    /* the whole precheck; gzip data is inflated into tmp on the way */
    if (c5_nrrd_precheck_inflate(path, &h, tmp, err) != 0) {
        if (tmp >= 0)
            close(tmp);
        return -1;
    }
    Nrrd *n;
    int endian = 0;
    if (nrrd_teem(path, &h, 1, &n, &endian, err) != 0) {
        if (tmp >= 0)
            close(tmp);
        return -1;
    }
    size_t dims[3];
    c5_voxel_type type = C5_VOX_NONE;
    if (nrrd_check(path, n, dims, &type, err) != 0) {
        nrrdNuke(n);
        if (tmp >= 0)
            close(tmp);
        return -1;
    }
    for (unsigned a = 0; a < 3; a++)
        out->spacing[a] = nrrd_spacing(n, a);
    nrrdNuke(n);
    memcpy(out->dims, dims, sizeof dims);
    out->type = type;
    out->big_endian = type == C5_VOX_U16 && endian == airEndianBig;
    if (tmp >= 0) {
        out->fd = tmp;
        out->offset = 0;
        return 0;
    }
    long long size;
    char where[sizeof h.data_path + 600];
    snprintf(where, sizeof where, "%s: data file %s", path, h.data_path);
    out->fd = c5_open_regular(h.detached ? h.data_path : path, h.detached ? where : path, &size, err);
    if (out->fd < 0)
        return -1;
    if (size < h.data_offset || (unsigned long long)(size - h.data_offset) < h.data_bytes) {
        close(out->fd);
        out->fd = -1;
        return c5_fail(err, "%s: the file shrank after its check", path);
    }
    out->offset = h.data_offset;
    return 0;
}

static int raw_open(const char *path, const c5_raw_spec *spec, c5_volume_file *out, c5_err *err)
{
    size_t count, bytes;
    long long size;
    int fd = c5_open_regular(path, path, &size, err);
    if (fd < 0)
        return -1;
    if (raw_layout(path, spec, out->dims, &out->type, err) != 0) {
        close(fd);
        return -1;
    }
    if (c5_dims_product(out->dims, &count) != 0 || c5_mul_size(count, voxel_size(out->type), &bytes) != 0) {
        close(fd);
        return c5_dims_fail(path, out->dims, err);
    }
    if ((unsigned long long)size != bytes) {
        char why[64] = "truncated";
        if ((unsigned long long)size > bytes)
            snprintf(why, sizeof why, "%llu extra bytes", (unsigned long long)size - bytes);
        close(fd);
        return c5_fail(err, "%s: file is %lld bytes, expected %zu (%zux%zux%zu %s): %s", path, size, bytes,
                       out->dims[0], out->dims[1], out->dims[2], type_name(out->type), why);
    }
    out->big_endian = out->type == C5_VOX_U16 && spec && spec->big_endian;
    out->fd = fd;
    out->offset = 0;
    return 0;
}

int c5_volume_probe(const char *path, const c5_raw_spec *spec, c5_volume_file *out, c5_err *err)
{
    memset(out, 0, sizeof *out);
    out->fd = -1;
    if (!path)
        return c5_fail(err, "(null): no file name");
    if (!(has_ext(path, ".nrrd") || has_ext(path, ".nhdr"))) {
        if (raw_open(path, spec, out, err) != 0)
            return -1;
        close(out->fd);
        out->fd = -1;
        return 0;
    }
    c5_nrrd_header h;
    if (c5_nrrd_header_info(path, &h, err) != 0)
        return -1;
    memcpy(out->dims, h.dims, sizeof h.dims);
    out->type = h.type;
    return 0;
}

int c5_volume_open(const char *path, const c5_raw_spec *spec, c5_volume_file *out, c5_err *err)
{
    memset(out, 0, sizeof *out);
    out->fd = -1;
    if (!path)
        return c5_fail(err, "(null): no file name");
    int rc = has_ext(path, ".nrrd") || has_ext(path, ".nhdr") ? nrrd_open(path, out, err) : raw_open(path, spec, out, err);
    if (rc != 0) {
        memset(out, 0, sizeof *out);
        out->fd = -1;
    }
    return rc;
}

/* ---- common ---------------------------------------------------------------------- */

static int has_ext(const char *path, const char *ext)
{
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    const char *dot = strrchr(base, '.');
    return dot && strcasecmp(dot, ext) == 0;
}

int c5_volume_load(const char *path, const c5_raw_spec *spec, c5_volume *out, c5_err *err)
{
    if (path && (has_ext(path, ".nrrd") || has_ext(path, ".nhdr")))
        return c5_volume_load_nrrd(path, out, err);
    return c5_volume_load_raw(path, spec, out, err);
}

void c5_volume_free(c5_volume *v)
{
    if (!v)
        return;
    free(v->data);
    memset(v, 0, sizeof *v);
}

size_t c5_volume_count(const c5_volume *v)
{
    if (!v || !v->data)
        return 0;
    return v->dims[0] * v->dims[1] * v->dims[2];
}

unsigned c5_volume_at(const c5_volume *v, size_t i)
{
    if (v->type == C5_VOX_U16)
        return ((const uint16_t *)v->data)[i];
    return ((const uint8_t *)v->data)[i];
}
