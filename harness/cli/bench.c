#include "bench.h"
#include "catalog.h"
#include "base/log.h"
#include "base/util.h"
#include "gl/gl_context.h"
#include "gl/shader.h"
#include "render/receiver.h"
#include "render/stage_timer.h"
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
     offsetof(struct probe_settings, first_taps), PARAM_INT, 0, 0, 0, NULL},
    {"second_taps", "depth-map fetches per pixel, second loop",
     offsetof(struct probe_settings, second_taps), PARAM_INT, 0, 0, 0, NULL},
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

int bench_main(const struct run_options *o)
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

    int status = EXIT_CHECK_FAILED;
    struct scene_mesh mesh = {0};
    struct shadowmap sm = {0};
    struct receiver rcv = {0};
    GLuint program = 0;
    if (gl_context_create() != 0)
        goto out_free_scene;
    if (shader_init(o->shader_dir) != 0 ||
        shadowmap_create(&sm, &s, &(struct shadowmap_desc){.size_texels = o->shadow_map_size}) != 0 ||
        receiver_create(&rcv, &s, o->width, o->height) != 0)
        goto out_free_gl;
    scene_mesh_upload(&s, &mesh);
    struct stage_timer timer = {.sm = &sm, .mesh = &mesh, .receiver = &rcv, .warmup = o->warmup,
                                .frames = o->frames};

    printf("scene %s, %dx%d, %d^2 shadow map, median of %d frames after %d warm-up, on %s\n",
           s.name, o->width, o->height, sm.desc.size_texels, o->frames, o->warmup,
           gl_context_renderer());
    printf("%-11s %12s %12s %12s %10s  %s\n", "technique", "shadow map", "filter prep", "receiver",
           "total", "(ms)  parameters");
    double receiver_ms[RUN_MAX_TECHNIQUES];
    for (int i = 0; i < o->technique_count; i++) {
        const struct technique *t = o->techniques[i];
        void *settings = run_settings(o, t);
        struct stage_times times;
        if (!(program = receiver_program(t, settings, s.light.shape)) ||
            stage_timer_cell(&timer, t, settings, program, &times) != 0)
            goto out_free_gl;
        glDeleteProgram(program);
        program = 0;
        receiver_ms[i] = times.receiver_ms;
        struct strbuf text = {0};
        params_summary(t, settings, &text);
        printf("%-11s %12.2f %12.2f %12.2f %10.2f  %s\n", t->name, times.shadowmap_ms,
               times.filter_prep_ms, times.receiver_ms, times.total_ms, text.data ? text.data : "");
        fflush(stdout);
        strbuf_free(&text);
    }

    /* The fetch limit, at the tap loops (PARAM_TAPS) of each technique that has any. */
    int covered = covered_pixels(&rcv);
    bool heading = false;
    for (int i = 0; i < o->technique_count; i++) {
        int loops[2] = {0, 0};
        int n = params_taps(o->techniques[i], run_settings(o, o->techniques[i]), loops, 2);
        if (n == 0)
            continue;
        if (!heading)
            printf("\nfetch limit: a receiver pass doing only N depth fetches per pixel (%d covered "
                   "pixels)\n", covered);
        heading = true;
        if (n > 2)
            log_warn("%s: %d tap loops; the fetch probe counts the first two", o->techniques[i]->name, n);
        struct probe_settings ps = {loops[0], loops[1]};
        int taps = ps.first_taps + ps.second_taps;
        if (!(program = receiver_program(&fetch_probe, &ps, s.light.shape)))
            goto out_free_gl;
        double probe_ms = stage_timer_receiver_ms(&timer, program);
        glDeleteProgram(program);
        program = 0;
        printf("  %-10s %3d fetches: probe %.2f ms (%.2f G fetches/s); %s receiver %.2f ms = %.2fx "
               "the probe\n", o->techniques[i]->name, taps, probe_ms,
               (double)covered * taps / (probe_ms * 1e6), o->techniques[i]->name, receiver_ms[i],
               receiver_ms[i] / probe_ms);
    }
    status = EXIT_OK;

out_free_gl:
    if (program)
        glDeleteProgram(program);
    receiver_destroy(&rcv);
    shadowmap_destroy(&sm);
    scene_mesh_destroy(&mesh);
    gl_context_destroy();
out_free_scene:
    scene_free(&s);
    return status;
}
