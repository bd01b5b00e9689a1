#include "bench.h"
#include "catalog.h"
#include "gl/gl_context.h"
#include "base/log.h"
#include "techniques/params.h"
#include "render/receiver.h"
#include "gl/shader.h"
#include "render/stage_timer.h"
#include "base/util.h"

#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The probe's own descriptor: reaches the receiver pass like a technique,
 * with its tap counts as parameters. Not in the registry. */
struct probe_settings {
    int first, second;  /* taps of each group: 0 or a sample count */
};

static const char *const probe_counts[] = {"0", "16", "25", "32", "64", "100", "128", NULL};

static const struct technique_param probe_params[] = {
    {"first", "depth-map fetches per pixel, first group", offsetof(struct probe_settings, first),
     PARAM_INT, 32, 0, 128, probe_counts},
    {"second", "depth-map fetches per pixel, second group", offsetof(struct probe_settings, second),
     PARAM_INT, 32, 0, 128, probe_counts},
    {NULL},
};

static const struct technique fetch_probe = {
    .name = "fetch_probe",
    .needs = SM_DEPTH,
    .params = probe_params,
    .settings_size = sizeof(struct probe_settings),
    .shader = "fetch_probe.glsl",
};

/* The probe matching the depth fetches per pixel of a PCF-family technique
 * at these settings (its tap parameters); false for the others. */
static bool probe_for(const struct technique *t, const void *settings, struct probe_settings *p)
{
    double a = 0, b = 0;
    if (params_get(t, settings, "samples", &a) != 0 &&
        (params_get(t, settings, "blocker_samples", &a) != 0 ||
         params_get(t, settings, "filter_samples", &b) != 0))
        return false;
    *p = (struct probe_settings){(int)a, (int)b};
    return true;
}

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
    struct stage_timer timer = {.sm = &sm, .mesh = &mesh, .warmup = o->warmup, .frames = o->frames};

    printf("scene %s, %dx%d, %d^2 shadow map, median of %d frames after %d warm-up, on %s\n",
           s.name, o->width, o->height, sm.desc.size_texels, o->frames, o->warmup,
           gl_context_renderer());
    printf("%-11s %12s %12s %12s %10s  %s\n", "technique", "shadow map", "filter prep", "receiver",
           "total", "(ms)  parameters");
    double receiver_ms[RUN_MAX_TECHNIQUES];
    for (int i = 0; i < o->technique_count; i++) {
        const struct technique *t = o->techniques[i];
        void *settings = run_settings(o, t);
        struct shadowmap_request req;
        technique_request(t, settings, &sm.frustum, sm.desc.size_texels, &req);
        if (!(program = receiver_program(t, settings, s.light.shape)) || shadowmap_prepare(&sm, &req) != 0)
            goto out_free_gl;
        double sm_ms = stage_timer_products_ms(&timer, &req, SM_DEPTH);
        double prep_ms = stage_timer_products_ms(&timer, &req, SM_MOMENTS | SM_MOMENTS_SAT);
        shadowmap_require(&sm, &mesh, &req);
        receiver_ms[i] = stage_timer_receiver_ms(&timer, &rcv, program);
        glDeleteProgram(program);
        program = 0;
        struct strbuf text = {0};
        params_summary(t, settings, &text);
        printf("%-11s %12.2f %12.2f %12.2f %10.2f  %s\n", t->name, sm_ms, prep_ms, receiver_ms[i],
               sm_ms + prep_ms + receiver_ms[i], text.data ? text.data : "");
        fflush(stdout);
        strbuf_free(&text);
    }

    /* The fetch limit, at the tap count of each PCF-family technique. */
    int covered = covered_pixels(&rcv);
    printf("\nfetch limit: a receiver pass doing only N depth fetches per pixel (%d covered pixels)\n",
           covered);
    for (int i = 0; i < o->technique_count; i++) {
        struct probe_settings ps;
        if (!probe_for(o->techniques[i], run_settings(o, o->techniques[i]), &ps))
            continue;
        int taps = ps.first + ps.second;
        if (!(program = receiver_program(&fetch_probe, &ps, s.light.shape)))
            goto out_free_gl;
        double probe_ms = stage_timer_receiver_ms(&timer, &rcv, program);
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
