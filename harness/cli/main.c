/* shadowbench: measures real-time shadow techniques against a ray-traced
 * area-light ground truth. This file picks the command; commands.c and
 * options.c say what each command and option is. */
#include "cli.h"
#include "base/log.h"
#include "base/util.h"
#include "truth/groundtruth.h"

#include <cjson/cJSON.h>

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

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

/* Whether the command was started with standard output closed. */
static bool stdout_closed;

/* A standard stream started closed would be the next file opened (.lock
 * would take the report's lines): each is opened on /dev/null first. */
static void open_standard_streams(void)
{
    for (int fd = 0; fd <= 2; fd++)
        if (fcntl(fd, F_GETFD) < 0 && errno == EBADF) {
            stdout_closed |= fd == STDOUT_FILENO;
            if (open("/dev/null", fd ? O_WRONLY : O_RDONLY) != fd)
                _exit(EXIT_CHECK_FAILED);  /* no stream left to say it on */
        }
}

/* The command's status once standard output is written whole. A reader
 * that closed the pipe early (`| head`) stops nothing: SIGPIPE is ignored,
 * the work is done and its status stands. Any other failure to write it (a
 * full disk, /dev/full) is one line and exit 1. */
static int finish_stdout(int status)
{
    const int flushed = fflush(stdout), err = errno;
    if (stdout_closed) {  /* what it printed went nowhere, as into a full disk */
        log_error("standard output: cannot write: it is closed");
        return status ? status : EXIT_CHECK_FAILED;
    }
    if (flushed == 0 && !ferror(stdout))
        return status;
    struct pollfd p = {.fd = STDOUT_FILENO, .events = POLLOUT};
    if (poll(&p, 1, 0) == 1 && (p.revents & POLLERR))  /* a pipe whose reader is gone */
        return status;
    log_error("standard output: cannot write: %s", flushed ? strerror(err) : "a write failed, so what it shows is "
              "incomplete");
    return status ? status : EXIT_CHECK_FAILED;
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

static int run(int argc, char **argv)
{
    if (argc < 2) {
        print(cli_help_main, stderr);
        return EXIT_USAGE;
    }
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

int main(int argc, char **argv)
{
    open_standard_streams();
    util_exit_cleanly_on_signals();
    /* cJSON reads a failed allocation as malformed JSON: out of memory is
     * said as such instead (util_out_of_memory) */
    cJSON_InitHooks(&(cJSON_Hooks){.malloc_fn = xmalloc, .free_fn = free});
    return finish_stdout(run(argc, argv));
}
