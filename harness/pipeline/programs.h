/* The programs of a command's cells, one set per technique, settings
 * (their bytes), light shape and variant (counting or not), compiled on
 * first use: a tuned cell's settings differ by scene and are often the
 * same, and a command meets the same cell on many scenes. Zero-initialise. */
#ifndef SB_PROGRAMS_H
#define SB_PROGRAMS_H

#include "gl/gl.h"
#include "render/receiver.h"
#include "scene/scene.h"
#include "techniques/technique.h"

#include <stdbool.h>

struct program_cache {
    struct program_entry {
        const struct technique *t;
        void *settings;
        enum light_shape shape;
        bool counting;
        struct receiver_programs programs;
    } *entries;
    int count;
};

/* The programs, compiled on first use (render/receiver.h); counting: the
 * counting variants, for scoring. After a logged compile error, .receiver
 * is 0. */
struct receiver_programs programs_get(struct program_cache *pc, const struct technique *t, const void *settings,
                                      enum light_shape shape, bool counting);

void programs_free(struct program_cache *pc);

#endif
