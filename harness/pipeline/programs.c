#include "programs.h"
#include "base/util.h"

#include <stdlib.h>
#include <string.h>

struct receiver_programs programs_get(struct program_cache *pc, const struct technique *t, const void *settings,
                                      enum light_shape shape, bool counting)
{
    for (int i = 0; i < pc->count; i++) {
        const struct program_entry *e = &pc->entries[i];
        if (e->t == t && e->shape == shape && e->counting == counting &&
            memcmp(e->settings, settings, t->settings_size) == 0)
            return e->programs;
    }
    struct receiver_programs p;
    receiver_programs_make(t, settings, shape, counting, &p);
    if (p.receiver) {
        pc->entries = xrealloc(pc->entries, sizeof *pc->entries * (size_t)(pc->count + 1));
        pc->entries[pc->count++] = (struct program_entry){
            t, memcpy(xmalloc(t->settings_size), settings, t->settings_size), shape, counting, p};
    }
    return p;
}

void programs_free(struct program_cache *pc)
{
    for (int i = 0; i < pc->count; i++) {
        receiver_programs_delete(&pc->entries[i].programs);
        free(pc->entries[i].settings);
    }
    free(pc->entries);
    memset(pc, 0, sizeof *pc);
}
