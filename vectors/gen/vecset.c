/* The vector set writer (vecset.h). */
#include "vecset.h"
#include "vcd.h"

#include <assert.h>
#include <dirent.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <zlib.h>

struct c5_vfile {
    c5_vset *set;
    const c5_vblock *b;
    c5_afile af;
    c5_vcd *vcd;        /* the waveform, or NULL */
    char name[512];
    json_t *entry;
    int field;          /* next field of the current vector */
    long count;
    uLong crc;
    char line[1024];    /* the current vector */
    size_t len;
};

static void set_fail(c5_vset *s, const char *what, const char *path)
{
    if (!s->failed)
        c5_fail(s->err, "%s %s: %s", what, path, strerror(errno));
    s->failed = 1;
}

/* The first failure's message, made by the writer (atomic_file.h: "PATH: cannot write: why"). */
static void set_failed(c5_vset *s, const c5_err *e)
{
    if (!s->failed)
        c5_fail(s->err, "%s", e->msg);
    s->failed = 1;
}

/* dir may be new, empty, or hold an earlier vector set (a manifest.json of this format):
 * that set's files are removed, nothing else. Anything else is refused: the user's files
 * are never overwritten. */
static int clear_dir(const char *dir, c5_err *err)
{
    DIR *d = opendir(dir);
    if (!d)
        return c5_fail(err, "cannot open %s: %s", dir, strerror(errno));
    int entries = 0;
    for (struct dirent *e; (e = readdir(d)) != NULL;)
        entries += strcmp(e->d_name, ".") && strcmp(e->d_name, "..");
    closedir(d);
    if (entries == 0)
        return 0;
    char path[4200];
    snprintf(path, sizeof path, "%s/manifest.json", dir);
    json_error_t je;
    json_t *m = json_load_file(path, 0, &je);
    const char *fmt = json_string_value(json_object_get(m, "format"));
    if (!fmt || strcmp(fmt, C5_VSET_FORMAT) != 0) {
        json_decref(m);
        return c5_fail(err, "%s is not empty and holds no cube5 vector set (no manifest.json of format '%s'): "
                            "refusing to write into it",
                       dir, C5_VSET_FORMAT);
    }
    size_t i;
    json_t *f;
    json_array_foreach(json_object_get(m, "files"), i, f) {
        static const char *const kinds[] = {"file", "waveform"};
        for (int k = 0; k < 2; k++) {
            const char *name = json_string_value(json_object_get(f, kinds[k]));
            if (!name || strchr(name, '/') || name[0] == '.')
                continue; /* not a file this program wrote */
            snprintf(path, sizeof path, "%s/%s", dir, name);
            if (remove(path) != 0 && errno != ENOENT) {
                json_decref(m);
                return c5_fail(err, "cannot remove %s: %s", path, strerror(errno));
            }
        }
    }
    json_decref(m);
    snprintf(path, sizeof path, "%s/manifest.json", dir);
    if (remove(path) != 0)
        return c5_fail(err, "cannot remove %s: %s", path, strerror(errno));
    return 0;
}

int c5_vset_init(c5_vset *s, const char *dir, uint64_t seed, long count, c5_err *err)
{
    memset(s, 0, sizeof *s);
    if (strlen(dir) + 64 > sizeof s->dir)
        return c5_fail(err, "--out: path too long");
    strcpy(s->dir, dir);
    s->seed = seed;
    s->count = count;
    s->err = err;
    if (c5_output_dir(dir, err) != 0)
        return -1;
    if (clear_dir(dir, err) != 0)
        return -1;
    s->files = json_array();
    return s->files ? 0 : c5_fail(err, "out of memory");
}

void c5_vset_abort(c5_vset *s)
{
    json_decref(s->files);
    s->files = NULL;
}

int c5_vset_finish(c5_vset *s, json_t *params)
{
    char path[4200];
    snprintf(path, sizeof path, "%s/manifest.json", s->dir);
    json_t *m = json_object();
    json_object_set_new(m, "format", json_string(C5_VSET_FORMAT));
    json_object_set_new(m, "generator", json_string("cube5 vectors"));
    json_object_set_new(m, "doc", json_string("docs/vectors.md"));
    json_object_set_new(m, "seed", json_integer((json_int_t)s->seed));
    json_object_set_new(m, "count", json_integer(s->count));
    if (params)
        json_object_update(m, params);
    json_decref(params);
    json_object_set(m, "files", s->files);
    char *text = s->failed ? NULL : json_dumps(m, JSON_INDENT(2) | JSON_PRESERVE_ORDER);
    if (!s->failed && !text) {
        set_fail(s, "out of memory for", path);
    } else if (!s->failed) {
        c5_afile a;
        c5_err e;
        if (c5_afile_open(&a, path, &e) != 0) {
            set_failed(s, &e);
        } else {
            c5_afile_printf(&a, "%s\n", text); /* jansson ends the document without a newline */
            if (c5_afile_commit(&a, &e) != 0)
                set_failed(s, &e);
        }
    }
    free(text);
    json_decref(m);
    c5_vset_abort(s);
    return s->failed ? -1 : 0;
}

c5_vfile *c5_vfile_open(c5_vset *s, const c5_vblock *b, const char *source, const char *scene, const char *image)
{
    c5_vfile *f = calloc(1, sizeof *f);
    if (!f) {
        set_fail(s, "out of memory for", b->name);
        return NULL;
    }
    f->set = s;
    f->b = b;
    if (image)
        snprintf(f->name, sizeof f->name, "%s.%s.%s.hex", b->name, source, image);
    else
        snprintf(f->name, sizeof f->name, "%s.%s.hex", b->name, source);
    char path[4700];
    snprintf(path, sizeof path, "%s/%s", s->dir, f->name);
    c5_err e;
    if (c5_afile_open(&f->af, path, &e) != 0) {
        set_failed(s, &e);
        free(f);
        return NULL;
    }
    f->crc = crc32(0L, Z_NULL, 0);
    f->entry = json_object();
    if (s->vcd && !image) {
        char wave[512];
        snprintf(wave, sizeof wave, "%s.%s.vcd", b->name, source);
        snprintf(path, sizeof path, "%s/%s", s->dir, wave);
        if (!(f->vcd = c5_vcd_open(path, b)))
            set_fail(s, "cannot create", path);
        json_object_set_new(f->entry, "waveform", json_string(wave));
    }
    json_object_set_new(f->entry, "file", json_string(f->name));
    json_object_set_new(f->entry, "block", json_string(b->name));
    json_object_set_new(f->entry, "kind", json_string(image ? "image" : "vectors"));
    if (image)
        json_object_set_new(f->entry, "image", json_string(image));
    json_object_set_new(f->entry, "source", json_string(scene ? "scene" : "directed"));
    json_object_set_new(f->entry, "scene", scene ? json_string(scene) : json_null());
    json_object_set_new(f->entry, "seed", json_integer((json_int_t)s->seed));
    json_object_set_new(f->entry, "doc", json_string(b->doc));
    json_t *fields = json_array();
    for (int i = 0; i < b->n_fields; i++) {
        const c5_vfield *v = &b->fields[i];
        json_t *o = json_object();
        json_object_set_new(o, "name", json_string(v->name));
        json_object_set_new(o, "width", json_integer(v->width));
        json_object_set_new(o, "dir", json_string(v->out ? "out" : "in"));
        json_object_set_new(o, "format", json_string(v->format));
        json_object_set_new(o, "digits", json_integer((v->width + 3) / 4));
        json_array_append_new(fields, o);
    }
    json_object_set_new(f->entry, "fields", fields);
    return f;
}

/* Appends the current field's digits: `digits` hex digits of the little-endian bytes,
 * most significant first, the top digit masked to the field's width. */
static void put_digits(c5_vfile *f, const uint8_t *le)
{
    assert(f->field < f->b->n_fields);
    const c5_vfield *v = &f->b->fields[f->field];
    unsigned digits = (v->width + 3) / 4;
    assert(f->len + digits + 2 < sizeof f->line);
    if (f->field > 0)
        f->line[f->len++] = ' ';
    for (unsigned d = digits; d-- > 0;) {
        unsigned nib = (le[d / 2] >> (4 * (d % 2))) & 15u;
        if (d == digits - 1 && v->width % 4)
            nib &= (1u << (v->width % 4)) - 1u;
        f->line[f->len++] = "0123456789abcdef"[nib];
    }
    f->field++;
}

/* Whether v (two's complement for a signed format: sint, SQ) fits the field's width: a value
 * that does not would be cut to its low bits, a vector the model never computed. */
static int fits(const c5_vfield *fd, uint64_t v)
{
    unsigned w = fd->width;
    if (w >= 64)
        return 1;
    if (!strcmp(fd->format, "sint") || !strncmp(fd->format, "SQ", 2)) {
        int64_t x = (int64_t)v, lim = (int64_t)1 << (w - 1);
        return x >= -lim && x < lim;
    }
    return v >> w == 0;
}

void c5_vfile_u(c5_vfile *f, uint64_t v)
{
    const c5_vfield *fd = &f->b->fields[f->field];
    if (!fits(fd, v) && !f->set->failed) {
        c5_fail(f->set->err, "%s line %ld: %s = %lld does not fit its %u bits (%s): the block's format cannot carry it",
                f->name, f->count + 1, fd->name, (long long)v, fd->width, fd->format);
        f->set->failed = 1;
    }
    uint8_t le[32] = {0};
    for (int i = 0; i < 8; i++)
        le[i] = (uint8_t)(v >> (8 * i));
    put_digits(f, le);
}

void c5_vfile_s(c5_vfile *f, int64_t v) { c5_vfile_u(f, (uint64_t)v); }

void c5_vfile_bytes(c5_vfile *f, const uint8_t *le)
{
    uint8_t buf[32] = {0};
    memcpy(buf, le, (f->b->fields[f->field].width + 7) / 8);
    put_digits(f, buf);
}

void c5_vfile_end(c5_vfile *f)
{
    assert(f->field == f->b->n_fields);
    f->line[f->len++] = '\n';
    c5_afile_write(&f->af, f->line, f->len); /* a failure is reported by c5_vfile_close */
    f->crc = crc32(f->crc, (const Bytef *)f->line, (uInt)f->len);
    if (f->vcd && c5_vcd_vector(f->vcd, f->line) != 0)
        set_fail(f->set, "cannot write the waveform of", f->name);
    f->len = 0;
    f->field = 0;
    f->count++;
}

long c5_vfile_count(const c5_vfile *f) { return f->count; }

void c5_vfile_set(c5_vfile *f, const char *key, json_t *value) { json_object_set_new(f->entry, key, value); }

void c5_vfile_close(c5_vfile *f)
{
    if (!f)
        return;
    assert(f->field == 0);
    c5_err e;
    if (c5_afile_commit(&f->af, &e) != 0)
        set_failed(f->set, &e);
    if (f->vcd && c5_vcd_close(f->vcd, &e) != 0)
        set_failed(f->set, &e);
    char crc[32];
    snprintf(crc, sizeof crc, "crc32:%08lx", (unsigned long)f->crc);
    json_object_set_new(f->entry, "count", json_integer(f->count));
    json_object_set_new(f->entry, "checksum", json_string(crc));
    json_array_append_new(f->set->files, f->entry);
    free(f);
}
