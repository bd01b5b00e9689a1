/* A test's read of a JSON file it expects: an unreadable or malformed one
 * fails the test (never a silent pass). */
#ifndef SB_TEST_READ_JSON_H
#define SB_TEST_READ_JSON_H

#include "check.h"
#include "base/util.h"

#include <cjson/cJSON.h>
#include <stdlib.h>

static inline cJSON *read_json(const char *path)
{
    char *text = NULL;
    size_t size;
    cJSON *j = util_read_file(path, &text, &size) == 0 ? cJSON_Parse(text) : NULL;
    free(text);
    CHECK(j, "%s: not readable JSON", path);
    return j;
}

#endif
