/* The shipped scenes (the .gltf and .glb files in scenes/), how a --scene
 * argument names one (a path to a glTF file, or the file stem of a shipped
 * scene), and the scenes of a command, loaded before any heavy work. */
#ifndef SB_CATALOG_H
#define SB_CATALOG_H

#include "scene.h"

/* Sorted malloc'ed paths of the shipped scenes; returns the count, or -1
 * (logged) when the scenes folder cannot be found. */
int catalog_shipped(char ***paths);

/* The path that arg names, malloc'ed, or NULL after logging
 * "unknown scene '<arg>' (shipped: ...)". */
char *catalog_resolve(const char *arg);

void catalog_free(char **paths, int count);

/* A scene's name is its file's stem and becomes <out>/<name>: it must name
 * a folder of its own there, not climb out, hide, or take one of a run's
 * own file names (reserved, NULL-terminated). Returns 0 or -1 (logged). */
int catalog_check_name(const struct scene *s, const char *const *reserved);

/* Loads the scenes that names[0..n-1] name (n = 0: every shipped scene),
 * at most max, into scenes[0..*count-1], each name checked as above, no
 * two with one name (outputs are per scene name), and each light's
 * frustum fitted (light_frustum_fit: geometry in front of the light). On
 * failure the scenes loaded so far stay counted in *count (scene_free
 * them). Returns 0 or -1 (logged). */
int catalog_load(const char *const *names, int n, const char *const *reserved, struct scene *scenes, int max,
                 int *count);

#endif
