/* The unshadowed irradiance pass: E, the area light's irradiance at each
 * pixel's surface point in closed form (shaders/view_shading.frag), for a
 * light of unit radiance; the ground truth's E (truth/groundtruth.h) is the
 * same quantity, sampled. The viewer shades with E x V. */
#ifndef SB_IRRADIANCE_H
#define SB_IRRADIANCE_H

#include "receiver.h"

struct irradiance_pass {
    int width, height;
    GLuint program, fbo, target, depth;
};

/* For lights of the shape of s's, at width x height. Returns 0 or -1
 * (logged); irradiance_destroy either way. */
int irradiance_create(struct irradiance_pass *p, const struct scene *s, int width, int height);

/* E of scene s seen through r's camera into out (width x height, top row
 * first, -1 where no geometry); returns its mean over the geometry (0 for
 * none). */
double irradiance_render(const struct irradiance_pass *p, const struct scene *s, const struct receiver *r,
                         const struct scene_mesh *mesh, float *out);

void irradiance_destroy(struct irradiance_pass *p);

#endif
