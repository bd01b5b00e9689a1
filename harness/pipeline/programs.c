#include "programs.h"
#include "base/util.h"
#include "render/receiver.h"

#include <stdlib.h>
#include <string.h>

GLuint programs_get(struct program_cache *pc, const struct technique *t, const void *settings,
                    enum light_shape shape)
{
    for (int i = 0; i < pc->count; i++) {
        const struct program_entry *e = &pc->entries[i];
        if (e->t == t && e->shape == shape && memcmp(e->settings, settings, t->settings_size) == 0)
            return e->program;
    }
    GLuint program = receiver_program(t, settings, shape);
    if (program) {
        pc->entries = xrealloc(pc->entries, sizeof *pc->entries * (size_t)(pc->count + 1));
        pc->entries[pc->count++] = (struct program_entry){
            t, memcpy(xmalloc(t->settings_size), settings, t->settings_size), shape, program};
    }
    return program;
}

void programs_free(struct program_cache *pc)
{
    for (int i = 0; i < pc->count; i++) {
        glDeleteProgram(pc->entries[i].program);
        free(pc->entries[i].settings);
    }
    free(pc->entries);
    memset(pc, 0, sizeof *pc);
}
