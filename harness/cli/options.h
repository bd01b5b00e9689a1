/* The option table (options.c) and what help.c needs of it. */
#ifndef SB_OPTIONS_H
#define SB_OPTIONS_H

#include "cli.h"

#define CLI_DEFAULT_SIZE 256                  /* --width, --height, unless the command says */
#define CLI_DEFAULT_CACHE "results/cache"
#define CLI_DEFAULT_CASCADE_LAMBDA 0.5f       /* three.js's CSM addon's practical split */
#define CLI_DEFAULT_BASELINES "results/baselines"

/* The type of the field of struct options an option sets. */
enum option_kind {
    OPTION_NONE,    /* none: `call` does everything */
    OPTION_FLAG,    /* bool, set true */
    OPTION_INT,     /* int in [lo, hi] */
    OPTION_FOLDER,  /* const char *: a folder, or a path where one may be made */
    OPTION_TEXT,    /* const char * as given */
    OPTION_HELP,    /* prints the command's help */
};

struct option_row {
    const char *name;       /* --name */
    char short_name;        /* -c, or 0 */
    const char *arg;        /* its argument in help ("DIR"), NULL: takes none */
    unsigned commands;      /* 1 << CMD_*: the commands that take it */
    enum option_kind kind;
    size_t offset;          /* of its field in struct options */
    int lo, hi;             /* OPTION_INT's range */
    /* Parses arg instead of the field's own parser (may be NULL). Returns 0
     * or -1 (logged). */
    int (*call)(struct options *o, const char *arg);
    const char *help;       /* {D}: the command's default, from the field (OPTION_INT, _FOLDER,
                               _TEXT rows only) */
};

/* Ends with {NULL}. */
extern const struct option_row option_rows[];

/* --opt's whole number text in [lo, hi] into *out, or its choice among
 * names (NULL-terminated) as an index. Return 0 or -1 (logged). */
int options_int(const char *opt, const char *text, int lo, int hi, int *out);
int options_choice(const char *opt, const char *text, const char *const *names, int *out);

/* A folder option: not empty, and not something other than a folder (it
 * may not exist yet). Returns 0 or -1 (logged). */
int options_folder(const char *opt, const char *text, const char **out);

/* Appends text wrapped at 80 columns, continuing lines at indent; the
 * first line continues from column at (help.c). */
void cli_help_wrap(struct strbuf *out, const char *text, int at, int indent);

/* "  NAME" and its text from the help column on, wrapped. */
void cli_help_item(struct strbuf *out, const char *name, const char *text);

#endif
