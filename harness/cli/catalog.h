/* The shipped scenes (the .gltf and .glb files in scenes/) and how a --scene argument
 * names one: a path to a glTF file, or the file stem of a shipped scene. */
#ifndef SB_CATALOG_H
#define SB_CATALOG_H

/* Sorted malloc'ed paths of the shipped scenes; returns the count, or -1
 * (logged) when the scenes folder cannot be found. */
int catalog_shipped(char ***paths);

/* The path that arg names, malloc'ed, or NULL after logging
 * "unknown scene '<arg>' (shipped: ...)". */
char *catalog_resolve(const char *arg);

void catalog_free(char **paths, int count);

#endif
