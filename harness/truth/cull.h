/* Which geometry can hide the light from a shadow-ray origin, found
 * exactly, so that the ground truth decides most light samples without a
 * ray (docs/design.md §6: V_gt is the ray-traced answer; this only skips rays
 * whose answer is certain).
 *
 * From an origin o every light sample lies in the pyramid with apex o over
 * the light (the rect, or the square round the disk), above o's tangent
 * plane. cull_occluders finds the triangles that can meet that pyramid and
 * hands them back as convex planar patches (a triangle, or a plate's or a
 * box face's quad): none means every sample reaches o; a few means a
 * sample's segment is blocked exactly when it crosses one of them, which
 * costs a few dot products instead of a ray. Every decision keeps a margin
 * (a distance well above float rounding): a sample closer than that to a
 * patch's plane or edge is left undecided and traced. */
#ifndef SB_CULL_H
#define SB_CULL_H

#include "scene/scene.h"

#include <embree3/rtcore.h>

#define CULL_MAX_OCCLUDERS 8

/* An Embree error code in words ("out of memory" for RTC_ERROR_OUT_OF_MEMORY). */
const char *cull_embree_error_text(enum RTCError code);

/* A patch set up for segments from o. The segment to a light point q
 * crosses the patch's plane where s(q) = n.q - d has the sign opposite to
 * so = s(o), at t = so / (so - s(q)), and crosses it inside the patch
 * where t * edge[k].(q - o) > 0 for every k: edge[k] are the unit normals
 * of the planes through o and the patch's edges, pointing inwards (a
 * triangle repeats its last edge). t * edge[k].(q - o) is the crossing's
 * distance from that plane, hence at most its distance from the edge. */
struct cull_occluder {
    struct vec3 n;
    float d, so;
    struct vec3 edge[4];
};

struct cull;

/* NULL on failure (logged). */
struct cull *cull_build(RTCDevice dev, const struct scene *s);
void cull_free(struct cull *c);

/* The patches that can block a light sample seen from o above the tangent
 * plane through o with normal n: their count, 0 when nothing can (every
 * sample reaches o). -1 (trace every sample) when o is behind the light or
 * within the margin of its plane, there are more than CULL_MAX_OCCLUDERS, a
 * patch cannot be set up exactly (o within the margin of its plane, a
 * degenerate triangle), or the search took more than a bounded amount of
 * work (about a few of o's rays). */
int cull_occluders(const struct cull *c, struct vec3 o, struct vec3 n,
                   struct cull_occluder out[CULL_MAX_OCCLUDERS]);

/* Decisions closer than this (world units) to a plane are undecided. */
float cull_margin(const struct cull *c);

#endif
