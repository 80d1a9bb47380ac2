#include "opt_table.h"

#include <string.h>

#include "cli.h"
#include "progress.h"

/* The usage text's lines: at most this wide, options' help from this column. */
#define USAGE_WIDTH 92
#define HELP_COL 20

int c5_opt_long(const c5_opt *o, const char *val, void *field, c5_err *err)
{
    return c5_cli_int(o->name, val, (long)o->lo, (long)o->hi, field, err);
}

int c5_opt_double(const c5_opt *o, const char *val, void *field, c5_err *err)
{
    return c5_cli_double(o->name, val, o->lo, o->hi, field, err);
}

int c5_opt_str(const c5_opt *o, const char *val, void *field, c5_err *err)
{
    if (!*val)
        return c5_fail(err, "%s: expected %s, got an empty string", o->name, o->arg);
    *(const char **)field = val;
    return 0;
}

int c5_opt_flag(const c5_opt *o, const char *val, void *field, c5_err *err)
{
    (void)o, (void)val, (void)err;
    *(int *)field = 1;
    return 0;
}

int c5_opt_size(const c5_opt *o, const char *val, void *field, c5_err *err)
{
    int *wh = field;
    return c5_cli_size(o->name, val, &wh[0], &wh[1], err);
}

int c5_opt_cells(const c5_opt *o, const char *val, void *field, c5_err *err)
{
    return c5_cli_cells(o->name, val, field, err);
}

int c5_opt_queue_key(const c5_opt *o, const char *val, void *field, c5_err *err)
{
    return c5_cli_queue_key(o->name, val, field, err);
}

int c5_opt_pick(const c5_opt *o, const char *val, const char *const *names, int first, int *out, c5_err *err)
{
    char list[256];
    size_t at = 0;
    int n = 0;
    for (; names[n]; n++)
        if (!strcmp(val, names[n])) {
            *out = first + n;
            return 0;
        }
    for (int i = 0; i < n && at < sizeof list; i++)
        at += (size_t)snprintf(list + at, sizeof list - at, "%s%s", i == 0 ? "" : i == n - 1 ? " or " : ", ",
                               names[i]);
    return c5_fail(err, "%s: expected %s, got '%s'", o->name, list, val);
}

int c5_opt_volume(const c5_opt *o, const char *val, void *field, c5_err *err)
{
    c5_cli_volumes *v = field;
    if (v->n == C5_MAX_VOLUMES)
        return c5_fail(err, "%s: at most %d", o->name, C5_MAX_VOLUMES);
    v->path[v->n++] = val;
    return 0;
}

static int progress_on(const c5_opt *o, const char *val, void *field, c5_err *err)
{
    (void)o, (void)val, (void)field, (void)err;
    c5_progress_requested = 1;
    return 0;
}

const c5_opt c5_progress_opts[] = {
    {"--progress", NULL, progress_on, 0, 0, 0, 0,
     "progress on stderr, one line per step (shown anyway, redrawn in place, when stderr is a terminal; never on "
     "stdout)"},
    {0},
};

/* The option NAME in the spec's tables, and the offset of its group's fields. */
static const c5_opt *find(const c5_cmd_spec *spec, const char *name, size_t *base)
{
    for (int g = 0; g < C5_OPT_GROUPS && spec->groups[g].opts; g++)
        for (const c5_opt *o = spec->groups[g].opts; o->name; o++)
            if (!strcmp(o->name, name)) {
                *base = spec->groups[g].base;
                return o;
            }
    return NULL;
}

int c5_opt_parse(const c5_cmd_spec *spec, int argc, char **argv, void *args, const char **operand, c5_err *err)
{
    char *at = args;
    int have_operand = 0;
    for (int i = 1; i < argc; i++) {
        size_t base = 0;
        const char *name = argv[i], *val = NULL;
        const c5_opt *o = find(spec, name, &base);
        if (!o) {
            if (name[0] == '-' && name[1])
                return c5_fail(err, "unknown option '%s' (see 'cube5 %s --help')", name, spec->name);
            if (!spec->operand || have_operand)
                return c5_fail(err, "unexpected argument '%s' (see 'cube5 %s --help')", name, spec->name);
            *operand = name;
            have_operand = 1;
            continue;
        }
        if (o->arg) {
            if (i + 1 >= argc)
                return c5_fail(err, "%s: missing value", name);
            val = argv[++i];
        }
        if (o->parse(o, val, at + base + o->off, err) != 0)
            return -1;
        if (o->seen)
            *(int *)(at + base + o->seen - 1) = 1;
    }
    return 0;
}

int c5_opt_help(const c5_cmd_spec *spec, int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            c5_opt_usage(spec, stdout);
            return 1;
        }
    return 0;
}

/* TEXT's words from column COL (the cursor is there), lines at most WIDTH wide, each further
 * line indented to INDENT. A NBSP joins two words into one and prints as a space. */
#define NBSP '\x1f'
static void wrap(FILE *f, const char *text, int col, int indent, int width)
{
    const char *p = text;
    int start = col;
    while (*p) {
        if (*p == ' ' || *p == '\n') {
            p++;
            continue;
        }
        int n = (int)strcspn(p, " \n");
        if (col > start && col + 1 + n > width) {
            fprintf(f, "\n%*s", indent, "");
            col = start = indent;
        } else if (col > start) {
            fputc(' ', f);
            col++;
        }
        for (int i = 0; i < n; i++)
            fputc(p[i] == NBSP ? ' ' : p[i], f);
        col += n;
        p += n;
    }
    fputc('\n', f);
}

/* The paragraph of TEXT at P (they are separated by "\n\n") into BUF; the next one, or NULL. A
 * paragraph that begins with a blank is a table: printed as written, never filled. */
static const char *paragraph(const char *p, char *buf, size_t len)
{
    const char *end = strstr(p, "\n\n");
    size_t n = end ? (size_t)(end - p) : strlen(p);
    snprintf(buf, len, "%.*s", (int)n, p);
    return end ? end + 2 : NULL;
}

void c5_opt_usage(const c5_cmd_spec *spec, FILE *f)
{
    char syn[4096] = "";
    size_t at = 0;
    if (spec->operand)
        at += (size_t)snprintf(syn + at, sizeof syn - at, "%s", spec->operand);
    for (int g = 0; g < C5_OPT_GROUPS && spec->groups[g].opts; g++)
        for (const c5_opt *o = spec->groups[g].opts; o->name && at < sizeof syn; o++)
            at += (size_t)snprintf(syn + at, sizeof syn - at, "%s[%s%s%s]", at ? " " : "", o->name,
                                   o->arg ? " " : "", o->arg ? o->arg : "");
    /* Brackets stay whole: the synopsis breaks only between options. */
    for (char *c = syn; *c; c++)
        if (*c == ' ' && c > syn && c[-1] != ']' && c[1] != '[')
            *c = NBSP;
    int lead = fprintf(f, "usage: cube5 %s%s", spec->name, at ? " " : "");
    wrap(f, syn, lead, lead, USAGE_WIDTH);
    char para[2048];
    for (const char *p = spec->about; p;) {
        p = paragraph(p, para, sizeof para);
        fputc('\n', f);
        if (para[0] == ' ')
            fprintf(f, "%s\n", para);
        else
            wrap(f, para, 0, 0, USAGE_WIDTH);
    }
    fputc('\n', f);
    for (int g = 0; g < C5_OPT_GROUPS && spec->groups[g].opts; g++)
        for (const c5_opt *o = spec->groups[g].opts; o->name; o++) {
            int col = fprintf(f, "  %s%s%s", o->name, o->arg ? " " : "", o->arg ? o->arg : "");
            if (col + 1 > HELP_COL) {
                fputc('\n', f);
                col = 0;
            }
            fprintf(f, "%*s", HELP_COL - col, "");
            wrap(f, o->help, HELP_COL, HELP_COL, USAGE_WIDTH);
        }
}

/* TEXT in roff: a backslash as \e, a hyphen as \- (options and ranges read as typed), a line
 * that would begin with a control character guarded. */
static void roff(FILE *f, const char *text)
{
    int bol = 1;
    for (const char *p = text; *p; p++) {
        if (bol && (*p == '.' || *p == '\''))
            fputs("\\&", f);
        bol = *p == '\n';
        if (*p == '\\')
            fputs("\\e", f);
        else if (*p == '-')
            fputs("\\-", f);
        else
            fputc(*p, f);
    }
}

void c5_opt_man(const c5_cmd_spec *spec, FILE *f)
{
    fprintf(f, ".SS \"cube5 %s%s%s [options]\"\n", spec->name, spec->operand ? " " : "",
            spec->operand ? spec->operand : "");
    char para[2048];
    for (const char *p = spec->about; p;) {
        if (p != spec->about)
            fputs(".PP\n", f);
        p = paragraph(p, para, sizeof para);
        fputs(para[0] == ' ' ? ".nf\n" : "", f);
        roff(f, para);
        fputs(para[0] == ' ' ? "\n.fi\n" : "\n", f);
    }
    for (int g = 0; g < C5_OPT_GROUPS && spec->groups[g].opts; g++)
        for (const c5_opt *o = spec->groups[g].opts; o->name; o++) {
            fputs(".TP\n", f);
            if (o->arg) {
                fputs(".BI ", f);
                roff(f, o->name);
                fputs(" \" ", f);
                roff(f, o->arg);
                fputs("\"\n", f);
            } else {
                fputs(".B ", f);
                roff(f, o->name);
                fputc('\n', f);
            }
            roff(f, o->help);
            fputc('\n', f);
        }
}
