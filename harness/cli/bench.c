#include "cli.h"
#include "base/log.h"
#include "base/util.h"
#include "gl/gl_context.h"
#include "gl/shader.h"
#include "render/receiver.h"
#include "render/stage_timer.h"
#include "scene/catalog.h"
#include "scene/light_frustum.h"
#include "techniques/params.h"

#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The probe's own descriptor: reaches the receiver pass like a technique,
 * its two tap loops as parameters (set from a technique's PARAM_TAPS values,
 * never parsed). Not in the registry. */
struct probe_settings {
    int first_taps, second_taps;  /* 0 or a tap count */
};

static const struct technique_param probe_params[] = {
    {"first_taps", "depth-map fetches per pixel, first loop",
     offsetof(struct probe_settings, first_taps), PARAM_INT, 0, 0, 0, NULL, NULL},
    {"second_taps", "depth-map fetches per pixel, second loop",
     offsetof(struct probe_settings, second_taps), PARAM_INT, 0, 0, 0, NULL, NULL},
    {NULL},
};

static const struct technique fetch_probe = {
    .name = "fetch_probe",
    .needs = SM_DEPTH,
    .params = probe_params,
    .settings_size = sizeof(struct probe_settings),
    .shader = "fetch_probe.glsl",
};

static int covered_pixels(const struct receiver *rc)
{
    size_t n = (size_t)rc->width * (size_t)rc->height;
    float *v = xmalloc(sizeof(float) * n), *distance = xmalloc(sizeof(float) * n);
    receiver_read(rc, v, distance);
    int covered = 0;
    for (size_t i = 0; i < n; i++)
        covered += distance[i] >= 0.0f;
    free(v);
    free(distance);
    return covered;
}

int bench_main(const struct options *o)
{
    char *path = NULL;
    if (o->scene_count) {
        path = catalog_resolve(o->scenes[0]);
    } else {
        char **paths;
        int n = catalog_shipped(&paths);
        if (n > 0)
            path = xstrdup(paths[0]);
        if (n >= 0)
            catalog_free(paths, n);
        if (n == 0)
            log_error("no shipped scenes found");
    }
    struct scene s;
    int rc = path ? scene_load(path, &s) : -1;
    free(path);
    if (rc != 0)
        return EXIT_USAGE;

    /* Bad input before any GL, with run's exit status: a light that sees
     * no geometry, a --shaders folder that is not one. */
    int status = EXIT_USAGE;
    struct scene_mesh mesh = {0};
    struct shadow_cascades cascades = {0};
    struct receiver rcv = {0};
    struct light_frustum f;
    if (light_frustum_fit(&s, (float)o->width / (float)o->height, &f) != 0 || cli_gl_open(o, o->gl) != 0)
        goto out_free_scene;
    status = EXIT_CHECK_FAILED;
    if (shadow_cascades_create(&cascades, &s,
                               &(struct shadowmap_desc){.size_texels = o->shadow_map_size,
                                                        .aspect = (float)o->width / (float)o->height},
                               &o->cascades) != 0 ||
        receiver_create(&rcv, &s, o->width, o->height) != 0)
        goto out_free_gl;
    scene_mesh_upload(&s, &mesh);
    struct stage_timer timer = {.cascades = &cascades, .mesh = &mesh, .receiver = &rcv, .warmup = o->warmup,
                                .frames = o->frames, .timing = o->timing};

    /* The cells: every technique, then a fetch probe at the tap loops
     * (PARAM_TAPS) of each technique that has any; all timed interleaved. */
    const int n = o->technique_count;
    struct stage_timer_cell cells[2 * CLI_MAX_TECHNIQUES] = {{0}};
    struct probe_settings probes[CLI_MAX_TECHNIQUES];
    int probe_of[CLI_MAX_TECHNIQUES], cell_count = n;  /* probe_of[i]: cell index or -1 */
    for (int i = 0; i < n; i++) {
        const struct technique *t = o->techniques[i];
        cells[i] = (struct stage_timer_cell){t, cli_settings(o, t), {0}};
        int loops[2] = {0, 0}, taps = params_taps(t, cells[i].settings, loops, 2);
        if (taps > 2)
            log_warn("%s: %d tap loops; the fetch probe counts the first two", t->name, taps);
        probe_of[i] = taps ? cell_count : -1;
        if (taps) {
            probes[i] = (struct probe_settings){loops[0], loops[1]};
            cells[cell_count++] = (struct stage_timer_cell){&fetch_probe, &probes[i], {0}};
        }
    }
    struct stage_times times[2 * CLI_MAX_TECHNIQUES];
    for (int i = 0; i < cell_count; i++) {
        receiver_programs_make(cells[i].technique, cells[i].settings, s.light.shape, false, &cells[i].programs);
        if (!cells[i].programs.receiver)
            goto out_free_programs;
    }
    printf("scene %s, %dx%d, %d^2 shadow map, median of %d frames after %d warm-up, interleaved, on %s (%s, %s), "
           "timed by %s\n", s.name, o->width, o->height, o->shadow_map_size, o->frames, o->warmup,
           gl_context_renderer(), gl_context_vendor(), gl_context_platform(), stage_timing_text(o->timing));
    if (stage_timer_run(&timer, cells, cell_count, times) != 0)
        goto out_free_programs;

    printf("%-11s %12s %12s %12s %12s %10s %15s  %s\n", "technique", "shadow map", "filter prep",
           "receiver", "mask+denoise", "total", "total q1-q3", "(ms)  parameters");
    for (int i = 0; i < n; i++) {
        struct strbuf text = {0};
        params_summary(cells[i].technique, cells[i].settings, &text);
        printf("%-11s %12.2f %12.2f %12.2f %12.2f %10.2f %7.2f-%-7.2f  %s\n", cells[i].technique->name,
               times[i].shadowmap_ms, times[i].filter_prep_ms, times[i].receiver_ms,
               times[i].mask_ms + times[i].denoise_ms,
               times[i].total_ms, times[i].total_q1_ms, times[i].total_q3_ms,
               text.data ? text.data : "");
        strbuf_free(&text);
    }

    int covered = covered_pixels(&rcv);
    bool heading = false;
    for (int i = 0; i < n; i++) {
        if (probe_of[i] < 0)
            continue;
        if (!heading)
            printf("\nfetch limit: a receiver pass doing only N depth fetches per pixel (%d covered "
                   "pixels)\n", covered);
        heading = true;
        int taps = probes[i].first_taps + probes[i].second_taps;
        double probe_ms = times[probe_of[i]].receiver_ms, receiver_ms = times[i].receiver_ms;
        printf("  %-10s %3d fetches: probe %.2f ms (%.2f G fetches/s); %s receiver %.2f ms = %.2fx "
               "the probe\n", cells[i].technique->name, taps, probe_ms,
               (double)covered * taps / (probe_ms * 1e6), cells[i].technique->name, receiver_ms,
               receiver_ms / probe_ms);
    }
    status = EXIT_OK;

out_free_programs:
    for (int i = 0; i < cell_count; i++)
        receiver_programs_delete(&cells[i].programs);
out_free_gl:
    receiver_destroy(&rcv);
    shadow_cascades_destroy(&cascades);
    scene_mesh_destroy(&mesh);
    gl_context_destroy();
out_free_scene:
    scene_free(&s);
    return status;
}
