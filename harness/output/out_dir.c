#include "out_dir.h"
#include "base/log.h"
#include "base/util.h"

#include <dirent.h>
#include <stdbool.h>
#include <string.h>

const char *const output_files[OUTPUT_FILE_COUNT + 1] = {
#define X(id, name) name,
    OUTPUT_FILES(X)
#undef X
    NULL,
};

char *out_dir_path(const char *dir, enum output_file f)
{
    return util_printf("%s/%s", dir, output_files[f]);
}

int out_dir_prepare(const char *dir)
{
    if (util_mkdirs(dir) != 0)
        return -1;
    if (!util_dir_writable(dir)) {
        log_error("%s: not a writable folder", dir);
        return -1;
    }
    return 0;
}

/* Whether dir exists with something in it other than what shadowbench
 * itself leaves (its .lock). */
static bool foreign_dir(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d)
        return false;
    bool any = false, lock = false;
    for (struct dirent *e; (e = readdir(d));) {
        lock |= strcmp(e->d_name, ".lock") == 0;
        any |= strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0;
    }
    closedir(d);
    return any && !lock;
}

int out_dir_claim(const char *dir)
{
    /* A folder shadowbench did not make is not cleaned: its report.html or
     * *.tmp.<pid> files may be someone else's. */
    if (foreign_dir(dir)) {
        log_error("%s: holds files and was not made by shadowbench (no .lock in it): name a new or empty "
                  "output folder", dir);
        return -1;
    }
    if (out_dir_prepare(dir) != 0 || util_lock_dir(dir) != 0)
        return -1;
    util_remove_stale_temps(dir, 3);  /* <out>/<scene>/<cell>/files */
    return 0;
}
