/* The guard in front of Teem (common/nrrd_precheck.c): every class of input it refuses,
 * that it accepts what Teem reads well, and that the loader goes through it. Each refusal
 * here was a crash, an over-read, a leak, a hang or a silent wrong volume in Teem or in the
 * loader before (docs/nrrd-teem.md). Inputs are written into the test's temp dir. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <zlib.h>

#include "harness.h"
#include "nrrd_precheck.h"
#include "volume.h"

static int write_file(const char *path, const void *a, size_t na, const void *b, size_t nb)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return -1;
    int ok = (na == 0 || fwrite(a, 1, na, f) == na) && (nb == 0 || fwrite(b, 1, nb, f) == nb);
    return (fclose(f) == 0 && ok) ? 0 : -1;
}

static int write_text(const char *path, const char *text) { return write_file(path, text, strlen(text), NULL, 0); }

/* gzip (not zlib) framing of n bytes into out; the compressed size, or 0. */
static size_t gzip_bytes(const void *in, size_t n, unsigned char *out, size_t cap)
{
    z_stream z;
    memset(&z, 0, sizeof z);
    if (deflateInit2(&z, 6, Z_DEFLATED, 16 + MAX_WBITS, 8, Z_DEFAULT_STRATEGY) != Z_OK)
        return 0;
    z.next_in = (unsigned char *)(uintptr_t)in;
    z.avail_in = (uInt)n;
    z.next_out = out;
    z.avail_out = (uInt)cap;
    int rc = deflate(&z, Z_FINISH);
    size_t used = cap - z.avail_out;
    deflateEnd(&z);
    return rc == Z_STREAM_END ? used : 0;
}

/* Precheck of a file holding `text`: expect a refusal whose message has `needle`. */
#define CHECK_REFUSED_TEXT(name, text, needle)                                                   \
    do {                                                                                         \
        const char *p_ = c5t_path(0, name);                                                      \
        CHECK(write_text(p_, text) == 0);                                                        \
        c5_err e_ = {{0}};                                                                       \
        CHECK_MSG(c5_nrrd_precheck(p_, &e_) == -1, "%s: accepted", name);                       \
        CHECK_HAS(e_.msg, needle);                                                               \
        CHECK_MSG(strchr(e_.msg, '\n') == NULL, "not one line: %s", e_.msg);                     \
    } while (0)

#define HEAD3(sizes, extra) "NRRD0004\ntype: uchar\ndimension: 3\nsizes: " sizes "\nencoding: raw\n" extra

TEST(nrrd_precheck_header_text)
{
    char line[C5_NRRD_LINE_MAX + 64];
    memset(line, 'A', sizeof line);
    memcpy(line, "NRRD0004\ntype: ", 15);
    strcpy(line + sizeof line - 3, "\n\n");
    /* Teem formats a long line into a 1025-byte stack buffer: abort */
    CHECK_REFUSED_TEXT("long.nrrd", line, "header line 2 is longer than 400 bytes");
    CHECK_REFUSED_TEXT("magic.nrrd", "NRRD000nany\n" HEAD3("2 2 2", "\n"), "the first line is not NRRD0001..NRRD0005");
    CHECK_REFUSED_TEXT("text.nrrd", "# a comment\n1 2\n", "the first line is not NRRD0001");
    /* a comment of unprintable bytes: airOneLinify reads before it */
    CHECK_REFUSED_TEXT("comment.nrrd", "NRRD0004\n#\xff\xff\n" HEAD3("2 2 2", "\n"), "byte 0xff in header line 2");
    CHECK_REFUSED_TEXT("noeol.nhdr", HEAD3("2 2 2", "data file: x.raw"), "header line 6 has no line end");
    CHECK_REFUSED_TEXT("noend.nhdr", HEAD3("2 2 2", ""), "ends without a blank line or a data file");
    CHECK_REFUSED_TEXT("empty.nrrd", "", "empty file");
    CHECK_REFUSED_TEXT("twice.nrrd", HEAD3("2 2 2", "type: uchar\n\n"), "field \"type\" given twice");
    CHECK_REFUSED_TEXT("nosizes.nrrd", "NRRD0004\ntype: uchar\ndimension: 3\nencoding: raw\n\n", "lacks sizes");
    CHECK_REFUSED_TEXT("bz.nrrd", "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 1 1 1\nencoding: bzip2\n\nx",
                       "encoding 'bzip2' is not supported (raw or gzip only)");
    CHECK_REFUSED_TEXT("float.nrrd", "NRRD0004\ntype: float\ndimension: 3\nsizes: 1 1 1\nencoding: raw\n\nxxxx",
                       "unsupported voxel type 'float'");
    CHECK_REFUSED_TEXT("2d.nrrd", "NRRD0004\ntype: uchar\ndimension: 2\nsizes: 1 1\nencoding: raw\n\nx",
                       "2-D NRRD, only 3-D");
    CHECK_REFUSED_TEXT("sizes.nrrd", HEAD3("2 2 +2", "\n"), "are not 3 whole numbers");
    CHECK_REFUSED_TEXT("huge.nrrd", HEAD3("2 99999999999999999999999 2", "\n"),
                       "dims: size 99999999999999999999999: every dim must be 1..65535");
    /* Teem leaks its mop refusing kinds or centers before the dimension */
    CHECK_REFUSED_TEXT("kinds.nrrd", "NRRD0004\nkinds: domain domain domain\ntype: uchar\ndimension: 3\n",
                       "field \"kinds\" before dimension");
    CHECK_REFUSED_TEXT("centers.nrrd", "NRRD0004\ncenterings: cell cell cell\ndimension: 3\n",
                       "field \"centerings\" before dimension");

    /* a NUL anywhere in the header (here: inside a data file name) */
    const char *p = c5t_path(0, "nul.nhdr");
    static const char nul[] = HEAD3("1 1 1", "data file: \0x.raw\n");
    CHECK(write_file(p, nul, sizeof nul - 1, NULL, 0) == 0);
    c5_err e = {{0}};
    CHECK(c5_nrrd_precheck(p, &e) == -1);
    CHECK_HAS(e.msg, "a NUL byte in header line 6");
}

TEST(nrrd_precheck_data_file_forms)
{
    CHECK_REFUSED_TEXT("empty.nhdr", HEAD3("1 1 1", "data file: \n"), "empty data file name");
    CHECK_REFUSED_TEXT("stdin.nhdr", HEAD3("1 1 1", "data file: -\n"), "'-' (standard input) is not supported");
    CHECK_REFUSED_TEXT("list.nhdr", HEAD3("1 1 2", "data file: LIST\na.raw\nb.raw\n"), "one data file only");
    CHECK_REFUSED_TEXT("fmt.nhdr", HEAD3("1 1 2", "data file: s%03d.raw 1 2 1\n"), "one data file only");
    CHECK_REFUSED_TEXT("gone.nhdr", HEAD3("1 1 1", "data file: gone.raw\n"), "gone.raw: cannot open: No such file");
    /* not regular files: a FIFO would block open() forever, /dev/zero never ends */
    CHECK_REFUSED_TEXT("zero.nhdr", HEAD3("4 4 4", "data file: /dev/zero\n"), "/dev/zero: not a regular file");
    CHECK(mkfifo(c5t_path(1, "fifo"), 0600) == 0);
    CHECK_REFUSED_TEXT("fifo.nhdr", HEAD3("4 4 4", "data file: fifo\n"), "data file ");
    CHECK_REFUSED_TEXT("fifo.nhdr", HEAD3("4 4 4", "data file: fifo\n"), "fifo: not a regular file");
    /* a readable file of another size: /etc/passwd is no volume */
    CHECK_REFUSED_TEXT("passwd.nhdr", HEAD3("16 16 4", "data file: /etc/passwd\n"), "expected 1024");
}

TEST(nrrd_precheck_raw_sizes)
{
    unsigned char buf[64] = {0};
    const char *p = c5t_path(0, "r.nrrd");
    static const char h[] = HEAD3("2 2 2", "\n");
    c5_err e = {{0}};
    CHECK(write_file(p, h, sizeof h - 1, buf, 8) == 0);
    CHECK_MSG(c5_nrrd_precheck(p, &e) == 0, "%s", e.msg);
    CHECK(write_file(p, h, sizeof h - 1, buf, 9) == 0);
    CHECK(c5_nrrd_precheck(p, &e) == -1);
    CHECK_HAS(e.msg, "r.nrrd: data is 9 bytes, expected 8 (2x2x2 uint8): extra bytes");
    CHECK(write_file(p, h, sizeof h - 1, buf, 7) == 0);
    CHECK(c5_nrrd_precheck(p, &e) == -1);
    CHECK_HAS(e.msg, "truncated");
    /* 71 bytes claiming 65535x65535x1: refused before anything is allocated */
    static const char big[] = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 65535 65535 1\nencoding: raw\n\n";
    CHECK(write_file(p, big, sizeof big - 1, buf, 1) == 0);
    CHECK(c5_nrrd_precheck(p, &e) == -1);
    CHECK_HAS(e.msg, "expected 4294836225");

    /* byte skip and line skip count; byte skip -1 takes the last bytes */
    const char *ph = c5t_path(1, "s.nhdr");
    const char *pd = c5t_path(2, "s.raw");
    CHECK(write_text(ph, HEAD3("2 2 1", "byte skip: 3\nline skip: 2\ndata file: s.raw\n")) == 0);
    CHECK(write_file(pd, "a\r\nb\rxyz", 8, "1234", 4) == 0);
    c5_nrrd_header info;
    CHECK_MSG(c5_nrrd_precheck_info(ph, &info, &e) == 0, "%s", e.msg);
    CHECK_INT(info.detached, 1);
    CHECK_INT(info.data_bytes, 4);
    CHECK_HAS(info.data_path, "/s.raw");
    CHECK(write_text(ph, HEAD3("2 2 1", "byte skip: -1\ndata file: s.raw\n")) == 0);
    CHECK_MSG(c5_nrrd_precheck(ph, &e) == 0, "%s", e.msg);
    CHECK(write_text(ph, HEAD3("2 2 1", "line skip: 9\ndata file: s.raw\n")) == 0);
    CHECK(c5_nrrd_precheck(ph, &e) == -1);
    CHECK_HAS(e.msg, "ends within the 9 lines to skip");
}

TEST(nrrd_precheck_gzip)
{
    unsigned char raw[256], gz[512], file[600];
    for (int i = 0; i < 256; i++)
        raw[i] = (unsigned char)(i * 13);
    static const char h[] = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 8 8 4\nencoding: gzip\n\n";
    size_t nz = gzip_bytes(raw, sizeof raw, gz, sizeof gz);
    CHECK(nz > 0);
    const char *p = c5t_path(0, "g.nrrd");
    c5_err e = {{0}};
    CHECK(write_file(p, h, sizeof h - 1, gz, nz) == 0);
    CHECK_MSG(c5_nrrd_precheck(p, &e) == 0, "%s", e.msg);
    /* and Teem then reads it */
    c5_volume v;
    CHECK_MSG(c5_volume_load(p, NULL, &v, &e) == 0, "%s", e.msg);
    CHECK_INT(c5_volume_at(&v, 255), raw[255]);
    c5_volume_free(&v);
    /* trailing bytes after the stream */
    memcpy(file, gz, nz);
    memcpy(file + nz, "junk", 4);
    CHECK(write_file(p, h, sizeof h - 1, file, nz + 4) == 0);
    CHECK(c5_nrrd_precheck(p, &e) == -1);
    CHECK_HAS(e.msg, "bytes after the gzip data");
    /* a stream cut short, a corrupt one, one that inflates to more than declared */
    CHECK(write_file(p, h, sizeof h - 1, gz, nz / 2) == 0);
    CHECK(c5_nrrd_precheck(p, &e) == -1);
    CHECK_HAS(e.msg, "gzip data ends early");
    memcpy(file, gz, nz);
    for (size_t i = 12; i < nz - 8; i++)
        file[i] ^= 0x5a;
    CHECK(write_file(p, h, sizeof h - 1, file, nz) == 0);
    CHECK(c5_nrrd_precheck(p, &e) == -1);
    CHECK_HAS(e.msg, "g.nrrd: gzip data");
    static const char small[] = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 8 8 2\nencoding: gz\n\n";
    CHECK(write_file(p, small, sizeof small - 1, gz, nz) == 0);
    CHECK(c5_nrrd_precheck(p, &e) == -1);
    CHECK_HAS(e.msg, "gzip data holds more than the 128 bytes the header declares");
}

TEST(nrrd_load_goes_through_the_precheck)
{
    /* The loader refuses with the precheck's words: Teem never sees these files. */
    const char *p = c5t_path(0, "x.nrrd");
    CHECK(write_text(p, "NRRD0004\n#\x80\n" HEAD3("1 1 1", "\nx")) == 0);
    c5_volume v;
    c5_err e = {{0}};
    CHECK(c5_volume_load(p, NULL, &v, &e) == -1);
    CHECK_HAS(e.msg, "byte 0x80 in header line 2");
    CHECK(v.data == NULL);
    /* a header-only volume_load of a missing raw file names it missing */
    CHECK(c5_volume_load("/nonexistent/missing.raw", NULL, &v, &e) == -1);
    CHECK_HAS(e.msg, "/nonexistent/missing.raw: cannot open: No such file or directory");
    /* a raw file that is a FIFO: refused, not a blocked open() */
    const char *fifo = c5t_path(1, "f_2x2x2_uint8.raw");
    CHECK(mkfifo(fifo, 0600) == 0);
    CHECK(c5_volume_load(fifo, NULL, &v, &e) == -1);
    CHECK_HAS(e.msg, "f_2x2x2_uint8.raw: not a regular file");
}

/* c5_nrrd_header_info: every header rule, nothing of the data (the output check and the
 * model's limits need only the sizes and the data file's name; the load checks the data). */
TEST(nrrd_header_info_reads_the_header_alone)
{
    const char *hdr = c5t_path(0, "alone.nhdr");
    CHECK(write_text(hdr, HEAD3("4 5 6", "data file: absent.raw\n")) == 0);
    c5_nrrd_header h;
    c5_err e = {{0}};
    CHECK_MSG(c5_nrrd_header_info(hdr, &h, &e) == 0, "%s", e.msg);
    CHECK(h.dims[0] == 4 && h.dims[1] == 5 && h.dims[2] == 6 && h.detached);
    CHECK_HAS(h.data_path, "absent.raw");
    CHECK(c5_nrrd_precheck(hdr, &e) == -1);
    CHECK_HAS(e.msg, "absent.raw");

    const char *gz = c5t_path(0, "corrupt.nrrd");
    CHECK(write_text(gz, "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: gzip\n\nnot gzip") == 0);
    CHECK_MSG(c5_nrrd_header_info(gz, &h, &e) == 0, "%s", e.msg);
    CHECK(h.encoding == C5_NRRD_GZIP && h.data_bytes == 8);
    CHECK(c5_nrrd_precheck(gz, &e) == -1);

    char line[600];
    snprintf(line, sizeof line, "NRRD0004\n# %0500d\n", 0);
    const char *lng = c5t_path(0, "long_alone.nrrd");
    CHECK(write_text(lng, line) == 0);
    CHECK(c5_nrrd_header_info(lng, &h, &e) == -1);
    CHECK_HAS(e.msg, "longer than 400 bytes");
}
