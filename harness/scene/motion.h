/* The motions of `shadowbench stability --motion` (docs/stability.md): a scene
 * moved a little every frame, the light shifted by sub-texel steps or
 * turned, the camera shifted, or one caster node moved. A motion is
 * NAME[:NODE][=STEP] (NODE for caster_shift only), given on the command
 * line or listed by a scene (extras.shadowbench.motions). */
#ifndef SB_MOTION_H
#define SB_MOTION_H

#include "light_frustum.h"
#include "pose.h"

#include <stdbool.h>

/* X(ID, name, unit of the step, default step, largest |step|, what moves). */
#define MOTIONS(X)                                                                                    \
    X(STATIC, "static", "", 0.0, 0.0, "nothing: the frames are one pose")                           \
    X(LIGHT_SHIFT, "light_shift", "shadow-map texels per frame", 0.125, 64.0,                       \
      "the light along its own x axis (a texel measured at the depth of the scene's centre)")         \
    X(LIGHT_ROTATE, "light_rotate", "degrees per frame", 0.01, 5.0,                                  \
      "the light turned about its own y axis through its centre")                                     \
    X(CAMERA_SHIFT, "camera_shift", "pixels per frame", 0.25, 64.0,                                   \
      "the camera along its own x axis (a pixel measured at the depth of the scene's centre)")      \
    X(CAMERA_YAW, "camera_yaw", "degrees per frame", 0.02, 5.0,                                      \
      "the camera turned about its own y axis (a sun's cascades are refitted to its view)")          \
    X(CASTER_SHIFT, "caster_shift", "shadow-map texels per frame", 0.125, 64.0,                     \
      "a node of the scene and what is under it along the light's x axis (a texel measured at the " \
      "depth of the node's centre)")

enum motion_kind {
#define X(id, name, unit, def, max, help) MOTION_##id,
    MOTIONS(X)
#undef X
    MOTION_KIND_COUNT
};

struct motion_kind_info {
    const char *name, *unit, *help;
    double def, max;  /* default step, largest |step| */
};
extern const struct motion_kind_info motion_kinds[MOTION_KIND_COUNT];

struct motion {
    enum motion_kind kind;
    double step;      /* in the kind's unit */
    char node[65];    /* caster_shift: the name of the node it moves */
    int scene, entry; /* the scene whose extras.shadowbench.motions[entry] it is, or -1: --motion */
    char name[80];    /* "light_shift", "caster_shift:sphere" */
    char label[128];  /* "light_shift=0.125", "caster_shift:sphere=0.25": its folder, each
                         character outside [A-Za-z0-9_.:=+-] as '_' */
};

/* Parses spec into m: a --motion (scene -1) or scene `scene`'s
 * extras.shadowbench.motions[entry]; `what` names it in errors. Returns 0
 * or -1 (logged). */
int motion_parse(const char *what, const char *spec, int scene, int entry, struct motion *m);

/* Whether m runs on scene index s (a --motion runs on every scene). */
bool motion_on(const struct motion *m, int s);

/* The pose of frame `frame` of m on scene s, whose light frustum is f (at
 * frame 0), its map map_size texels and its image height pixels high;
 * node: the node a caster motion moves (pose_find_node). */
struct scene_pose motion_pose(const struct motion *m, const struct scene *s, const struct light_frustum *f,
                              int map_size, int height, int node, int frame);

#endif
