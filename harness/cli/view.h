/* `shadowbench view`: the interactive viewer. One scene in a GLFW window,
 * shaded by a technique's V_tech; keys switch the technique, the view
 * (shaded, V_tech, V_gt, signed error) and a split screen of two
 * techniques, move the light and the camera and step the technique's
 * parameters; the ground truth of each pose is ray traced in the
 * background, refining on screen (1, 4, 16, ... samples per pixel).
 * --script replays key events, --screenshot writes the window as a PNG. */
#ifndef SB_VIEW_H
#define SB_VIEW_H

#include "run.h"

#define VIEW_MAX_SCRIPT 4096  /* key events in a --script file */
#define VIEW_MAX_SCRIPT_BYTES (1 << 20)
#define VIEW_MAX_FRAMES 100000000
#define VIEW_LIGHT_REACH 2.0f  /* the light moves at most this many scene sizes */
#define VIEW_DOLLY_REACH 20.0f /* the camera's distance changes at most this many times */
#define VIEW_WHITE 2.5       /* the shaded and E views: this times the mean E over the geometry is white */

int view_main(const struct run_options *o);

#endif
