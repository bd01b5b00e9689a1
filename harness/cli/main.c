/* shadowbench: measures real-time shadow techniques against a ray-traced
 * area-light ground truth. This file picks the command; commands.c and
 * options.c say what each command and option is. */
#include "cli.h"
#include "base/log.h"
#include "base/util.h"
#include "truth/groundtruth.h"

#include <stdio.h>
#include <string.h>

static int command_named(const char *name)
{
    for (int k = 0; k < COMMAND_COUNT; k++)
        if (strcmp(commands[k].name, name) == 0)
            return k;
    return -1;
}

static void print(void (*help)(struct strbuf *), FILE *to)
{
    struct strbuf text = {0};
    help(&text);
    fputs(text.data, to);
    strbuf_free(&text);
}

static int unknown_command(const char *name)
{
    struct strbuf names = {0};
    for (int k = 0; k < COMMAND_COUNT; k++)
        strbuf_list_printf(&names, ", ", "%s", commands[k].name);
    log_error("unknown command '%s' (commands: %s; see --help)", name, names.data);
    strbuf_free(&names);
    return EXIT_USAGE;
}

int help_main(const struct options *o)
{
    struct strbuf text = {0};
    if (o->markdown)
        cli_help_markdown(&text);
    else
        cli_help_main(&text);
    fputs(text.data, stdout);
    strbuf_free(&text);
    return EXIT_OK;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        print(cli_help_main, stderr);
        return EXIT_USAGE;
    }
    util_exit_cleanly_on_signals();
    const char *name = argv[1];
    if (strcmp(name, "--help") == 0 || strcmp(name, "-h") == 0) {
        print(cli_help_main, stdout);
        return EXIT_OK;
    }
    const int k = command_named(name);
    if (k < 0)
        return unknown_command(name);
    if (k == CMD_HELP && argc >= 3 && argv[2][0] != '-') {  /* shadowbench help COMMAND */
        const int of = command_named(argv[2]);
        if (of < 0)
            return unknown_command(argv[2]);
        if (argc > 3) {
            log_error("%s: unexpected argument (see --help)", argv[3]);
            return EXIT_USAGE;
        }
        struct strbuf text = {0};
        cli_help((enum command)of, &text);
        fputs(text.data, stdout);
        strbuf_free(&text);
        return EXIT_OK;
    }
    struct options o = {.argc = argc, .argv = argv};
    const enum cli_parse_result rc = cli_parse(argc - 1, argv + 1, (enum command)k, &o);
    const int status = rc == CLI_PARSE_HELP ? EXIT_OK : rc == CLI_PARSE_ERROR ? EXIT_USAGE : commands[k].main(&o);
    cli_options_free(&o);
    gt_shutdown();
    return status;
}
