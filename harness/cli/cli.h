/* The command line (docs/design.md §10; docs/cli.md). One table of commands
 * (commands.c: name, summary, entry, defaults, help) and one of options
 * (options.c: name, argument, the commands that take it, help), from which
 * parsing, the "not an option of this command" check, --help and
 * docs/cli.md are generated. A command (one file each) calls the library,
 * loops over its cells and sets the exit status. */
#ifndef SB_CLI_H
#define SB_CLI_H

#include "base/util.h"
#include "gl/gl_context.h"
#include "output/out_dir.h"
#include "pipeline/configs.h"
#include "pipeline/shard.h"
#include "render/receiver.h"
#include "render/stage_timer.h"
#include "scene/scene.h"
#include "techniques/technique.h"

#include <cjson/cJSON.h>
#include <stdbool.h>

/* Exit statuses (docs/design.md §10). */
enum { EXIT_OK = 0, EXIT_CHECK_FAILED = 1, EXIT_USAGE = 2 };

/* X(ID, name): every command, in the order --help lists them. */
#define COMMANDS(X)                                                                                 \
    X(RUN, "run") X(GT, "gt") X(BENCH, "bench") X(CHECK, "check") X(TUNE, "tune")                    \
    X(STABILITY, "stability") X(MERGE, "merge") X(VIEW, "view") X(LIST, "list")     \
    X(HELP, "help")

enum command {
#define X(id, name) CMD_##id,
    COMMANDS(X)
#undef X
    COMMAND_COUNT
};

#define CLI_MAX_SCENES 64
#define CLI_MAX_TECHNIQUES TECHNIQUE_SELECTION_MAX
#define CLI_MAX_MOTIONS 16
#define CLI_MAX_VARIES 16
#define CLI_MAX_WARMUP 100

/* Everything a command line says, every option at its command's default
 * first (cli_options_defaults). */
struct options {
    enum command cmd;
    const char *scenes[CLI_MAX_SCENES];  /* names or paths; none = the command's default scenes */
    int scene_count;
    const struct technique *techniques[CLI_MAX_TECHNIQUES];  /* at least one once parsed */
    int technique_count;
    void *settings[TECHNIQUE_COUNT_MAX];  /* per technique_list index, every one set */
    int set_count;                       /* --set options given */
    unsigned long long held[TECHNIQUE_COUNT_MAX];  /* per technique_list index: bit k, its params[k] --set */
    const char *sweeps[CONFIG_MAX_SWEEPS];  /* --sweep T.P=v1,v2,... as given */
    int sweep_count;
    int width, height;                   /* image size in pixels */
    int gt_samples;                      /* light samples per pixel of the ground truth */
    int shadow_map_size;                 /* texels */
    struct cascade_settings cascades;    /* the sun's (--cascades ...) */
    int fractions_given;                 /* --cascade-split f1,f2,...: how many */
    int frames;                          /* timed frames; stability: of each motion; view: drawn, 0 = until closed */
    int warmup;                          /* untimed frames first (0 allowed) */
    int engine_timeout;                  /* seconds an engine cell may take */
    bool keep_going;                     /* run: a failed engine cell does not stop the run */
    const char *out_dir;
    const char *cache_dir;               /* NULL: no ground-truth cache */
    const char *shader_dir;              /* NULL: found automatically */
    enum gl_backend gl;                  /* --gl: the context's backend */
    enum stage_timing timing;            /* --timing: how stages are timed */
    const char *baselines_dir;           /* check: the baselines read (and written by update) */
    bool update;                         /* check: record the selected baselines anew */
    bool strict;                         /* check: an improvement fails too */
    bool allow_uncommitted;              /* check --update, tune --write-tuned: record from a changed tree */
    const char *tuned_dir;               /* run, check: tuned settings read; tune: written */
    bool tuned_given;                    /* --tuned was given */
    enum config_mode settings_mode;      /* run: default, tuned or both cells */
    int objective;                       /* tune: the metric minimised (METRIC_*) */
    bool cost_fetches;                   /* tune --cost fetches: the frontiers by counted fetches */
    bool write_tuned;                    /* tune: write tuned_dir/<technique>.json */
    const char *motions[CLI_MAX_MOTIONS];  /* stability: --motion specs as given */
    int motion_count;
    const char *varies[CLI_MAX_VARIES];    /* stability: --vary specs as given */
    int vary_count;
    double accumulate;                   /* stability: the accumulation's weight of a new frame */
    const char *screenshot;              /* view: the PNG the last frame is written to */
    const char *script;                  /* view: key events replayed */
    bool markdown;                       /* help: docs/cli.md */
    struct shard shard;                  /* --shard K/N (count 0: the whole command) */
    bool *placement;                     /* per argument after the command's name: --shard's or --out's
                                            (where a shard runs and writes, not what it computes) */
    char **operands;                     /* merge: OUT SHARD... */
    int operand_count;
    int argc;                            /* the command line, for the provenance record */
    char **argv;
};

/* A command's row (commands.c). */
struct command_def {
    const char *name;
    const char *summary;                  /* one line for shadowbench --help */
    int (*main)(const struct options *o);
    const char *synopsis;                 /* after "usage: shadowbench " */
    bool operands;                        /* takes arguments that are not options (merge's folders) */
    const char *about;                    /* before the options */
    const char *after;                    /* after them (may be NULL) */
    void (*more)(struct strbuf *out);     /* help generated from other tables (may be NULL) */
    bool one_scene, needs_scene;          /* takes at most one --scene; needs one */
    /* The command's defaults (0, NULL: the option's own, or none). */
    int size, frames, warmup, gt_samples;
    const char *out;
    /* What an option means to this command, where it differs from the
     * option's own help ({"scene", "(required)"}), ending with {NULL}. */
    const struct option_note {
        const char *option, *help;
    } *notes;
};
extern const struct command_def commands[COMMAND_COUNT];

/* Every option at command cmd's default (0 warm-up frames and no cache are
 * choices, not "unset"). */
void cli_options_defaults(struct options *o, enum command cmd);

/* Parses argv[1..argc-1] (argv[0]: the command's name) into o. */
enum cli_parse_result {
    CLI_PARSE_ERROR = -1,  /* logged: exit 2 */
    CLI_PARSE_OK = 0,
    CLI_PARSE_HELP = 1,    /* --help printed: exit 0 */
};
enum cli_parse_result cli_parse(int argc, char **argv, enum command cmd, struct options *o);

void cli_options_free(struct options *o);

/* Command cmd's --help (help.c). */
void cli_help(enum command cmd, struct strbuf *out);
/* shadowbench --help: the commands. */
void cli_help_main(struct strbuf *out);
/* docs/cli.md: every command's --help. */
void cli_help_markdown(struct strbuf *out);

/* The settings of technique t in o. */
void *cli_settings(const struct options *o, const struct technique *t);

/* The commands' shared steps (common.c), each logging its refusal: */
/* the scenes of o (its default scenes when none is named), at most max
 * (the room in scenes): 0 or -1 (scene_free the *count loaded either way); */
int cli_load_scenes(const struct options *o, const char *const *defaults, int default_count, struct scene *scenes,
                    int max, int *count);
/* the shaders and the GL context of o's --shaders and --gl: 0 or -1 (bad
 * usage: a --shaders that is not one, a context that cannot be made here). */
int cli_gl_open(const struct options *o, enum gl_backend backend);

/* Recording committed results (check --update, tune --write-tuned, named
 * by `what`) needs committed code: 0, or -1 after one line saying what
 * changed, unless --allow-uncommitted (which the files record). */
int cli_require_committed(const struct options *o, const char *what);

/* The end of a command whose last writes held signals (util.h), with its
 * status: signals end it from now on with that status; and, written (its
 * outputs are), its last words: where its page and its data are (stdout)
 * and how long it took (the log), for what ("run", "stability"). */
void cli_done(const struct options *o, int status, bool written, const char *what, enum output_file page,
              const char *data_name, enum output_file data, double start_ms);

/* run.json's record of o (run.c): the provenance (timed: whether the
 * command times stages), the sizes and frames, and the seconds it took. */
cJSON *cli_run_record(const struct options *o, bool timed, double seconds);

/* Shards (docs/scale-out.md). A sharded command's last write, once its
 * outputs are complete: <out>/shard.json, which says what it computed
 * (the command, its arguments but --shard and --out, the code, the
 * ground truth's version, the scenes and their bytes) and which shard it
 * is, with `more`'s keys (taken; may be NULL). Unsharded: nothing. Returns
 * 0 or -1 (logged). cli_shard_begin removes the last one first: a folder
 * being written is no finished shard. */
void cli_shard_begin(const struct options *o);
int cli_shard_end(const struct options *o, const struct scene *scenes, int scene_count, cJSON *more);

/* A cell's expected cost for the split into shards: 1 for one of
 * shadowbench's own, 20 for an engine cell (an estimate, not a
 * measurement: it starts a browser and renders there, docs/scale-out.md). */
static inline double cli_cell_cost(const struct technique *t)
{
    return technique_is_engine(t) ? 20.0 : 1.0;
}

/* The owner (1..shards) of each of run's cells, scene by scene in
 * configuration order (owner[scene * configs + config]): contiguous runs
 * of about equal expected cost (cli_cell_cost). */
void run_owners(const struct config_set *configs, int scene_count, int shards, int *owner);

/* The owner of each technique of a tuning (o->techniques' order): balanced
 * by each one's search size (tuner_size: the values of its tuned
 * parameters). */
void tune_owners(const struct options *o, int shards, int *owner);

/* What merge (merge.c) hands a command's merge: shards 1..count of one
 * command line, checked to agree. */
struct merge_input {
    const char *const *dirs;     /* [1..count]: shard k's folder */
    cJSON *const *records;       /* [1..count]: its shard.json */
    int count;
    const struct options *merge; /* merge's own command line */
};
/* Each command's merge: writes into o->out_dir what the command o (the
 * shards' command line, unsharded) writes, from the shards' outputs, and
 * returns the exit status the command would have. */
int run_merge(const struct options *o, const struct merge_input *in);
int tune_merge(const struct options *o, const struct merge_input *in);
int check_merge(const struct options *o, const struct merge_input *in);
int stability_merge(const struct options *o, const struct merge_input *in);

/* Whether path is a file, not a link (else logged: missing, or what it
 * is); and a copy of one (from) to to, written atomically, its folder
 * made (the last one, as shadowbench's own): 0 or -1 (logged). */
bool cli_is_file(const char *path);
int cli_copy_file(const char *from, const char *to);

/* A command's plan: its cells' names in its order, hashed one by one
 * (cli_plan_add), which every shard records and merge computes again, so
 * that inputs that changed in between (tuned files, baselines) are
 * refused rather than merged into the wrong cells. A shard's record of
 * its time and plan (for cli_shard_end); merge's check of the plan
 * (0, or -1 logged). */
uint64_t cli_plan_add(uint64_t plan, const char *name);
cJSON *cli_shard_more(double seconds, uint64_t plan);
int cli_merge_plan(const struct merge_input *in, uint64_t plan);

/* The shards' time side by side: the longest shard's seconds. */
double cli_merge_seconds(const struct merge_input *in);

/* The merged record of the shards (their shard.json each, under
 * "shards"), added to a command's record r. */
void cli_merge_record(cJSON *r, const struct merge_input *in);

/* stability's defaults, when it is given no --scene (the scenes), or no
 * --motion and no --vary (the motions and variations; "scene": each
 * scene's own motions, extras.shadowbench.motions). */
#define STABILITY_DEFAULT_SCENES 3
#define STABILITY_DEFAULT_MOTIONS 5
#define STABILITY_DEFAULT_VARIES 3
extern const char *const stability_default_scenes[STABILITY_DEFAULT_SCENES];
extern const char *const stability_default_motions[STABILITY_DEFAULT_MOTIONS];
extern const char *const stability_default_varies[STABILITY_DEFAULT_VARIES];

/* The entries. */
int run_main(const struct options *o);
int gt_main(const struct options *o);
int bench_main(const struct options *o);
int check_main(const struct options *o);
int tune_main(const struct options *o);
int stability_main(const struct options *o);
int view_main(const struct options *o);
int list_main(const struct options *o);
int help_main(const struct options *o);
int merge_main(const struct options *o);

#endif
