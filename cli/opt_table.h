/* A command's options as one table: name, argument, parser and help of each. The table is
 * the one source of the command's parsing, its --help text and its section of the manual page
 * (`cube5 help --man`, from which man/cube5.1 is made). */
#ifndef C5_CLI_OPT_TABLE_H
#define C5_CLI_OPT_TABLE_H

#include <stddef.h>
#include <stdio.h>

#include "err.h"

typedef struct c5_opt c5_opt;
/* Stores VAL (NULL for a flag) into the field the option names (`field`: the command's
 * arguments plus the option's offset). */
typedef int (*c5_opt_parse_fn)(const c5_opt *o, const char *val, void *field, c5_err *err);

struct c5_opt {
    const char *name;      /* "--cells", "-o" */
    const char *arg;       /* "N|NxMxK" (synopsis and manual); NULL: a flag */
    c5_opt_parse_fn parse;
    size_t off;            /* the field parse writes: offsetof(the command's arguments, field) */
    double lo, hi;         /* the range of c5_opt_long and c5_opt_double */
    size_t seen;           /* C5_SEEN(field): an int set to 1 when the option is given; 0: none */
    const char *help;      /* one paragraph; the usage text and the manual wrap it */
};
#define C5_SEEN(type, field) (offsetof(type, field) + 1)

/* The generic parsers: a long or a double in [lo, hi] (c5_cli_int/c5_cli_double); a string
 * (const char *, refused when empty); an int set to 1; "N|WxH" into int[2]; "N|NxMxK" into
 * int[3]; morton|fifo into a c5_queue_key. */
int c5_opt_long(const c5_opt *o, const char *val, void *field, c5_err *err);
int c5_opt_double(const c5_opt *o, const char *val, void *field, c5_err *err);
int c5_opt_str(const c5_opt *o, const char *val, void *field, c5_err *err);
int c5_opt_flag(const c5_opt *o, const char *val, void *field, c5_err *err);
int c5_opt_size(const c5_opt *o, const char *val, void *field, c5_err *err);
int c5_opt_cells(const c5_opt *o, const char *val, void *field, c5_err *err);
int c5_opt_queue_key(const c5_opt *o, const char *val, void *field, c5_err *err);
/* For a parser of a word among NAMES (NULL-ended): its index plus FIRST into *out, else an
 * error listing the words. */
int c5_opt_pick(const c5_opt *o, const char *val, const char *const *names, int first, int *out, c5_err *err);
/* --volume [I=]FILE, repeatable: into a c5_cli_volumes (cli.h). */
int c5_opt_volume(const c5_opt *o, const char *val, void *field, c5_err *err);

/* Options shared by several commands: a table with its own fields, placed in the command's
 * arguments at `base`. */
typedef struct {
    const c5_opt *opts; /* ended by an entry whose name is NULL */
    size_t base;
} c5_opt_group;

#define C5_OPT_GROUPS 4
typedef struct {
    const char *name;    /* "render" */
    const char *operand; /* "[SCENE|FILE.json]": one argument that is no option; NULL: none */
    const char *about;   /* paragraphs separated by "\n\n"; wrapped like the help */
    c5_opt_group groups[C5_OPT_GROUPS];
} c5_cmd_spec;

/* argv[1..argc-1] against the spec's tables into args (its defaults already set); the operand,
 * when the spec takes one, into *operand (left as it is when none is given). An unknown
 * option, a missing or bad value, or a second operand is an error naming it. */
int c5_opt_parse(const c5_cmd_spec *spec, int argc, char **argv, void *args, const char **operand, c5_err *err);
/* The --help text: synopsis, about, the options. */
void c5_opt_usage(const c5_cmd_spec *spec, FILE *f);
/* The command's section of the manual page, in roff (man(7)). */
void c5_opt_man(const c5_cmd_spec *spec, FILE *f);
/* 1 (after printing the usage to stdout) when any argument is --help or -h. */
int c5_opt_help(const c5_cmd_spec *spec, int argc, char **argv);

/* The --progress option of every long command (cli/progress.h). */
extern const c5_opt c5_progress_opts[];

#endif
