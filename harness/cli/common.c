/* What every command does the same way before its work. */
#include "cli.h"
#include "gl/shader.h"
#include "base/log.h"
#include "output/out_dir.h"
#include "output/provenance.h"
#include "scene/catalog.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>

int cli_load_scenes(const struct options *o, const char *const *defaults, int default_count, struct scene *scenes,
                    int max, int *count)
{
    const bool named = o->scene_count > 0;
    const int rc = catalog_load(named ? o->scenes : defaults, named ? o->scene_count : default_count, output_files,
                                scenes, max, count);
    if (rc == -ENOMEM) {  /* said; a runtime error, not bad input. Nothing is written yet. */
        for (int i = 0; i < *count; i++)
            scene_free(&scenes[i]);
        exit(EXIT_CHECK_FAILED);
    }
    return rc;
}

int cli_gl_open(const struct options *o, enum gl_backend backend)
{
    /* a bad --shaders is bad usage; so is a context that cannot be made here */
    return shader_init(o->shader_dir) != 0 || gl_context_create(backend) != 0 ? -1 : 0;
}

int cli_require_committed(const struct options *o, const char *what)
{
    char changed[512];
    const enum source_state state = provenance_source_state(changed, sizeof changed);
    if (state == SOURCE_CLEAN || o->allow_uncommitted)
        return 0;
    if (state == SOURCE_CHANGED)
        log_error("%s: the source tree has uncommitted changes to code that renders or scores (%s, ...): what "
                  "it records would name a build nobody can reproduce; commit them, or pass --allow-uncommitted "
                  "(recorded in the files it writes)", what, changed);
    else if (state == SOURCE_NOT_GIT)
        log_error("%s: the source tree (%s) is not a git checkout, so what it records cannot name the code it came "
                  "from; pass --allow-uncommitted (recorded in the files it writes)", what, SB_SOURCE_DIR);
    else
        log_error("%s: git failed on the source tree %s (%s), so what it records cannot name the code it came "
                  "from; mend that, or pass --allow-uncommitted (recorded in the files it writes)", what,
                  SB_SOURCE_DIR, changed);
    return -1;
}

void cli_done(const struct options *o, int status, bool written, const char *what, enum output_file page,
              const char *data_name, enum output_file data, double start_ms)
{
    util_signals_finished(status);
    if (!written)
        return;
    printf("report: %s/%s\n%s: %s/%s\n", o->out_dir, output_files[page], data_name, o->out_dir, output_files[data]);
    log_info("%s finished in %.1f s", what, (util_now_ms() - start_ms) * 1e-3);
}
