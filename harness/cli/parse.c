/* Parsing a command line with the option table (options.c), and the rules
 * across options. */
#include "options.h"
#include "base/log.h"
#include "base/util.h"
#include "engine/engine.h"
#include "pipeline/stability.h"
#include "score/metrics.h"
#include "score/tuned.h"
#include "techniques/params.h"
#include "techniques/shadowmap.h"
#include "truth/groundtruth.h"

#include <errno.h>
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int options_int(const char *opt, const char *text, int lo, int hi, int *out)
{
    char *end;
    errno = 0;
    long v = strtol(text, &end, 10);
    if (!*text || *end || errno || !(text[0] == '-' || (text[0] >= '0' && text[0] <= '9'))) {
        log_error("--%s: '%s' is not a whole number", opt, text);
        return -1;
    }
    if (v < lo || v > hi) {
        log_error("--%s: %ld is out of range [%d, %d]", opt, v, lo, hi);
        return -1;
    }
    *out = (int)v;
    return 0;
}

int options_choice(const char *opt, const char *text, const char *const *names, int *out)
{
    for (int i = 0; names[i]; i++)
        if (strcmp(names[i], text) == 0) {
            *out = i;
            return 0;
        }
    struct strbuf known = {0};
    strbuf_join(&known, names, ", ");
    log_error("--%s: '%s' is not one of: %s", opt, text, known.data);
    strbuf_free(&known);
    return -1;
}

int options_folder(const char *opt, const char *text, const char **out)
{
    if (!*text) {
        log_error("--%s: an empty folder name", opt);
        return -1;
    }
    if (util_file_exists(text) && !util_is_dir(text)) {
        log_error("--%s %s: not a folder", opt, text);
        return -1;
    }
    *out = text;
    return 0;
}

void cli_options_defaults(struct options *o, enum command cmd)
{
    const struct command_def *c = &commands[cmd];
    o->cmd = cmd;
    o->width = o->height = c->size ? c->size : CLI_DEFAULT_SIZE;
    o->gt_samples = c->gt_samples ? c->gt_samples : GT_DEFAULT_SAMPLES;
    o->shadow_map_size = SHADOWMAP_DEFAULT_SIZE;
    o->cascades = (struct cascade_settings){.count = 1, .split = CASCADE_SPLIT_PRACTICAL,
                                            .lambda = CLI_DEFAULT_CASCADE_LAMBDA};
    o->frames = c->frames;
    o->warmup = c->warmup;
    o->engine_timeout = (int)ENGINE_TIME_LIMIT_S;
    o->out_dir = c->out;
    o->cache_dir = CLI_DEFAULT_CACHE;
    o->baselines_dir = CLI_DEFAULT_BASELINES;
    o->tuned_dir = TUNED_DEFAULT_DIR;
    o->objective = METRIC_penumbra_rmse;
    o->accumulate = STABILITY_DEFAULT_ACCUMULATE;
}

/* The rules across options, once every option is read. */
static int check_options(struct options *o)
{
    const struct command_def *c = &commands[o->cmd];
    if (o->update && o->strict) {
        log_error("--strict: has no effect with --update (which records every cell)");
        return -1;
    }
    if (o->update && o->shard.count) {
        log_error("--shard: check --update records every baseline as one set; record them unsharded");
        return -1;
    }
    if (o->allow_uncommitted && !o->update && !o->write_tuned) {
        log_error("--allow-uncommitted: has an effect only when recording (check --update, tune --write-tuned)");
        return -1;
    }
    if (o->cascades.split == CASCADE_SPLIT_FRACTIONS && o->fractions_given != o->cascades.count - 1) {
        log_error("--cascade-split: %d fractions for %d cascades (it takes one fewer: the splits between them)",
                  o->fractions_given, o->cascades.count);
        return -1;
    }
    if (c->needs_scene && o->scene_count == 0) {
        log_error("%s: --scene is required (see --help)", c->name);
        return -1;
    }
    if (o->cmd == CMD_VIEW && o->screenshot && o->frames == 0)
        o->frames = 1;
    if (o->tuned_given && o->cmd == CMD_TUNE && !o->write_tuned) {
        log_error("--tuned: tune writes there only with --write-tuned");
        return -1;
    }
    if (o->tuned_given && o->cmd != CMD_TUNE && !util_is_dir(o->tuned_dir)) {  /* a typo would drop every tuned cell */
        log_error("--tuned %s: no such folder", o->tuned_dir);
        return -1;
    }
    for (int i = 0; technique_list[i] && o->technique_count; i++)
        if (o->settings[i] && !technique_in(o->techniques, o->technique_count, technique_list[i])) {  /* set, so meant: as a sweep of it would be */
            log_error("--set: %s is not among the techniques selected with --technique", technique_list[i]->name);
            return -1;
        }
    /* Every technique selected when none is, every setting at its default
     * unless --set, and (without sweeps: run checks each configuration once
     * its swept values are in) the rules across parameters. */
    /* engine cells and presets only when named: engines need a browser, and
     * both take their own time (docs/presets.md) */
    if (!o->technique_count)
        for (const struct technique *const *t = technique_list; *t; t++)
            if (!technique_named_only(*t))
                o->techniques[o->technique_count++] = *t;
    for (int i = 0; i < o->technique_count; i++)
        if (technique_is_engine(o->techniques[i]) && o->cmd != CMD_RUN && o->cmd != CMD_TUNE &&
            o->cmd != CMD_CHECK) {
            log_error("%s: %s is an engine cell (%s, rendered in a browser): run, tune and check take engine "
                      "cells, %s does not (docs/engines.md)", c->name, o->techniques[i]->name,
                      o->techniques[i]->engine, c->name);
            return -1;
        }
    for (int i = 0; i < o->technique_count; i++) {
        if (!technique_is_engine(o->techniques[i]))
            continue;
        if (o->cascades.count > 1) {  /* an engine gets one map: the nearest slice alone would lie */
            log_error("--cascades %d: %s is an engine cell, rendered with one map over the view; engine cells "
                      "take no cascades (docs/engines.md)", o->cascades.count, o->techniques[i]->name);
            return -1;
        }
        if (o->cost_fetches) {
            log_error("--cost fetches: %s is an engine cell, whose fetches are the engine's and are not counted "
                      "(docs/engines.md)", o->techniques[i]->name);
            return -1;
        }
    }
    engine_set_time_limit(o->engine_timeout);
    for (int i = 0; technique_list[i]; i++)
        if (!o->settings[i])
            o->settings[i] = params_defaults(technique_list[i]);
    for (int i = 0; i < o->technique_count && o->cmd != CMD_RUN; i++)
        if (params_check(o->techniques[i], cli_settings(o, o->techniques[i])) != 0)
            return -1;
    return 0;
}

static int apply(const struct option_row *r, struct options *o, const char *arg)
{
    char *base = (char *)o + r->offset;
    if (r->call)
        return r->call(o, arg);
    switch (r->kind) {
    case OPTION_NONE: return -1;
    case OPTION_FLAG: *(bool *)base = true; return 0;
    case OPTION_INT: return options_int(r->name, arg, r->lo, r->hi, (int *)base);
    case OPTION_FOLDER: return options_folder(r->name, arg, (const char **)base);
    case OPTION_TEXT: *(const char **)base = arg; return 0;
    case OPTION_HELP: return 0;
    }
    return -1;
}

enum cli_parse_result cli_parse(int argc, char **argv, enum command cmd, struct options *o)
{
    cli_options_defaults(o, cmd);
    int rows = 0;
    while (option_rows[rows].name)
        rows++;
    struct option *long_options = xcalloc((size_t)rows + 1, sizeof *long_options);
    char shorts[16] = "+:";
    int n = 0;
    for (const struct option_row *r = option_rows; r->name; r++, n++) {
        long_options[n] = (struct option){r->name, r->arg ? required_argument : no_argument, NULL, 256 + n};
        if (r->short_name)
            snprintf(shorts + strlen(shorts), sizeof shorts - strlen(shorts), "%c", r->short_name);
    }
    int c, index = 0, at = 1;
    enum cli_parse_result result = CLI_PARSE_OK;
    free(o->placement);
    o->placement = xcalloc((size_t)argc + 1, sizeof *o->placement);
    optind = 0;  /* glibc's full reset: "+" is read again (merge parses a second command line) */
    opterr = 0;
    /* "+": options stop at the first argument that is none, so what each
     * consumed, argv[at..optind-1], is where it was given; merge's folders
     * and options may mix (it records no placement) */
    if (commands[cmd].operands)
        memmove(shorts, shorts + 1, strlen(shorts));
    for (; result == CLI_PARSE_OK && (c = getopt_long(argc, argv, shorts, long_options, &index)) != -1;
         at = optind) {
        const struct option_row *r = option_rows;
        if (c >= 256)
            r += c - 256;
        else
            while (r->name && r->short_name != c)
                r++;
        if (c == '?' || c == ':' || !r->name) {
            log_error("%s: %s (see --help)", argv[optind - 1], c == ':' ? "needs a value" : "unknown option");
            result = CLI_PARSE_ERROR;
        } else if (!(r->commands & (1u << cmd))) {
            log_error("--%s: unknown option for %s (see --help)", r->name, commands[cmd].name);
            result = CLI_PARSE_ERROR;
        } else if (r->kind == OPTION_HELP) {
            struct strbuf help = {0};
            cli_help(cmd, &help);
            fputs(help.data, stdout);
            strbuf_free(&help);
            result = CLI_PARSE_HELP;
        } else if (apply(r, o, optarg) != 0) {
            result = CLI_PARSE_ERROR;
        } else if (!strcmp(r->name, "shard") || !strcmp(r->name, "out")) {
            for (int k = at; k < optind; k++)
                o->placement[k] = true;
        }
    }
    free(long_options);
    if (result != CLI_PARSE_OK)
        return result;
    if (commands[cmd].operands) {
        o->operands = argv + optind;
        o->operand_count = argc - optind;
    } else if (optind < argc) {
        log_error("%s: unexpected argument (see --help)", argv[optind]);
        return CLI_PARSE_ERROR;
    }
    return check_options(o) ? CLI_PARSE_ERROR : CLI_PARSE_OK;
}

void *cli_settings(const struct options *o, const struct technique *t)
{
    return o->settings[technique_index(t)];
}

void cli_options_free(struct options *o)
{
    free(o->placement);
    o->placement = NULL;
    for (int i = 0; i < TECHNIQUE_COUNT_MAX; i++)
        free(o->settings[i]);
    memset(o->settings, 0, sizeof o->settings);
}
