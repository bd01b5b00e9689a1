/* A folder of recorded results (tuned settings, baselines) rewritten as one
 * set: a reader sees the previous set or the next, never a mix, whatever
 * stops the writer (docs/outputs.md).
 *
 * The next set is a sibling folder, "<dir>.tmp.<pid>", that starts as a
 * copy of dir (hard links: files are only ever replaced by rename, never
 * written in place, so the two sets share nothing that changes); the
 * command writes into it, and commit swaps the two folders in one step
 * (renameat2's RENAME_EXCHANGE) and removes the previous set. A writer
 * killed before that leaves dir as it was and its next set for the next
 * writer to remove. Readers take no lock and read file by file: one that
 * reads while a set is swapped in can still read one file of each. */
#ifndef SB_RESULTS_SET_H
#define SB_RESULTS_SET_H

#include <stdbool.h>

struct results_set {
    char *dir;   /* what readers read, as the command was given it */
    char *real;  /* its real path (links resolved), the one swapped */
    char *next;  /* where the command writes: NULL once committed or dropped */
};

/* Claims dir (made if need be, locked for the rest of the process: a second
 * shadowbench on it fails at once), removes what killed writers left (its
 * temporaries, depth levels of folders down; their next sets beside it)
 * and opens the next set. A mount point, or a folder holding the current
 * one, is refused. Returns 0 or -1 (one line logged: nothing changed). */
int results_set_open(struct results_set *rs, const char *dir, int depth);

/* The next set in dir's place, at once, and the previous one removed.
 * Returns 0 or -1 (logged: dir is the previous set). On a filesystem that
 * cannot swap two folders (some network ones) the files are moved over one
 * by one, said in a warning; a move that fails there leaves a mix, said,
 * and the set is closed either way. */
int results_set_commit(struct results_set *rs);

/* Whether a name in a results folder is its writer's own (".", "..",
 * .lock, a temporary), not a result. */
bool results_set_own_name(const char *name);

/* Drops the next set (if still open; say: and says that dir is as it was)
 * and frees rs. */
void results_set_free(struct results_set *rs, bool say);

#endif
