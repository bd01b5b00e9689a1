/* The stability study's outputs (docs/stability.md), under its output folder:
 * stability.html (tables, charts, each motion's frames with a slider),
 * stability.csv (one row per technique x motion variant or varied value),
 * stability.json (the same, the break points, the rule), charts/<name>.svg, and
 * <scene>/<motion>/<row>/visibility_frames.png and error_frames.png (the
 * frames side by side). A new study first removes what the last one into
 * the folder listed in its stability.json, and nothing else. */
#ifndef SB_STABILITY_PAGE_H
#define SB_STABILITY_PAGE_H

#include "picture.h"
#include "pipeline/stability.h"

#include <cjson/cJSON.h>

/* A motion row's frames, in <scene>/<motion>/<row>/: V_tech, signed error. */
extern const char *const stability_frame_files[2];

struct stability_output {
    const struct stability *st;
    const char *out_dir;
    cJSON *charts;          /* the names of the charts written, for stability.json */
    struct frame_strip {    /* a row's frames side by side, while its motion runs */
        int w, ph, frames;
        uint8_t *rgb;
    } (*strips)[2];         /* by row index: V_tech, signed error */
    int strip_count;
};

/* Starts the outputs of st into out_dir: the last study's files there
 * removed. */
void stability_output_begin(struct stability_output *so, const struct stability *st, const char *out_dir);

/* st->on_frame (user: the stability_output): a frame of a row into its
 * strips. */
int stability_output_frame(void *user, const struct motion_row *row, int frame, int frames,
                           const struct scene_setup *ss, const float *v);

/* After a motion ran whole: its rows' strips written (and freed). Returns
 * 0 or -1 (logged). A motion that failed writes none: stability_output_free
 * drops them. */
int stability_output_frames(struct stability_output *so);

/* stability.html, stability.json and stability.csv, with the run record
 * (run.json's keys); on failure none of the three. Returns 0 or -1. */
int stability_output_write(struct stability_output *so, const cJSON *run);

void stability_output_free(struct stability_output *so);

#endif
