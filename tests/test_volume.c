/* Volume loading: Open SciVis names, raw files, NRRD through Teem, and every error path.
 * Every input file is written into the test's temp dir here. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <teem/nrrd.h>

#include "harness.h"
#include "volume.h"

/* ---- helpers --------------------------------------------------------------------- */

static void fill_ramp(unsigned char *p, size_t n)
{
    for (size_t i = 0; i < n; i++)
        p[i] = (unsigned char)(i * 7 + 3);
}

/* 16-bit test values that differ in both bytes, so a byte-order slip shows. */
static uint16_t u16_value(size_t i) { return (uint16_t)(0x0102 + i * 0x1011); }

static void put_u16(unsigned char *p, size_t n, int big_endian)
{
    for (size_t i = 0; i < n; i++) {
        uint16_t v = u16_value(i);
        p[2 * i + (big_endian ? 0 : 1)] = (unsigned char)(v >> 8);
        p[2 * i + (big_endian ? 1 : 0)] = (unsigned char)(v & 0xff);
    }
}

/* A failed load must leave an empty volume and a one-line message. */
static int failed_cleanly(int rc, const c5_volume *v, const c5_err *e)
{
    return rc == -1 && v->data == NULL && v->dims[0] == 0 && e->msg[0] != 0 &&
           strchr(e->msg, '\n') == NULL;
}

#define CHECK_FAILS(rc, v, e) \
    CHECK_MSG(failed_cleanly((rc), &(v), &(e)), "expected a clean failure, got rc=%d msg \"%s\"", (rc), (e).msg)

/* ---- Open SciVis names ----------------------------------------------------------- */

TEST(volume_scivis_name_good)
{
    size_t d[3];
    c5_voxel_type t;
    CHECK_INT(c5_scivis_name("/data/skull_256x256x256_uint8.raw", d, &t), 0);
    CHECK_INT(d[0], 256);
    CHECK_INT(d[1], 256);
    CHECK_INT(d[2], 256);
    CHECK_INT(t, C5_VOX_U8);
    CHECK_INT(c5_scivis_name("csafe_heptane_302x301x300_uint16.raw", d, &t), 0);
    CHECK_INT(d[0], 302);
    CHECK_INT(d[1], 301);
    CHECK_INT(d[2], 300);
    CHECK_INT(t, C5_VOX_U16);
    /* Only the base name counts, whatever the folders look like. */
    CHECK_INT(c5_scivis_name("a_1x1x1_uint16.raw/b_2x3x4_uint8.raw", d, &t), 0);
    CHECK_INT(d[0], 2);
    CHECK_INT(d[2], 4);
    CHECK_INT(t, C5_VOX_U8);
    /* The name is about form; the dims check comes later. */
    CHECK_INT(c5_scivis_name("vol_0x10x10_uint8.raw", d, &t), 0);
    CHECK_INT(d[0], 0);
}

TEST(volume_scivis_name_bad)
{
    static const char *bad[] = {
        "vol_10x10_uint8.raw",      "vol_10x10x10_int16.raw",  "vol_10x10x10_float32.raw",
        "vol_10x10x10_uint8.dat",   "vol_10x10x10_uint8.raw.gz", "10x10x10_uint8.raw",
        "_10x10x10_uint8.raw",      "vol_axbxc_uint8.raw",     "vol_10x10x10x_uint8.raw",
        "vol_10x-1x10_uint8.raw",   "vol_10xx10_uint8.raw",    "vol_10x10x10_.raw",
        "vol_10x10x10_UINT8.raw",   "vol_10x10x10uint8.raw",   "",
        ".raw",                     "dir_2x2x2_uint8.raw/vol", "vol_ 1x2x3_uint8.raw",
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        size_t d[3] = {7, 7, 7};
        c5_voxel_type t = C5_VOX_U16;
        CHECK_MSG(c5_scivis_name(bad[i], d, &t) == -1, "accepted \"%s\"", bad[i]);
    }
}

/* ---- dims ------------------------------------------------------------------------ */

TEST(volume_dims_product)
{
    size_t n = 0;
    CHECK_INT(c5_dims_product((size_t[3]){2, 3, 4}, &n), 0);
    CHECK_INT(n, 24);
    CHECK_INT(c5_dims_product((size_t[3]){65535, 1, 1}, &n), 0);
    CHECK_INT(n, 65535);
    CHECK_INT(c5_dims_product((size_t[3]){4096, 4096, 256}, &n), 0);
    CHECK_INT(n, (size_t)1 << 32);
    CHECK_INT(c5_dims_product((size_t[3]){2048, 2048, 2048}, &n), 0); /* 8 GiB: out of core */
    CHECK_INT(n, (size_t)1 << 33);
    CHECK_INT(c5_dims_product((size_t[3]){65535, 65535, 4096}, &n), 0);
    CHECK_INT(c5_dims_product((size_t[3]){65535, 65535, 4097}, &n), -1); /* past 2^44 */
    CHECK_INT(c5_dims_product((size_t[3]){0, 10, 10}, &n), -1);
    CHECK_INT(c5_dims_product((size_t[3]){65536, 1, 1}, &n), -1);
    CHECK_INT(c5_dims_product((size_t[3]){(size_t)1 << 32, (size_t)1 << 32, 2}, &n), -1);
    CHECK_INT(c5_dims_product((size_t[3]){SIZE_MAX, SIZE_MAX, SIZE_MAX}, &n), -1);
}

/* ---- raw ------------------------------------------------------------------------- */

TEST(volume_raw_u8_scivis)
{
    unsigned char buf[4 * 3 * 2];
    fill_ramp(buf, sizeof buf);
    const char *p = c5t_path(0, "vol_4x3x2_uint8.raw");
    CHECK(c5t_write_file(p, NULL, buf, sizeof buf) == 0);
    c5_volume v;
    c5_err e = {{0}};
    CHECK_MSG(c5_volume_load(p, NULL, &v, &e) == 0, "%s", e.msg);
    CHECK_INT(v.dims[0], 4);
    CHECK_INT(v.dims[1], 3);
    CHECK_INT(v.dims[2], 2);
    CHECK_INT(v.type, C5_VOX_U8);
    CHECK_INT(c5_volume_count(&v), 24);
    for (size_t i = 0; i < sizeof buf; i++)
        CHECK_INT(c5_volume_at(&v, i), buf[i]);
    CHECK_NEAR(v.spacing[0] + v.spacing[1] + v.spacing[2], 0, 0);
    c5_volume_free(&v);
    CHECK(v.data == NULL && v.dims[0] == 0 && v.type == C5_VOX_NONE);

    /* An all-zero spec means the same as none. */
    c5_raw_spec spec = {{0, 0, 0}, C5_VOX_NONE, 0};
    CHECK_MSG(c5_volume_load_raw(p, &spec, &v, &e) == 0, "%s", e.msg);
    CHECK_INT(c5_volume_at(&v, 23), buf[23]);
    c5_volume_free(&v);
}

TEST(volume_raw_u16_little_explicit)
{
    enum { N = 5 * 2 * 3 };
    unsigned char buf[2 * N];
    put_u16(buf, N, 0);
    const char *p = c5t_path(0, "data.bin");
    CHECK(c5t_write_file(p, NULL, buf, sizeof buf) == 0);
    c5_raw_spec spec = {{5, 2, 3}, C5_VOX_U16, 0};
    c5_volume v;
    c5_err e = {{0}};
    CHECK_MSG(c5_volume_load(p, &spec, &v, &e) == 0, "%s", e.msg);
    CHECK_INT(v.type, C5_VOX_U16);
    CHECK_INT(v.dims[0], 5);
    CHECK_INT(v.dims[2], 3);
    CHECK_INT(c5_volume_count(&v), N);
    for (size_t i = 0; i < N; i++)
        CHECK_INT(c5_volume_at(&v, i), u16_value(i));
    CHECK_INT(((const uint16_t *)v.data)[1], u16_value(1));
    c5_volume_free(&v);
}

TEST(volume_raw_u16_big_explicit)
{
    enum { N = 3 * 3 * 3 };
    unsigned char buf[2 * N];
    put_u16(buf, N, 1);
    const char *p = c5t_path(0, "data.be16");
    CHECK(c5t_write_file(p, NULL, buf, sizeof buf) == 0);
    c5_raw_spec spec = {{3, 3, 3}, C5_VOX_U16, 1};
    c5_volume v;
    c5_err e = {{0}};
    CHECK_MSG(c5_volume_load_raw(p, &spec, &v, &e) == 0, "%s", e.msg);
    for (size_t i = 0; i < N; i++)
        CHECK_INT(c5_volume_at(&v, i), u16_value(i));
    c5_volume_free(&v);
}

TEST(volume_raw_u16_scivis_both_endians)
{
    enum { N = 2 * 2 * 2 };
    unsigned char le[2 * N], be[2 * N];
    put_u16(le, N, 0);
    put_u16(be, N, 1);
    const char *pl = c5t_path(0, "le_2x2x2_uint16.raw");
    const char *pb = c5t_path(1, "be_2x2x2_uint16.raw");
    CHECK(c5t_write_file(pl, NULL, le, sizeof le) == 0);
    CHECK(c5t_write_file(pb, NULL, be, sizeof be) == 0);
    c5_volume v;
    c5_err e = {{0}};
    CHECK_MSG(c5_volume_load(pl, NULL, &v, &e) == 0, "%s", e.msg);
    CHECK_INT(v.type, C5_VOX_U16);
    for (size_t i = 0; i < N; i++)
        CHECK_INT(c5_volume_at(&v, i), u16_value(i));
    c5_volume_free(&v);
    /* big_endian applies to dims and type taken from the name as well. */
    c5_raw_spec spec = {{0, 0, 0}, C5_VOX_NONE, 1};
    CHECK_MSG(c5_volume_load(pb, &spec, &v, &e) == 0, "%s", e.msg);
    for (size_t i = 0; i < N; i++)
        CHECK_INT(c5_volume_at(&v, i), u16_value(i));
    c5_volume_free(&v);
}

TEST(volume_raw_truncated)
{
    static unsigned char buf[900];
    const char *p = c5t_path(0, "vol_10x10x10_uint8.raw");
    CHECK(c5t_write_file(p, NULL, buf, sizeof buf) == 0);
    c5_volume v;
    c5_err e = {{0}};
    int rc = c5_volume_load(p, NULL, &v, &e);
    CHECK_FAILS(rc, v, e);
    CHECK_HAS(e.msg, p);
    CHECK_HAS(e.msg, "vol_10x10x10_uint8.raw: file is 900 bytes, expected 1000 (10x10x10 uint8): truncated");
}

TEST(volume_raw_oversized)
{
    static unsigned char buf[1024];
    const char *p = c5t_path(0, "vol_10x10x10_uint8.raw");
    CHECK(c5t_write_file(p, NULL, buf, sizeof buf) == 0);
    c5_volume v;
    c5_err e = {{0}};
    int rc = c5_volume_load(p, NULL, &v, &e);
    CHECK_FAILS(rc, v, e);
    CHECK_HAS(e.msg, "vol_10x10x10_uint8.raw: file is 1024 bytes, expected 1000");
    CHECK_HAS(e.msg, ": 24 extra bytes");
}

TEST(volume_raw_empty_file)
{
    const char *p = c5t_path(0, "vol_2x2x2_uint16.raw");
    CHECK(c5t_write_file(p, NULL, NULL, 0) == 0);
    c5_volume v;
    c5_err e = {{0}};
    int rc = c5_volume_load(p, NULL, &v, &e);
    CHECK_FAILS(rc, v, e);
    CHECK_HAS(e.msg, "vol_2x2x2_uint16.raw: file is 0 bytes, expected 16 (2x2x2 uint16): truncated");
}

TEST(volume_raw_explicit_dims_mismatch)
{
    static unsigned char buf[1000];
    const char *p = c5t_path(0, "vol_10x10x10_uint8.raw");
    CHECK(c5t_write_file(p, NULL, buf, sizeof buf) == 0);
    c5_volume v;
    c5_err e = {{0}};
    /* Explicit dims win over the name. */
    c5_raw_spec spec = {{5, 5, 5}, C5_VOX_U16, 0};
    int rc = c5_volume_load(p, &spec, &v, &e);
    CHECK_FAILS(rc, v, e);
    CHECK_HAS(e.msg, "vol_10x10x10_uint8.raw: file is 1000 bytes, expected 250 (5x5x5 uint16): 750 extra bytes");
    c5_raw_spec spec2 = {{10, 10, 10}, C5_VOX_U16, 0};
    rc = c5_volume_load(p, &spec2, &v, &e);
    CHECK_FAILS(rc, v, e);
    CHECK_HAS(e.msg, "expected 2000 (10x10x10 uint16): truncated");
}

TEST(volume_raw_dims_overflow)
{
    const char *p = c5t_path(0, "big.raw");
    CHECK(c5t_write_file(p, NULL, "x", 1) == 0);
    c5_volume v;
    c5_err e = {{0}};
    size_t g = (size_t)1 << 32;
    c5_raw_spec s1 = {{g, g, 2}, C5_VOX_U8, 0};
    int rc = c5_volume_load_raw(p, &s1, &v, &e);
    CHECK_FAILS(rc, v, e);
    CHECK_HAS(e.msg, "big.raw: dims 4294967296x4294967296x2 overflow");
    c5_raw_spec s2 = {{65536, 65536, 65536}, C5_VOX_U16, 0};
    rc = c5_volume_load_raw(p, &s2, &v, &e);
    CHECK_FAILS(rc, v, e);
    CHECK_HAS(e.msg, "big.raw: dims 65536x65536x65536: every dim must be 1..65535");
    c5_raw_spec s3 = {{65535, 65535, 65535}, C5_VOX_U8, 0};
    rc = c5_volume_load_raw(p, &s3, &v, &e);
    CHECK_FAILS(rc, v, e);
    CHECK_HAS(e.msg, "big.raw: dims 65535x65535x65535:");
    CHECK_HAS(e.msg, "limit");
}

TEST(volume_raw_name_dims_overflow)
{
    /* Digits beyond size_t saturate, so the name still ends in the dims check. */
    const char *p = c5t_path(0, "v_99999999999999999999999x99999999999x2_uint8.raw");
    CHECK(c5t_write_file(p, NULL, "x", 1) == 0);
    c5_volume v;
    c5_err e = {{0}};
    int rc = c5_volume_load(p, NULL, &v, &e);
    CHECK_FAILS(rc, v, e);
    CHECK_HAS(e.msg, "v_99999999999999999999999x99999999999x2_uint8.raw: dims ");
    CHECK_HAS(e.msg, "overflow");
}

TEST(volume_raw_zero_dim)
{
    const char *p = c5t_path(0, "vol_0x10x10_uint8.raw");
    CHECK(c5t_write_file(p, NULL, NULL, 0) == 0);
    c5_volume v;
    c5_err e = {{0}};
    int rc = c5_volume_load(p, NULL, &v, &e);
    CHECK_FAILS(rc, v, e);
    CHECK_HAS(e.msg, "vol_0x10x10_uint8.raw: dims 0x10x10: every dim must be 1..65535");
    /* Partly given dims count as given, and a zero among them is refused the same way. */
    c5_raw_spec spec = {{10, 0, 10}, C5_VOX_U8, 0};
    rc = c5_volume_load(p, &spec, &v, &e);
    CHECK_FAILS(rc, v, e);
    CHECK_HAS(e.msg, "dims 10x0x10: every dim must be 1..65535");
}

TEST(volume_raw_spec_needs_both)
{
    const char *p = c5t_path(0, "vol_2x2x2_uint8.raw");
    CHECK(c5t_write_file(p, NULL, "12345678", 8) == 0);
    c5_volume v;
    c5_err e = {{0}};
    c5_raw_spec dims_only = {{2, 2, 2}, C5_VOX_NONE, 0};
    int rc = c5_volume_load(p, &dims_only, &v, &e);
    CHECK_FAILS(rc, v, e);
    CHECK_HAS(e.msg, "vol_2x2x2_uint8.raw: ");
    CHECK_HAS(e.msg, "give both");
    c5_raw_spec type_only = {{0, 0, 0}, C5_VOX_U8, 0};
    rc = c5_volume_load(p, &type_only, &v, &e);
    CHECK_FAILS(rc, v, e);
    CHECK_HAS(e.msg, "vol_2x2x2_uint8.raw: ");
    CHECK_HAS(e.msg, "give both");
    c5_raw_spec bad_type = {{2, 2, 2}, (c5_voxel_type)7, 0};
    rc = c5_volume_load(p, &bad_type, &v, &e);
    CHECK_FAILS(rc, v, e);
    CHECK_HAS(e.msg, "unsupported voxel type");
}

TEST(volume_raw_name_without_dims)
{
    const char *p = c5t_path(0, "data.raw");
    CHECK(c5t_write_file(p, NULL, "12345678", 8) == 0);
    c5_volume v;
    c5_err e = {{0}};
    int rc = c5_volume_load(p, NULL, &v, &e);
    CHECK_FAILS(rc, v, e);
    CHECK_HAS(e.msg, "data.raw: no dims and type given");
    CHECK_HAS(e.msg, "NAME_XxYxZ_uint8.raw");
}

TEST(volume_raw_name_unsupported_type)
{
    const char *p = c5t_path(0, "vol_2x2x2_float32.raw");
    CHECK(c5t_write_file(p, NULL, "12345678", 8) == 0);
    c5_volume v;
    c5_err e = {{0}};
    int rc = c5_volume_load(p, NULL, &v, &e);
    CHECK_FAILS(rc, v, e);
    CHECK_HAS(e.msg, "vol_2x2x2_float32.raw: unsupported voxel type 'float32' (uint8 or uint16 only)");
}

TEST(volume_missing_file)
{
    static const char *names[] = {"vol_2x2x2_uint8.raw", "missing.nrrd", "missing.nhdr"};
    for (int i = 0; i < 3; i++) {
        const char *p = c5t_path(0, names[i]);
        c5_volume v;
        c5_err e = {{0}};
        int rc = c5_volume_load(p, NULL, &v, &e);
        CHECK_FAILS(rc, v, e);
        CHECK_HAS(e.msg, p);
        CHECK_HAS(e.msg, ": cannot open: No such file or directory");
    }
}

TEST(volume_directory_refused)
{
    const char *p = c5t_path(0, "d_1x1x1_uint8.raw");
    char cmd[1200];
    snprintf(cmd, sizeof cmd, "mkdir '%s'", p);
    CHECK(system(cmd) == 0);
    c5_volume v;
    c5_err e = {{0}};
    int rc = c5_volume_load(p, NULL, &v, &e);
    CHECK_FAILS(rc, v, e);
    CHECK_HAS(e.msg, "d_1x1x1_uint8.raw: not a regular file");
}

/* ---- NRRD ------------------------------------------------------------------------ */

#define NRRD_HEAD(type, sizes, extra) \
    "NRRD0004\ntype: " type "\ndimension: 3\nsizes: " sizes "\n" extra

TEST(volume_nrrd_attached_raw_u8)
{
    unsigned char buf[3 * 2 * 4];
    fill_ramp(buf, sizeof buf);
    const char *p = c5t_path(0, "a.nrrd");
    CHECK(c5t_write_file(p, NRRD_HEAD("uchar", "3 2 4", "encoding: raw\n\n"), buf, sizeof buf) == 0);
    c5_volume v;
    c5_err e = {{0}};
    CHECK_MSG(c5_volume_load(p, NULL, &v, &e) == 0, "%s", e.msg);
    CHECK_INT(v.type, C5_VOX_U8);
    CHECK_INT(v.dims[0], 3);
    CHECK_INT(v.dims[1], 2);
    CHECK_INT(v.dims[2], 4);
    for (size_t i = 0; i < sizeof buf; i++)
        CHECK_INT(c5_volume_at(&v, i), buf[i]);
    /* No spacing in the header: unknown. */
    CHECK_NEAR(v.spacing[0], 0, 0);
    CHECK_NEAR(v.spacing[1], 0, 0);
    CHECK_NEAR(v.spacing[2], 0, 0);
    c5_volume_free(&v);
}

TEST(volume_nrrd_u16_little_and_big_endian)
{
    enum { N = 2 * 3 * 2 };
    unsigned char le[2 * N], be[2 * N];
    put_u16(le, N, 0);
    put_u16(be, N, 1);
    const char *pl = c5t_path(0, "le.nrrd");
    const char *pb = c5t_path(1, "be.nrrd");
    CHECK(c5t_write_file(pl, NRRD_HEAD("unsigned short", "2 3 2", "endian: little\nencoding: raw\n\n"),
                     le, sizeof le) == 0);
    CHECK(c5t_write_file(pb, NRRD_HEAD("ushort", "2 3 2", "endian: big\nencoding: raw\n\n"), be,
                     sizeof be) == 0);
    const char *paths[2] = {pl, pb};
    for (int k = 0; k < 2; k++) {
        c5_volume v;
        c5_err e = {{0}};
        CHECK_MSG(c5_volume_load(paths[k], NULL, &v, &e) == 0, "%s", e.msg);
        CHECK_INT(v.type, C5_VOX_U16);
        CHECK_INT(c5_volume_count(&v), N);
        for (size_t i = 0; i < N; i++)
            CHECK_INT(c5_volume_at(&v, i), u16_value(i));
        c5_volume_free(&v);
    }
}

/* Saves a NRRD with Teem; gzip when asked. 0 on success. */
static int save_with_teem(const char *path, void *data, int type, unsigned dim, const size_t *sizes,
                          int gzip)
{
    Nrrd *n = nrrdNew();
    NrrdIoState *nio = nrrdIoStateNew();
    int rc = nrrdWrap_nva(n, data, type, dim, sizes);
    if (rc == 0) {
        if (gzip)
            nio->encoding = nrrdEncodingGzip;
        rc = nrrdSave(path, n, nio);
    }
    if (rc != 0)
        free(biffGetDone(NRRD));
    nrrdIoStateNix(nio);
    nrrdNix(n); /* the data is the caller's */
    return rc;
}

TEST(volume_nrrd_attached_gzip)
{
    enum { N = 4 * 5 * 6 };
    uint16_t data[N];
    for (size_t i = 0; i < N; i++)
        data[i] = u16_value(i);
    const char *p = c5t_path(0, "z.nrrd");
    CHECK(save_with_teem(p, data, nrrdTypeUShort, 3, (size_t[3]){4, 5, 6}, 1) == 0);
    /* Make sure the file really is gzip-encoded. */
    char head[512] = {0};
    FILE *f = fopen(p, "rb");
    CHECK(f != NULL);
    size_t got = fread(head, 1, sizeof head - 1, f);
    fclose(f);
    CHECK(got > 0);
    CHECK_HAS(head, "encoding: gzip");
    c5_volume v;
    c5_err e = {{0}};
    CHECK_MSG(c5_volume_load(p, NULL, &v, &e) == 0, "%s", e.msg);
    CHECK_INT(v.type, C5_VOX_U16);
    CHECK_INT(v.dims[0], 4);
    CHECK_INT(v.dims[1], 5);
    CHECK_INT(v.dims[2], 6);
    for (size_t i = 0; i < N; i++)
        CHECK_INT(c5_volume_at(&v, i), data[i]);
    c5_volume_free(&v);
}

TEST(volume_nrrd_detached_raw)
{
    enum { N = 3 * 3 * 2 };
    unsigned char buf[2 * N];
    put_u16(buf, N, 1);
    const char *ph = c5t_path(0, "d.nhdr");
    const char *pd = c5t_path(1, "d.raw");
    /* The data file name is relative to the header's folder. */
    CHECK(c5t_write_file(ph, NRRD_HEAD("ushort", "3 3 2",
                                   "endian: big\nencoding: raw\ndata file: d.raw\n"),
                     NULL, 0) == 0);
    CHECK(c5t_write_file(pd, NULL, buf, sizeof buf) == 0);
    c5_volume v;
    c5_err e = {{0}};
    CHECK_MSG(c5_volume_load(ph, NULL, &v, &e) == 0, "%s", e.msg);
    CHECK_INT(v.type, C5_VOX_U16);
    CHECK_INT(v.dims[0], 3);
    CHECK_INT(v.dims[2], 2);
    for (size_t i = 0; i < N; i++)
        CHECK_INT(c5_volume_at(&v, i), u16_value(i));
    c5_volume_free(&v);
}

TEST(volume_nrrd_detached_missing_data)
{
    const char *ph = c5t_path(0, "lonely.nhdr");
    CHECK(c5t_write_file(ph, NRRD_HEAD("uchar", "2 2 2", "encoding: raw\ndata file: gone.raw\n"),
                     NULL, 0) == 0);
    c5_volume v;
    c5_err e = {{0}};
    int rc = c5_volume_load(ph, NULL, &v, &e);
    CHECK_FAILS(rc, v, e);
    CHECK_HAS(e.msg, "lonely.nhdr: data file ");
    CHECK_HAS(e.msg, "gone.raw: cannot open: No such file or directory");
}

TEST(volume_nrrd_float_refused)
{
    float data[8] = {0};
    const char *p = c5t_path(0, "f.nrrd");
    CHECK(save_with_teem(p, data, nrrdTypeFloat, 3, (size_t[3]){2, 2, 2}, 0) == 0);
    c5_volume v;
    c5_err e = {{0}};
    int rc = c5_volume_load(p, NULL, &v, &e);
    CHECK_FAILS(rc, v, e);
    CHECK_HAS(e.msg, "f.nrrd: unsupported voxel type 'float' (uint8 or uint16 only)");
}

TEST(volume_nrrd_signed_short_refused)
{
    static unsigned char buf[16];
    const char *p = c5t_path(0, "s.nrrd");
    CHECK(c5t_write_file(p, NRRD_HEAD("short", "2 2 2", "endian: little\nencoding: raw\n\n"), buf,
                     sizeof buf) == 0);
    c5_volume v;
    c5_err e = {{0}};
    int rc = c5_volume_load(p, NULL, &v, &e);
    CHECK_FAILS(rc, v, e);
    CHECK_HAS(e.msg, "s.nrrd: unsupported voxel type 'short'");
}

TEST(volume_nrrd_2d_refused)
{
    static unsigned char buf[12];
    const char *p = c5t_path(0, "flat.nrrd");
    CHECK(c5t_write_file(p, "NRRD0004\ntype: uchar\ndimension: 2\nsizes: 4 3\nencoding: raw\n\n", buf,
                     sizeof buf) == 0);
    c5_volume v;
    c5_err e = {{0}};
    int rc = c5_volume_load(p, NULL, &v, &e);
    CHECK_FAILS(rc, v, e);
    CHECK_HAS(e.msg, "flat.nrrd: 2-D NRRD");
    CHECK_HAS(e.msg, "3-D");
}

TEST(volume_nrrd_4d_refused)
{
    static unsigned char buf[16];
    const char *p = c5t_path(0, "four.nrrd");
    CHECK(save_with_teem(p, buf, nrrdTypeUChar, 4, (size_t[4]){2, 2, 2, 2}, 0) == 0);
    c5_volume v;
    c5_err e = {{0}};
    int rc = c5_volume_load(p, NULL, &v, &e);
    CHECK_FAILS(rc, v, e);
    CHECK_HAS(e.msg, "four.nrrd: 4-D NRRD");
}

TEST(volume_nrrd_color_axis_refused)
{
    static unsigned char buf[3 * 2 * 2];
    const char *p = c5t_path(0, "rgb.nrrd");
    CHECK(c5t_write_file(p, NRRD_HEAD("uchar", "3 2 2", "kinds: RGB-color domain domain\nencoding: raw\n\n"),
                     buf, sizeof buf) == 0);
    c5_volume v;
    c5_err e = {{0}};
    int rc = c5_volume_load(p, NULL, &v, &e);
    CHECK_FAILS(rc, v, e);
    CHECK_HAS(e.msg, "rgb.nrrd: axis 0 has kind 'RGB-color'");
}

TEST(volume_nrrd_spacing)
{
    static unsigned char buf[8];
    const char *p = c5t_path(0, "sp.nrrd");
    CHECK(c5t_write_file(p, NRRD_HEAD("uchar", "2 2 2", "spacings: 0.5 1.25 NaN\nencoding: raw\n\n"), buf,
                     sizeof buf) == 0);
    c5_volume v;
    c5_err e = {{0}};
    CHECK_MSG(c5_volume_load(p, NULL, &v, &e) == 0, "%s", e.msg);
    CHECK_NEAR(v.spacing[0], 0.5, 1e-12);
    CHECK_NEAR(v.spacing[1], 1.25, 1e-12);
    CHECK_NEAR(v.spacing[2], 0, 0);
    c5_volume_free(&v);

    /* With a world space, the voxel step is the length of each space direction. */
    const char *q = c5t_path(1, "dir.nrrd");
    CHECK(c5t_write_file(q, NRRD_HEAD("uchar", "2 2 2",
                                  "space: right-anterior-superior\n"
                                  "space directions: (0.5,0,0) (0,0,-2) (0,3,4)\n"
                                  "encoding: raw\n\n"),
                     buf, sizeof buf) == 0);
    CHECK_MSG(c5_volume_load(q, NULL, &v, &e) == 0, "%s", e.msg);
    CHECK_NEAR(v.spacing[0], 0.5, 1e-12);
    CHECK_NEAR(v.spacing[1], 2, 1e-12);
    CHECK_NEAR(v.spacing[2], 5, 1e-12);
    c5_volume_free(&v);
}

TEST(volume_nrrd_huge_sizes_refused_before_reading)
{
    /* Teem would try to allocate these sizes; the header is checked first. */
    const char *p = c5t_path(0, "huge.nrrd");
    CHECK(c5t_write_file(p, NRRD_HEAD("uchar", "65536 65536 65536", "encoding: raw\n\n"), NULL, 0) == 0);
    c5_volume v;
    c5_err e = {{0}};
    int rc = c5_volume_load(p, NULL, &v, &e);
    CHECK_FAILS(rc, v, e);
    CHECK_HAS(e.msg, "huge.nrrd: dims 65536x65536x65536: every dim must be 1..65535");
    const char *q = c5t_path(1, "wide.nrrd");
    CHECK(c5t_write_file(q, NRRD_HEAD("ushort", "65535 65535 4097", "endian: little\nencoding: gzip\n\n"), NULL, 0) == 0);
    rc = c5_volume_load(q, NULL, &v, &e);
    CHECK_FAILS(rc, v, e);
    CHECK_HAS(e.msg, "wide.nrrd: dims 65535x65535x4097:");
    CHECK_HAS(e.msg, "limit");
}

TEST(volume_nrrd_truncated_data)
{
    const char *p = c5t_path(0, "short.nrrd");
    CHECK(c5t_write_file(p, NRRD_HEAD("uchar", "2 2 2", "encoding: raw\n\n"), "abc", 3) == 0);
    c5_volume v;
    c5_err e = {{0}};
    int rc = c5_volume_load(p, NULL, &v, &e);
    CHECK_FAILS(rc, v, e);
    CHECK_HAS(e.msg, "short.nrrd: data is 3 bytes, expected 8 (2x2x2 uint8): truncated");
}

TEST(volume_nrrd_garbage_refused)
{
    const char *p = c5t_path(0, "junk.nrrd");
    CHECK(c5t_write_file(p, "this is not a nrrd\n", NULL, 0) == 0);
    c5_volume v;
    c5_err e = {{0}};
    int rc = c5_volume_load(p, NULL, &v, &e);
    CHECK_FAILS(rc, v, e);
    CHECK_HAS(e.msg, "junk.nrrd: cannot read NRRD: ");

    const char *q = c5t_path(1, "badsizes.nrrd");
    CHECK(c5t_write_file(q, NRRD_HEAD("uchar", "2 2 bogus", "encoding: raw\n\n"), NULL, 0) == 0);
    rc = c5_volume_load(q, NULL, &v, &e);
    CHECK_FAILS(rc, v, e);
    CHECK_HAS(e.msg, "badsizes.nrrd: cannot read NRRD: ");

    const char *r = c5t_path(2, "empty.nhdr");
    CHECK(c5t_write_file(r, NULL, NULL, 0) == 0);
    rc = c5_volume_load(r, NULL, &v, &e);
    CHECK_FAILS(rc, v, e);
    CHECK_HAS(e.msg, "empty.nhdr: cannot read NRRD: ");
}

TEST(volume_load_dispatch_by_extension)
{
    static unsigned char buf[8] = {1, 2, 3, 4, 5, 6, 7, 8};
    /* A .nrrd name goes to NRRD even with a raw spec, and the extension ignores case. */
    const char *p = c5t_path(0, "UP.NRRD");
    CHECK(c5t_write_file(p, NRRD_HEAD("uchar", "2 2 2", "encoding: raw\n\n"), buf, sizeof buf) == 0);
    c5_raw_spec spec = {{8, 1, 1}, C5_VOX_U8, 0};
    c5_volume v;
    c5_err e = {{0}};
    CHECK_MSG(c5_volume_load(p, &spec, &v, &e) == 0, "%s", e.msg);
    CHECK_INT(v.dims[0], 2);
    CHECK_INT(c5_volume_at(&v, 7), 8);
    c5_volume_free(&v);
    /* Anything else is raw, even a file that holds a NRRD. */
    const char *q = c5t_path(1, "nrrd.dat");
    CHECK(c5t_write_file(q, NULL, buf, sizeof buf) == 0);
    CHECK_MSG(c5_volume_load(q, &spec, &v, &e) == 0, "%s", e.msg);
    CHECK_INT(v.dims[0], 8);
    CHECK_INT(c5_volume_at(&v, 0), 1);
    c5_volume_free(&v);
    c5_volume_free(&v); /* freeing twice is harmless: free zeroes */
    c5_volume_free(NULL);
}
