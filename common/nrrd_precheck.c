/* The guard in front of Teem's NRRD reader (nrrd_precheck.h, docs/nrrd-teem.md). It reads
 * the header the way Teem's _nrrdFormatNRRD_read does (lines end at \n, \r or \r\n; a line
 * starting with '#' is a comment; "NAME: value" is a field when NAME is one of Teem's field
 * names, case-insensitive; anything else is left to Teem), but only the fields that fix
 * where the data is and how big it is. */
#include "nrrd_precheck.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include <zlib.h>

#define FAIL(...) c5_fail(err, __VA_ARGS__)

/* read() until n bytes or end of file; the count read, or -1. */
static long long read_full(int fd, unsigned char *buf, size_t n)
{
    size_t got = 0;
    while (got < n) {
        ssize_t r = read(fd, buf + got, n - got);
        if (r < 0 && errno == EINTR)
            continue;
        if (r < 0)
            return -1;
        if (r == 0)
            break;
        got += (size_t)r;
    }
    return (long long)got;
}

/* ---- header ------------------------------------------------------------------------- */

typedef struct {
    const char *path;
    c5_nrrd_header *h;
    int seen_type, seen_dim, seen_sizes, seen_enc, seen_data, seen_line, seen_byte;
} parse_state;

/* Teem's spellings of a type (nrrd/enumsNrrd.c, _nrrdTypeStrEqv), each with the name
 * airEnumStr(nrrdType, ...) gives it, for the message. */
static const struct {
    const char *name, *teem;
} TYPES[] = {
    {"signed char", "signed char"}, {"int8", "signed char"}, {"int8_t", "signed char"},
    {"uchar", "uchar"}, {"unsigned char", "uchar"}, {"uint8", "uchar"}, {"uint8_t", "uchar"},
    {"short", "short"}, {"short int", "short"}, {"signed short", "short"},
    {"signed short int", "short"}, {"int16", "short"}, {"int16_t", "short"},
    {"ushort", "ushort"}, {"unsigned short", "ushort"}, {"unsigned short int", "ushort"},
    {"uint16", "ushort"}, {"uint16_t", "ushort"}, {"int", "int"}, {"signed int", "int"},
    {"int32", "int"}, {"int32_t", "int"}, {"uint", "uint"}, {"unsigned int", "uint"},
    {"uint32", "uint"}, {"uint32_t", "uint"}, {"longlong", "longlong"}, {"long long", "longlong"},
    {"long long int", "longlong"}, {"signed long long", "longlong"},
    {"signed long long int", "longlong"}, {"int64", "longlong"}, {"int64_t", "longlong"},
    {"ulonglong", "ulonglong"}, {"unsigned long long", "ulonglong"},
    {"unsigned long long int", "ulonglong"}, {"uint64", "ulonglong"}, {"uint64_t", "ulonglong"},
    {"float", "float"}, {"double", "double"}, {"block", "block"},
};

static int parse_type(parse_state *s, const char *v, c5_err *err)
{
    for (size_t i = 0; i < sizeof TYPES / sizeof TYPES[0]; i++) {
        if (strcasecmp(v, TYPES[i].name) != 0)
            continue;
        if (!strcmp(TYPES[i].teem, "uchar"))
            s->h->type = C5_VOX_U8;
        else if (!strcmp(TYPES[i].teem, "ushort"))
            s->h->type = C5_VOX_U16;
        else
            return FAIL("%s: unsupported voxel type '%s' (uint8 or uint16 only)", s->path, TYPES[i].teem);
        return 0;
    }
    return FAIL("%s: cannot read NRRD: unknown type \"%s\"", s->path, v);
}

/* Strict decimal: digits only (no sign, no space), saturating at max + 1 so that an absurd
 * value still reaches the limit checks and their message. */
static int parse_uint(const char *s, size_t len, unsigned long long max, unsigned long long *out)
{
    if (len == 0)
        return -1;
    unsigned long long n = 0;
    for (size_t i = 0; i < len; i++) {
        if (s[i] < '0' || s[i] > '9')
            return -1;
        unsigned d = (unsigned)(s[i] - '0');
        if (n <= max)
            n = n > (max - d) / 10 ? max + 1 : n * 10 + d;
    }
    *out = n;
    return 0;
}

static int parse_dimension(parse_state *s, const char *v, c5_err *err)
{
    unsigned long long d;
    if (parse_uint(v, strlen(v), 1000, &d) != 0)
        return FAIL("%s: cannot read NRRD: dimension \"%s\" is not a whole number", s->path, v);
    if (d != 3)
        return FAIL("%s: %llu-D NRRD, only 3-D scalar volumes are supported", s->path, d);
    return 0;
}

static int parse_sizes(parse_state *s, const char *v, c5_err *err)
{
    const char *p = v;
    for (unsigned a = 0; a < 3; a++) {
        p += strspn(p, " \t");
        size_t len = strcspn(p, " \t");
        unsigned long long n;
        if (parse_uint(p, len, 999999999999ull, &n) != 0)
            return FAIL("%s: cannot read NRRD: sizes \"%s\" are not 3 whole numbers", s->path, v);
        if (n > 999999999999ull) /* saturated: quote it rather than print the cap */
            return FAIL("%s: dims: size %.*s: every dim must be 1..%u", s->path, (int)len, p, C5_VOLUME_MAX_DIM);
        s->h->dims[a] = (size_t)n;
        p += len;
    }
    if (p[strspn(p, " \t")])
        return FAIL("%s: cannot read NRRD: sizes \"%s\" are not 3 whole numbers", s->path, v);
    return 0;
}

static int parse_encoding(parse_state *s, const char *v, c5_err *err)
{
    static const char *const other[] = {"txt", "text", "ascii", "hex", "bz2", "bzip2", "zrl"};
    if (!strcasecmp(v, "raw")) {
        s->h->encoding = C5_NRRD_RAW;
        return 0;
    }
    if (!strcasecmp(v, "gz") || !strcasecmp(v, "gzip")) {
        s->h->encoding = C5_NRRD_GZIP;
        return 0;
    }
    for (size_t i = 0; i < sizeof other / sizeof other[0]; i++)
        if (!strcasecmp(v, other[i]))
            return FAIL("%s: NRRD encoding '%s' is not supported (raw or gzip only)", s->path, v);
    return FAIL("%s: cannot read NRRD: unknown encoding \"%s\"", s->path, v);
}

static int parse_skip(parse_state *s, const char *v, long *out, int allow_minus_one, const char *what,
                      c5_err *err)
{
    unsigned long long n;
    if (allow_minus_one && !strcmp(v, "-1")) {
        *out = -1;
        return 0;
    }
    if (parse_uint(v, strlen(v), 1u << 30, &n) != 0 || n > (1u << 30))
        return FAIL("%s: cannot read NRRD: %s \"%s\" is not a whole number 0..%u%s", s->path, what, v,
                    1u << 30, allow_minus_one ? " or -1" : "");
    *out = (long)n;
    return 0;
}

/* The one form of "data file" cube5 reads: a single file name, relative to the header's
 * folder unless absolute (Teem's nrrdIoStateDataFileIterNext does the same). */
static int parse_data_file(parse_state *s, const char *v, c5_err *err)
{
    if (!*v)
        return FAIL("%s: cannot read NRRD: empty data file name", s->path);
    if (!strcmp(v, "-"))
        return FAIL("%s: NRRD data file '-' (standard input) is not supported", s->path);
    if (strchr(v, '%') || !strncmp(v, "LIST", 4) || !strncmp(v, "SKIPLIST", 8))
        return FAIL("%s: NRRD data file \"%s\": one data file only (no LIST, SKIPLIST or %%d pattern)",
                    s->path, v);
    const char *slash = strrchr(s->path, '/');
    int n;
    if (v[0] == '/' || !slash)
        n = snprintf(s->h->data_path, sizeof s->h->data_path, "%s", v);
    else
        n = snprintf(s->h->data_path, sizeof s->h->data_path, "%.*s/%s", (int)(slash - s->path), s->path, v);
    if (n < 0 || (size_t)n >= sizeof s->h->data_path)
        return FAIL("%s: NRRD data file name too long", s->path);
    s->h->detached = 1;
    return 0;
}

/* Teem's field names that fix the data's place and size (and their spellings without
 * spaces); every other line is Teem's to judge. */
enum { F_TYPE, F_DIM, F_SIZES, F_ENC, F_DATA, F_LINE, F_BYTE, F_AXIS, F_OTHER };

static int field_of(const char *name)
{
    static const struct {
        const char *name;
        int f;
    } names[] = {{"type", F_TYPE},          {"dimension", F_DIM},  {"sizes", F_SIZES},
                 {"encoding", F_ENC},        {"data file", F_DATA}, {"datafile", F_DATA},
                 {"line skip", F_LINE},      {"lineskip", F_LINE},  {"byte skip", F_BYTE},
                 {"byteskip", F_BYTE},
                 /* one value per axis: Teem needs the dimension first */
                 {"spacings", F_AXIS},       {"thicknesses", F_AXIS}, {"axis mins", F_AXIS},
                 {"axismins", F_AXIS},       {"axis maxs", F_AXIS},   {"axismaxs", F_AXIS},
                 {"space directions", F_AXIS}, {"spacedirections", F_AXIS}, {"centers", F_AXIS},
                 {"centerings", F_AXIS},     {"kinds", F_AXIS},       {"labels", F_AXIS},
                 {"units", F_AXIS}};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if (!strcasecmp(name, names[i].name))
            return names[i].f;
    return F_OTHER;
}

static int parse_line(parse_state *s, char *line, c5_err *err)
{
    if (line[0] == '#')
        return 0;
    char *colon = strstr(line, ": ");
    if (!colon)
        return 0; /* a key/value pair or garbage: Teem's to judge */
    *colon = 0;
    int f = field_of(line);
    const char *name = line;
    char *v = colon + 2;
    v += strspn(v, " \t");
    int *seen[] = {&s->seen_type, &s->seen_dim, &s->seen_sizes, &s->seen_enc,
                   &s->seen_data, &s->seen_line, &s->seen_byte};
    if (f == F_OTHER)
        return 0;
    /* Teem refuses these too, but leaks doing so for kinds and centers (parseNrrd.c's
     * _CHECK_HAVE_DIM returns past its airMop; found by fuzz/fuzz_volume.c) */
    if (f == F_AXIS || f == F_SIZES) {
        if (!s->seen_dim)
            return FAIL("%s: cannot read NRRD: field \"%s\" before dimension", s->path, name);
        if (f == F_AXIS)
            return 0;
    }
    if (*seen[f])
        return FAIL("%s: cannot read NRRD: field \"%s\" given twice", s->path, name);
    *seen[f] = 1;
    switch (f) {
    case F_TYPE: return parse_type(s, v, err);
    case F_DIM: return parse_dimension(s, v, err);
    case F_SIZES: return parse_sizes(s, v, err);
    case F_ENC: return parse_encoding(s, v, err);
    case F_DATA: return parse_data_file(s, v, err);
    case F_LINE: return parse_skip(s, v, &s->h->line_skip, 0, "line skip", err);
    default: return parse_skip(s, v, &s->h->byte_skip, 1, "byte skip", err);
    }
}

/* Length of the line end at p ("\n", "\r", "\r\n"), 0 when p is not one. */
static size_t line_end(const unsigned char *p, const unsigned char *end)
{
    if (p < end && *p == '\n')
        return 1;
    if (p < end && *p == '\r')
        return p + 1 < end && p[1] == '\n' ? 2 : 1;
    return 0;
}

/* Walks the header in buf[0..n); *data_at = the offset after the blank line that ends an
 * attached header, 0 when the header ends with the file (a detached header may). */
static int parse_header(parse_state *s, unsigned char *buf, size_t n, int whole_file, size_t *data_at,
                        c5_err *err)
{
    static const char *const magics[] = {"NRRD0001", "NRRD0002", "NRRD0003", "NRRD0004", "NRRD0005"};
    const unsigned char *end = buf + n;
    unsigned char *p = buf;
    for (unsigned lineno = 1;; lineno++) {
        unsigned char *q = p;
        while (q < end && *q != '\n' && *q != '\r' && (*q == '\t' || (*q >= 0x20 && *q < 0x7f)))
            q++;
        if (q < end && *q == 0)
            return FAIL("%s: cannot read NRRD: a NUL byte in header line %u", s->path, lineno);
        /* Teem's airOneLinify reads before a comment (or content, label, unit) whose every
         * byte is unprintable; a NRRD header is ASCII text anyway. */
        if (q < end && *q != '\n' && *q != '\r')
            return FAIL("%s: cannot read NRRD: byte 0x%02x in header line %u (a header is printable ASCII)",
                        s->path, *q, lineno);
        if ((size_t)(q - p) > C5_NRRD_LINE_MAX)
            return FAIL("%s: cannot read NRRD: header line %u is longer than %d bytes", s->path, lineno,
                        C5_NRRD_LINE_MAX);
        size_t le = line_end(q, end);
        if (!le) {
            if (!whole_file)
                return FAIL("%s: cannot read NRRD: header longer than %d bytes", s->path, C5_NRRD_HEADER_MAX);
            if (q > p) /* Teem drops such a line without a word */
                return FAIL("%s: cannot read NRRD: header line %u has no line end", s->path, lineno);
            *data_at = 0;
            return lineno == 1 ? FAIL("%s: cannot read NRRD: empty file", s->path) : 0;
        }
        *q = 0;
        if (lineno == 1) {
            int ok = 0;
            for (size_t i = 0; i < sizeof magics / sizeof magics[0]; i++)
                ok |= !strcmp((char *)p, magics[i]);
            if (!ok)
                return FAIL("%s: cannot read NRRD: the first line is not NRRD0001..NRRD0005", s->path);
        } else if (q == p) {
            *data_at = (size_t)(q + le - buf);
            return 0;
        } else if (parse_line(s, (char *)p, err) != 0) {
            return -1;
        }
        p = q + le;
    }
}

/* ---- data --------------------------------------------------------------------------- */

/* Skips `lines` line ends (Teem's airOneLine: \n, \r or \r\n) from the descriptor's
 * position; the bytes consumed, or -1 when the file ends first. */
static long long skip_lines(int fd, long lines)
{
    unsigned char buf[4096];
    long long used = 0, pending_cr = 0;
    size_t n = 0, i = 0;
    while (lines > 0 || pending_cr) {
        if (i == n) {
            long long r = read_full(fd, buf, sizeof buf);
            if (r <= 0)
                return pending_cr && lines == 0 ? used : -1;
            n = (size_t)r;
            i = 0;
        }
        if (pending_cr) { /* after \r, a \n belongs to the same line end */
            pending_cr = 0;
            if (buf[i] == '\n') {
                i++;
                used++;
            }
            continue;
        }
        unsigned char c = buf[i++];
        used++;
        if (c == '\n')
            lines--;
        else if (c == '\r') {
            lines--;
            pending_cr = 1;
        }
    }
    return used;
}

/* Writes all n bytes at the descriptor's position; 0, or -1 with errno. */
static int write_full(int fd, const unsigned char *p, size_t n)
{
    while (n > 0) {
        ssize_t w = write(fd, p, n);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            return -1;
        p += w;
        n -= (size_t)w;
    }
    return 0;
}

/* Inflates one gzip member from fd, counting its output; 0 when it gives exactly `want`
 * bytes and nothing follows it. With out_fd >= 0 the output after its first `skip` bytes
 * (the voxels) is written there as it comes, else it is not kept. */
static int check_gzip(int fd, const char *path, size_t want, int out_fd, size_t skip, c5_err *err)
{
    z_stream z;
    memset(&z, 0, sizeof z);
    if (inflateInit2(&z, 16 + MAX_WBITS) != Z_OK)
        return FAIL("%s: out of memory for the gzip check", path);
    enum { IN = 16384, OUT = 65536 };
    unsigned char *in = malloc(IN), *out = malloc(OUT);
    unsigned long long total = 0;
    int rc = Z_OK, ok = -1;
    long long r = 0;
    if (!in || !out) {
        FAIL("%s: out of memory for the gzip check", path);
        goto done;
    }
    while (rc != Z_STREAM_END) {
        if (z.avail_in == 0) {
            r = read_full(fd, in, IN);
            if (r < 0) {
                FAIL("%s: read failed: %s", path, strerror(errno));
                goto done;
            }
            if (r == 0) {
                FAIL("%s: gzip data ends early (%llu of %zu bytes)", path, total, want);
                goto done;
            }
            z.next_in = in;
            z.avail_in = (uInt)r;
        }
        z.next_out = out;
        z.avail_out = OUT;
        rc = inflate(&z, Z_NO_FLUSH);
        if (rc != Z_OK && rc != Z_STREAM_END) {
            FAIL("%s: gzip data is corrupt (%s)", path, z.msg ? z.msg : "inflate failed");
            goto done;
        }
        size_t made = OUT - z.avail_out;
        if (total + made > want) {
            FAIL("%s: gzip data holds more than the %zu bytes the header declares", path, want);
            goto done;
        }
        if (out_fd >= 0 && total + made > skip) {
            size_t from = total >= skip ? 0 : (size_t)(skip - total);
            if (write_full(out_fd, out + from, made - from) != 0) {
                FAIL("%s: cannot write the inflated data to a temporary file: %s", path, strerror(errno));
                goto done;
            }
        }
        total += made;
    }
    if (total != want) {
        FAIL("%s: gzip data holds %llu bytes, the header declares %zu", path, total, want);
        goto done;
    }
    if (z.avail_in > 0 || read_full(fd, in, 1) != 0) {
        FAIL("%s: bytes after the gzip data (one gzip stream of exactly the data only)", path);
        goto done;
    }
    ok = 0;
done:
    inflateEnd(&z);
    free(in);
    free(out);
    return ok;
}

/* Checks the data at offset `at` of the open file fd (of `size` bytes) against the header. */
static int check_data(int fd, const char *path, long long size, long long at, c5_nrrd_header *h, int out_fd,
                      c5_err *err)
{
    if (lseek(fd, (off_t)at, SEEK_SET) < 0)
        return FAIL("%s: cannot seek: %s", path, strerror(errno));
    if (h->line_skip > 0) {
        long long used = skip_lines(fd, h->line_skip);
        if (used < 0)
            return FAIL("%s: the file ends within the %ld lines to skip", path, h->line_skip);
        at += used;
    }
    unsigned long long left = (unsigned long long)(size - at);
    if (h->encoding == C5_NRRD_GZIP) {
        if (h->byte_skip < 0)
            return FAIL("%s: byte skip -1 with gzip encoding is not supported", path);
        h->data_offset = at;
        return check_gzip(fd, path, h->data_bytes + (size_t)h->byte_skip, out_fd, (size_t)h->byte_skip, err);
    }
    if (h->byte_skip < 0) {
        if (left < h->data_bytes)
            return FAIL("%s: data is %llu bytes, expected at least %zu", path, left, h->data_bytes);
        h->data_offset = size - (long long)h->data_bytes; /* byte skip -1: the data ends the file */
        return 0;
    }
    h->data_offset = at + h->byte_skip;
    unsigned long long want = (unsigned long long)h->byte_skip + h->data_bytes;
    if (left != want) /* a raw loader's rule: the exact size, so that /etc/passwd is no volume */
        return FAIL("%s: data is %llu bytes, expected %llu (%zux%zux%zu %s%s): %s", path, left, want,
                    h->dims[0], h->dims[1], h->dims[2], h->type == C5_VOX_U16 ? "uint16" : "uint8",
                    h->byte_skip ? " after the byte skip" : "", left < want ? "truncated" : "extra bytes");
    return 0;
}

static int precheck(const char *path, c5_nrrd_header *info, int with_data, int out_fd, c5_err *err)
{
    c5_nrrd_header local;
    c5_nrrd_header *h = info ? info : &local;
    memset(h, 0, sizeof *h);
    if (!path)
        return FAIL("(null): no file name");
    long long size;
    int fd = c5_open_regular(path, path, &size, err);
    if (fd < 0)
        return -1;
    size_t cap = size < C5_NRRD_HEADER_MAX ? (size_t)size : C5_NRRD_HEADER_MAX;
    unsigned char *buf = malloc(cap + 1);
    int rc = -1;
    size_t data_at = 0;
    parse_state s = {.path = path, .h = h};
    if (!buf) {
        FAIL("%s: out of memory", path);
        goto done;
    }
    long long got = read_full(fd, buf, cap);
    if (got != (long long)cap) {
        FAIL("%s: read failed: %s", path, got < 0 ? strerror(errno) : "file shrank while reading");
        goto done;
    }
    if (parse_header(&s, buf, cap, (long long)cap == size, &data_at, err) != 0)
        goto done;
    if (!s.seen_type || !s.seen_dim || !s.seen_sizes || !s.seen_enc) {
        FAIL("%s: cannot read NRRD: the header lacks %s", path,
             !s.seen_type ? "type" : !s.seen_dim ? "dimension" : !s.seen_sizes ? "sizes" : "encoding");
        goto done;
    }
    size_t count;
    if (c5_dims_product(h->dims, &count) != 0) {
        c5_dims_fail(path, h->dims, err);
        goto done;
    }
    h->data_bytes = count * (h->type == C5_VOX_U16 ? 2 : 1);
    if (!with_data) {
        rc = 0;
        goto done;
    }
    if (!h->detached) {
        if (!data_at) {
            FAIL("%s: cannot read NRRD: the header ends without a blank line or a data file", path);
            goto done;
        }
        rc = check_data(fd, path, size, (long long)data_at, h, out_fd, err);
        goto done;
    }
    close(fd);
    /* Messages name the header too: the data file alone does not say where it came from. */
    char where[sizeof h->data_path + 600];
    snprintf(where, sizeof where, "%s: data file %s", path, h->data_path);
    fd = c5_open_regular(h->data_path, where, &size, err);
    if (fd >= 0)
        rc = check_data(fd, where, size, 0, h, out_fd, err);
done:
    free(buf);
    if (fd >= 0)
        close(fd);
    return rc;
}

int c5_nrrd_precheck_info(const char *path, c5_nrrd_header *info, c5_err *err)
{
    return precheck(path, info, 1, -1, err);
}

int c5_nrrd_precheck_inflate(const char *path, c5_nrrd_header *info, int out_fd, c5_err *err)
{
    return precheck(path, info, 1, out_fd, err);
}

int c5_nrrd_precheck(const char *path, c5_err *err) { return c5_nrrd_precheck_info(path, NULL, err); }

int c5_nrrd_header_info(const char *path, c5_nrrd_header *info, c5_err *err)
{
    return precheck(path, info, 0, -1, err);
}
