#include "motion.h"
#include "base/log.h"
#include "base/util.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const struct motion_kind_info motion_kinds[MOTION_KIND_COUNT] = {
#define X(id, name, unit, def, max, help) {name, unit, help, def, max},
    MOTIONS(X)
#undef X
};

int motion_parse(const char *what, const char *spec, int scene, int entry, struct motion *m)
{
    memset(m, 0, sizeof *m);
    m->scene = scene, m->entry = entry;
    const char *colon = strchr(spec, ':'), *eq = strrchr(spec, '=');
    if (eq && colon && eq < colon)  /* NAME=...:... : the ':' is the step's */
        colon = NULL;
    const size_t len = colon ? (size_t)(colon - spec) : eq ? (size_t)(eq - spec) : strlen(spec);
    int k = 0;
    while (k < MOTION_KIND_COUNT && !(strlen(motion_kinds[k].name) == len && !strncmp(spec, motion_kinds[k].name, len)))
        k++;
    if (k == MOTION_KIND_COUNT) {
        struct strbuf known = {0};
        for (int i = 0; i < MOTION_KIND_COUNT; i++)
            strbuf_list_printf(&known, ", ", "%s", motion_kinds[i].name);
        log_error("%s: '%s' is not a motion (motions: %s; see --help)", what, spec, known.data);
        strbuf_free(&known);
        return -1;
    }
    m->kind = (enum motion_kind)k;
    m->step = motion_kinds[k].def;
    if ((k == MOTION_CASTER_SHIFT) != (colon != NULL)) {
        log_error("%s: '%s': %s", what, spec, colon ? "only caster_shift names a node (NAME:NODE)"
                                                    : "caster_shift names the node it moves: caster_shift:NODE[=STEP]");
        return -1;
    }
    if (colon) {
        const size_t n = (eq ? (size_t)(eq - colon) : strlen(colon)) - 1;
        if (n == 0 || n >= sizeof m->node) {
            log_error("%s: '%s': a node's name is 1 to %zu bytes", what, spec, sizeof m->node - 1);
            return -1;
        }
        memcpy(m->node, colon + 1, n);
    }
    if (eq && k == MOTION_STATIC) {
        log_error("%s: '%s': static takes no step", what, spec);
        return -1;
    }
    if (eq && util_parse_finite(what, eq + 1, &m->step) != 0)
        return -1;
    if (k != MOTION_STATIC && !(m->step != 0 && fabs(m->step) <= motion_kinds[k].max)) {
        log_error("%s: '%s': the step must be non-zero and at most %g %s in size", what, spec, motion_kinds[k].max,
                  motion_kinds[k].unit);
        return -1;
    }
    snprintf(m->name, sizeof m->name, "%s%s%s", motion_kinds[k].name, colon ? ":" : "", m->node);
    if (k == MOTION_STATIC)
        snprintf(m->label, sizeof m->label, "static");
    else
        snprintf(m->label, sizeof m->label, "%s=%g", m->name, m->step);
    for (char *c = m->label; *c; c++)  /* the label is a folder's name */
        if (!(isalnum((unsigned char)*c) || strchr("_.:=+-", *c)))
            *c = '_';
    return 0;
}

bool motion_on(const struct motion *m, int s) { return m->scene < 0 || m->scene == s; }

struct scene_pose motion_pose(const struct motion *m, const struct scene *s, const struct light_frustum *f,
                              int map_size, int height, int node, int frame)
{
    struct scene_pose p = {0};
    const double amount = m->step * frame;
    switch (m->kind) {
    case MOTION_STATIC: break;
    case MOTION_LIGHT_SHIFT:
        p.light_shift = (float)amount * light_frustum_texel_world(f, map_size, pose_light_depth_of_centre(s));
        break;
    case MOTION_LIGHT_ROTATE: p.light_turn_rad = (float)(amount * M_PI / 180); break;
    case MOTION_CAMERA_SHIFT: p.camera_shift = (float)amount * pose_pixel_world(s, height); break;
    case MOTION_CAMERA_YAW: p.camera_yaw_rad = (float)(amount * M_PI / 180); break;
    case MOTION_CASTER_SHIFT:
        p.caster = node + 1;
        p.caster_shift = (float)amount * light_frustum_texel_world(f, map_size, pose_light_depth_of_node(s, node));
        break;
    case MOTION_KIND_COUNT: break;
    }
    return p;
}
