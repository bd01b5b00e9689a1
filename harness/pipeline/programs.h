/* The receiver programs of a command, one per technique, settings (their
 * bytes) and light shape, compiled on first use: a tuned cell's settings
 * differ by scene and are often the same, and a command meets the same
 * cell on many scenes. Zero-initialise. */
#ifndef SB_PROGRAMS_H
#define SB_PROGRAMS_H

#include "gl/gl.h"
#include "scene/scene.h"
#include "techniques/technique.h"

struct program_cache {
    struct program_entry {
        const struct technique *t;
        void *settings;
        enum light_shape shape;
        GLuint program;
    } *entries;
    int count;
};

/* The program, compiled on first use (render/receiver.h); 0 after a logged
 * compile error. */
GLuint programs_get(struct program_cache *pc, const struct technique *t, const void *settings,
                    enum light_shape shape);

void programs_free(struct program_cache *pc);

#endif
