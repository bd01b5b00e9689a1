/* A folder of recorded results (tuned settings, baselines) rewritten as one
 * set: a reader sees the previous set or the next, never a mix, whatever
 * stops the writer (README, Outputs).
 *
 * The next set is a sibling folder, "<dir>.tmp.<pid>", that starts as a
 * copy of dir (hard links: files are only ever replaced by rename, never
 * written in place, so the two sets share nothing that changes); the
 * command writes into it, and commit swaps the two folders in one step
 * (renameat2's RENAME_EXCHANGE) and removes the previous set. A writer
 * killed before that leaves dir as it was and its next set for the next
 * writer to remove. */
#ifndef SB_RESULTS_SET_H
#define SB_RESULTS_SET_H

struct results_set {
    char *dir;   /* what readers read */
    char *next;  /* where the command writes: NULL once committed or dropped */
};

/* Claims dir (made if need be, locked for the rest of the process: a second
 * shadowbench on it fails at once), removes what killed writers left (its
 * temporaries, depth levels of folders down; their next sets beside it)
 * and opens the next set. Returns 0 or -1 (one line logged: nothing
 * changed). */
int results_set_open(struct results_set *rs, const char *dir, int depth);

/* The next set in dir's place, at once, and the previous one removed. On a
 * filesystem that cannot swap two folders (some network ones), the files
 * are moved over one by one, said in a warning. Returns 0 or -1 (logged:
 * dir is the previous set). */
int results_set_commit(struct results_set *rs);

/* Drops the next set (if still open) and frees rs: dir stays as it was. */
void results_set_free(struct results_set *rs);

#endif
