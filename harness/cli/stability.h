/* `shadowbench stability`: where methods fail on purpose.
 *
 * --motion: the scene moves for K frames (the light shifted by sub-texel
 * steps or turned, the camera shifted, a caster node moved), each frame ray traced (its own
 * ground truth, cached per pose) and rendered by every technique; scored
 * by flicker (score/flicker.h): how much each pixel's error changes from
 * frame to frame, against the ground truth's own frame-to-frame noise.
 * Techniques with per-pixel noise are measured with it still (as every
 * other command scores them) and animated by the frame index (Jimenez
 * 2014), each per frame and accumulated by the moving average TAA keeps.
 *
 * --vary: one thing varied over a list of values (the shadow map's size,
 * the light's size, the shadow map's depth range, or a technique
 * parameter), the error of each technique against it, and where each
 * breaks: the first value, walking away from the reference value, where it
 * meets the break rule (stability.c: STABILITY_BREAK_*).
 *
 * Writes <out>/stability.json, stability.csv, stability.html, charts/<name>.svg
 * and per scene, motion and technique the frames as two picture strips. */
#ifndef SB_STABILITY_H
#define SB_STABILITY_H

#include "run.h"

/* The break rule (also in --help, the page and the json). A value breaks a
 * technique when its V has any NaN/Inf, or against the reference value its
 * rmse is at least FACTOR times as large and RISE larger, or its leak or
 * dark fraction at least FRACTION_RISE larger. */
#define STABILITY_BREAK_RMSE_FACTOR 2.0
#define STABILITY_BREAK_RMSE_RISE 0.01
#define STABILITY_BREAK_FRACTION_RISE 0.05

/* The motions (--motion NAME[:NODE][=STEP]; NODE for caster_shift only):
 * X(ID, name, unit of the step, default step, largest |step|, what moves). */
#define STABILITY_MOTIONS(X)                                                                          \
    X(STATIC, "static", "", 0.0, 0.0, "nothing: the frames are one pose")                           \
    X(LIGHT_SHIFT, "light_shift", "shadow-map texels per frame", 0.125, 64.0,                       \
      "the light along its own x axis (a texel measured at the depth of the scene's centre)")         \
    X(LIGHT_ROTATE, "light_rotate", "degrees per frame", 0.01, 5.0,                                  \
      "the light turned about its own y axis through its centre")                                     \
    X(CAMERA_SHIFT, "camera_shift", "pixels per frame", 0.25, 64.0,                                   \
      "the camera along its own x axis (a pixel measured at the depth of the scene's centre)")      \
    X(CASTER_SHIFT, "caster_shift", "shadow-map texels per frame", 0.125, 64.0,                     \
      "a node of the scene and what is under it along the light's x axis (a texel measured at the " \
      "depth of the node's centre)")

/* What --vary takes besides T.P: X(ID, name, reference value, smallest,
 * largest, meaning). */
#define STABILITY_VARIABLES(X)                                                                        \
    X(MAP_SIZE, "shadow_map_size", NAN, SHADOWMAP_MIN_SIZE, SHADOWMAP_MAX_SIZE,                      \
      "the shadow map's side in texels (reference: --shadow-map-size)")                              \
    X(LIGHT_SCALE, "light_scale", 1.0, 1.0 / 64, 64.0,                                               \
      "the light's size times this (the ground truth follows)")                                       \
    X(DEPTH_RANGE, "depth_range", 1.0, 1.0, 1e6,                                                      \
      "the shadow map's near plane pulled towards the light to near / this: the scene's depths fill " \
      "less of the map's depth range, as with an engine's fixed small near plane")

/* The default scenes, motions and variations (no --scene, --motion, --vary);
 * "scene": each scene's own motions (extras.shadowbench.motions). */
#define STABILITY_DEFAULT_SCENES {"floating_box_sphere", "overlapping_occluders"}
#define STABILITY_DEFAULT_MOTIONS {"static", "light_shift", "light_rotate", "camera_shift", "scene"}
#define STABILITY_DEFAULT_VARIES                                                          \
    {"shadow_map_size=256,512,1024,2048,4096", "light_scale=0.25,0.5,1,2,4",              \
     "depth_range=1,10,100,1000,10000"}

int stability_main(const struct run_options *o);

#endif
