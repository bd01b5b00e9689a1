/* Output folders (docs/design.md §8): the names of a run's own files, written
 * once, and how a command takes a folder for itself: one writer at a time
 * (a lock held for the rest of the process), a killed run's temporaries
 * removed, and a folder that shadowbench did not make left alone. */
#ifndef SB_OUT_DIR_H
#define SB_OUT_DIR_H

/* X(ID, name): the files a command writes at the top of its output folder.
 * A scene's folder, <out>/<scene name>, may take none of these names. */
#define OUTPUT_FILES(X)                                                           \
    X(RUN_JSON, "run.json") X(MATRIX_CSV, "matrix.csv") X(MATRIX_JSON, "matrix.json") X(DEPTH_CSV, "depth.csv") \
    X(REPORT, "report.html") X(CHARTS, "charts") X(CHECK_PAGE, "check.html")          \
    X(STABILITY_JSON, "stability.json") X(STABILITY_CSV, "stability.csv")             \
    X(STABILITY_PAGE, "stability.html") X(TUNE_JSON, "tune.json") X(SHARD_JSON, "shard.json")

enum output_file {
#define X(id, name) OUTPUT_##id,
    OUTPUT_FILES(X)
#undef X
    OUTPUT_FILE_COUNT
};

/* Their names, by enum value, NULL-terminated. */
extern const char *const output_files[OUTPUT_FILE_COUNT + 1];

/* "<dir>/<name of f>", malloc'ed. */
char *out_dir_path(const char *dir, enum output_file f);

/* Creates dir and checks it is writable. Returns 0 or -1 (logged). */
int out_dir_prepare(const char *dir);

/* out_dir_prepare, then an exclusive lock on it for the rest of the process
 * (a second shadowbench on it fails at once) and the removal of the
 * temporaries a killed run left there (<out>/<scene>/<cell>/files). A
 * folder holding files that shadowbench did not make (no .lock) is
 * refused. Returns 0 or -1 (logged). */
int out_dir_claim(const char *dir);

#endif
