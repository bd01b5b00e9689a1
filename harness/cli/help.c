/* --help and docs/cli.md, generated from the command and option tables. */
#include "options.h"
#include "base/util.h"

#include <stdio.h>
#include <string.h>

#define HELP_WIDTH 80
#define HELP_INDENT 24  /* where an option's help starts */

/* Appends text wrapped at HELP_WIDTH, continuing lines at indent; the first
 * line continues from column `at`. */
void cli_help_wrap(struct strbuf *out, const char *text, int at, int indent)
{
    int col = at;
    for (const char *p = text; *p;) {
        const size_t word = strcspn(p, " ");
        if (col > indent && col + 1 + (int)word > HELP_WIDTH) {
            strbuf_printf(out, "\n%*s", indent, "");
            col = indent;
        } else if (col > indent) {
            strbuf_printf(out, " ");
            col++;
        }
        strbuf_append(out, p, word);
        col += (int)word;
        p += word;
        p += strspn(p, " ");
    }
    strbuf_printf(out, "\n");
}

/* An option's help for command cmd: its command's note, else its own, with
 * {D} as the default the command gives the option's field. */
static void option_help(const struct option_row *r, enum command cmd, const struct options *defaults,
                        struct strbuf *out)
{
    const char *help = r->help;
    for (const struct option_note *n = commands[cmd].notes; n && n->option; n++)
        if (strcmp(n->option, r->name) == 0)
            help = n->help;
    const char *mark = strstr(help, "{D}");
    if (!mark || !(r->kind == OPTION_INT || r->kind == OPTION_FOLDER || r->kind == OPTION_TEXT)) {  /* no field */
        strbuf_printf(out, "%s", help);
        return;
    }
    const char *field = (const char *)defaults + r->offset;
    strbuf_printf(out, "%.*s", (int)(mark - help), help);
    if (r->kind == OPTION_INT)
        strbuf_printf(out, "%d", *(const int *)field);
    else
        strbuf_printf(out, "%s", *(const char *const *)field ? *(const char *const *)field : "none");
    strbuf_printf(out, "%s", mark + 3);
}

void cli_help_item(struct strbuf *out, const char *name, const char *text)
{
    const int len = 2 + (int)strlen(name);
    strbuf_printf(out, "  %s", name);
    if (len < HELP_INDENT - 1)
        strbuf_printf(out, "%*s", HELP_INDENT - len, "");
    else
        strbuf_printf(out, "\n%*s", HELP_INDENT, "");
    cli_help_wrap(out, text, HELP_INDENT, HELP_INDENT);
}

void cli_help(enum command cmd, struct strbuf *out)
{
    const struct command_def *c = &commands[cmd];
    struct options defaults = {0};
    cli_options_defaults(&defaults, cmd);
    strbuf_printf(out, "usage: shadowbench %s\n\n%s", c->synopsis, c->about);
    strbuf_printf(out, "\noptions:\n");
    for (const struct option_row *r = option_rows; r->name; r++) {
        if (!(r->commands & (1u << cmd)))
            continue;
        struct strbuf name = {0}, help = {0};
        strbuf_printf(&name, "  %s%s--%s%s%s", r->short_name ? (char[]){'-', r->short_name, 0} : "",
                      r->short_name ? ", " : "", r->name, r->arg ? " " : "", r->arg ? r->arg : "");
        option_help(r, cmd, &defaults, &help);
        cli_help_item(out, name.data + 2, help.data);
        strbuf_free(&name), strbuf_free(&help);
    }
    if (c->after)
        strbuf_printf(out, "\n%s", c->after);
    if (c->more)
        c->more(out);
}

void cli_help_main(struct strbuf *out)
{
    strbuf_printf(out, "usage: shadowbench <command> [options]\n\n"
                       "Measures real-time shadow techniques against an Embree ray-traced area-light\n"
                       "ground truth: error numbers, signed-error heatmaps, a comparison matrix, timings.\n\n"
                       "commands:\n");
    for (int k = 0; k < COMMAND_COUNT; k++) {
        strbuf_printf(out, "  %-11s", commands[k].name);
        cli_help_wrap(out, commands[k].summary, 13, 13);
    }
    strbuf_printf(out, "\n'shadowbench <command> --help' or 'shadowbench help <command>' explains each\n"
                       "command's options; docs/cli.md has them all.\n"
                       "exit status: 0 ok, 1 a check failed (e.g. NaN in a technique's output) or a\n"
                       "runtime error, 2 bad usage or input, or an engine that cannot start or render\n"
                       "(run, tune, check: one line naming the engine and the cell).\n");
}

void cli_help_markdown(struct strbuf *out)
{
    strbuf_printf(out, "# Command line\n\n"
                       "Every command's `--help`, as `shadowbench help --markdown` prints it from the\n"
                       "command and option tables (`harness/cli/commands.c`, `harness/cli/options.c`);\n"
                       "`test_cli_docs` fails when this page and the program disagree.\n\n"
                       "| command | what it does |\n| --- | --- |\n");
    for (int k = 0; k < COMMAND_COUNT; k++)
        strbuf_printf(out, "| [`%s`](#shadowbench-%s) | %s |\n", commands[k].name, commands[k].name,
                      commands[k].summary);
    strbuf_printf(out, "\n## shadowbench\n\n```text\n");
    cli_help_main(out);
    strbuf_printf(out, "```\n");
    for (int k = 0; k < COMMAND_COUNT; k++) {
        strbuf_printf(out, "\n## shadowbench %s\n\n```text\n", commands[k].name);
        cli_help((enum command)k, out);
        strbuf_printf(out, "```\n");
    }
}
