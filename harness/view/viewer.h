/* The interactive viewer (`shadowbench view`; docs/viewer.md): one scene
 * in a GLFW window, shaded by a technique's V_tech; keys switch the
 * technique, the view (shaded, V_tech, V_gt, signed error, E) and a split
 * screen of two techniques, move the light and the camera and step the
 * technique's parameters; the ground truth of each pose is ray traced on a
 * worker thread (truth/gt_worker.h), refining on screen (1, 4, 16, ...
 * samples per pixel). viewer.c keeps the state and answers keys;
 * compose.c renders a frame and makes the window's picture. */
#ifndef SB_VIEWER_H
#define SB_VIEWER_H

#include "output/picture.h"
#include "pipeline/programs.h"
#include "render/irradiance.h"
#include "render/receiver.h"
#include "render/stage_timer.h"
#include "scene/pose.h"
#include "score/metrics.h"
#include "techniques/shadowmap.h"
#include "truth/gt_worker.h"

#include <stdbool.h>

#define VIEWER_MAX_TECHNIQUES TECHNIQUE_SELECTION_MAX
#define VIEWER_LIGHT_REACH 2.0f  /* the light moves at most this many scene sizes */
#define VIEWER_DOLLY_REACH 20.0f /* the camera's distance changes at most this many times */
#define VIEWER_WHITE 2.5         /* the shaded and E views: this times the mean E over the geometry is white */
#define VIEWER_PITCH_MAX 1.4f    /* radians: the orbit stops short of the poles */

enum view_mode { MODE_SHADED, MODE_VTECH, MODE_VGT, MODE_ERROR, MODE_E, MODE_COUNT };
extern const char *const view_mode_names[MODE_COUNT];

struct viewer_desc {
    int width, height;            /* the picture */
    int gt_samples;               /* the ground truth's last level */
    int shadow_map_size;
    const struct cascade_settings *cascades;  /* the sun's (NULL: one map over the view) */
    const struct technique *techniques[VIEWER_MAX_TECHNIQUES];  /* what Tab steps through */
    const void *settings[VIEWER_MAX_TECHNIQUES];                /* their first settings (copied) */
    int technique_count;
};

struct viewer {
    struct viewer_desc d;
    void *settings[VIEWER_MAX_TECHNIQUES];  /* each technique's, as - and = step them */
    const struct scene *base;
    struct scene posed;
    int w, h;
    float extent;  /* the scene's bounding-box diagonal: the unit of motion */
    struct scene_mesh mesh;
    struct shadowmap_desc cascades_desc;  /* of the maps, made again when C and V change the settings */
    struct shadow_cascades cascades;
    struct receiver receiver;
    struct stage_timer timer;
    struct program_cache programs;

    int side[2];       /* technique indices (what Tab and B step through) of the left (and
                          only) and the right technique */
    int param;         /* the left technique's parameter that - and = step */
    enum view_mode mode;
    bool split, overlay;

    struct scene_orbit pose, shown;    /* asked for; in effect */
    unsigned pose_id;                  /* counts the poses put into effect: the ground truth's key */
    bool pose_dirty;

    float *v[2], *distance[2], *scored[2];
    float *irradiance;                 /* E of the pose in effect, -1 where no geometry */
    double mean_irradiance;            /* its mean over the geometry */
    float *shade;                      /* scratch for a view's values */
    struct stage_times times[2];       /* moving averages */
    bool timed[2];
    struct metrics m[2];
    struct gt_image gt;                /* of the current pose when gt_samples > 0 */
    int gt_samples;                    /* 0: none yet, -1: failed */
    struct gt_worker worker;

    struct irradiance_pass irradiance_pass;
    GLuint show_fbo, show_texture;
    int show_w, show_h;
    struct picture pic;

    double mouse_x, mouse_y;
    char message[200];                 /* the last refusal, shown until the next key */
    bool quit;
};

/* Opens the viewer of scene s in the current GL context (a window's).
 * Returns 0 or -1 (logged); viewer_free either way. */
int viewer_open(struct viewer *v, const struct viewer_desc *d, const struct scene *s);

/* The technique of side k (0 left, 1 right) and its settings. */
const struct technique *viewer_technique(const struct viewer *v, int k);
void *viewer_settings(const struct viewer *v, int k);

/* A key (GLFW key code and modifiers) pressed. */
void viewer_key(struct viewer *v, int key, int mods);

/* Left drag orbits the camera, right drag moves the light (window_width:
 * the window's, for the light's scale); the wheel dollies. */
void viewer_drag(struct viewer *v, float dx, float dy, bool left, bool right, int window_width);
void viewer_scroll(struct viewer *v, double amount);

/* Puts the pose asked for into effect, if it changed: the shadow map
 * refitted, the camera moved, the ground truth asked for. A pose the light
 * frustum cannot be fitted to (logged) is refused: the last stays. */
void viewer_apply_pose(struct viewer *v);

/* One frame (compose.c): the pose's newest ground truth taken (waiting
 * for its last level when wait_for_truth), each side rendered and timed,
 * the window's picture composed into v->pic. Returns 0 or -1 (logged). */
int viewer_frame(struct viewer *v, bool wait_for_truth);

/* v->pic to the current window framebuffer of fw x fh, scaled to fit and
 * centred. */
void viewer_present(struct viewer *v, int fw, int fh);

/* The window's back buffer (fw x fh: what the next swap shows) as a PNG.
 * Returns 0 or -1 (logged). */
int viewer_screenshot(int fw, int fh, const char *path);

/* The last line of the log: the technique, the view and its score. */
void viewer_summary(const struct viewer *v, char *out, size_t size);

void viewer_free(struct viewer *v);

#endif
