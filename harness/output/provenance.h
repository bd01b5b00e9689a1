/* Where a result came from (docs/design.md §8): one record, written with the
 * same keys into run.json, tuned files and baselines (util_json_merge): the
 * command line (as UTF-8 text), the versions, the device, the CPU, the date
 * (UTC), `git describe` of the source tree ("-dirty" where its code has
 * uncommitted changes) and whether its code was committed ("source_tree"). */
#ifndef SB_PROVENANCE_H
#define SB_PROVENANCE_H

#include "render/stage_timer.h"

#include <cjson/cJSON.h>
#include <stdbool.h>

/* The record of this process: its command line argv[0..argc-1], the GL
 * context now current, and how it times stages (timed false: it times
 * nothing). */
cJSON *provenance_json(int argc, char **argv, bool timed, enum stage_timing timing);

/* The state of the source tree's code that renders or scores (its folders
 * harness/, techniques/, shaders/, scenes/ and CMakeLists.txt): committed,
 * or with changes git has not committed (edited or new files), or no git
 * checkout to tell. */
/* UNKNOWN: git failed (a repository it refuses, no file descriptors left). */
enum source_state { SOURCE_CLEAN, SOURCE_CHANGED, SOURCE_NOT_GIT, SOURCE_UNKNOWN };

/* The state, and into what the first path changed (SOURCE_CHANGED) or why
 * git failed (SOURCE_UNKNOWN). */
enum source_state provenance_source_state(char *what, size_t size);

/* What names the code that renders or scores, for telling shards of one
 * code from another (docs/scale-out.md): the commit ("git <hash>"), with
 * a hash of its uncommitted changes and new files where there are any
 * ("+changes <hash>"); without git, the version and the executable's bytes.
 * As the source tree was at the first call (shaders are read from it as a
 * command starts). malloc'ed. */
char *provenance_code_id(void);

/* The state in words, as the record's "source_tree" says it. */
const char *provenance_source_text(enum source_state s);

#endif
