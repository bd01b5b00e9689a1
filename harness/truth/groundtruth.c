/* Ground truth with Embree 3 (docs/design.md §6).
 *
 * Primary rays through pixel centres; at the hit p, geometric normal n
 * flipped towards the camera; N = n*n stratified light samples, jittered per
 * pixel (every pixel draws its own jitter in every stratum, so the pattern is
 * scrambled per pixel). A sample is above the horizon when it lies in front
 * of the one-sided light and above p's tangent plane; H counts those, V is
 * the share of them that the shadow ray from p + eps*n reaches unblocked.
 * The sun's samples are directions in its cone, its rays unbounded.
 *
 * Noise floor without a second trace: the strata split into two halves in
 * a checkerboard, each a stratified estimate on its own with independent
 * jitter. V is their average (weighted by their samples above), so the
 * halves' difference, scaled, is a sample of V's error (see noise below).
 *
 * Speed: most samples need no ray. Per pixel, cull.h finds the few planar
 * patches that can hide the light (none on most lit pixels, a plate in a
 * plate's penumbra and umbra), and a sample is decided by whether its
 * segment crosses one; only samples that no patch decides with a margin,
 * and every sample of pixels with too much geometry in the way (the
 * bunny's), are traced. The pixels are the same as with every sample
 * traced (gt_desc.trace_all; test_groundtruth compares the two). Traced
 * rays go in packets of 16 (rtcOccluded16) over 4x4 pixel tiles; the 16
 * pixels of a tile visit the same stratum together, so their rays are
 * coherent. */
#include "groundtruth.h"
#include "base/image.h"
#include "base/log.h"
#include "base/util.h"
#include "cull.h"

#include <embree3/rtcore.h>

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <float.h>
#include <math.h>
#include <omp.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <unistd.h>

#define TILE 4

static void desc_defaults(struct gt_desc *d)
{
    if (!d->samples)
        d->samples = GT_DEFAULT_SAMPLES;
    if (!d->seed)
        d->seed = 1;
}

/* An integer hash (lowbias32): decorrelated streams per pixel and seed,
 * stateless, so the stratum loop vectorises across the 16 lanes of a packet. */
static uint32_t hash32(uint32_t x)
{
    x ^= x >> 16;
    x *= 0x7feb352dU;
    x ^= x >> 15;
    x *= 0x846ca68bU;
    x ^= x >> 16;
    return x;
}

/* sin and cos on [-pi/4, pi/4] by their Taylor series to a^9 and a^8
 * (truncation below 3e-8, under float rounding): branch-free, so the lane
 * loops below vectorise, which libm's sinf and cosf do not. */
static inline float sin_quarter(float a)
{
    float a2 = a * a;
    return a * (1.0f + a2 * (-1.0f / 6 + a2 * (1.0f / 120 + a2 * (-1.0f / 5040 + a2 * (1.0f / 362880)))));
}

static inline float cos_quarter(float a)
{
    float a2 = a * a;
    return 1.0f + a2 * (-0.5f + a2 * (1.0f / 24 + a2 * (-1.0f / 720 + a2 * (1.0f / 40320))));
}

/* Uniform points on the light for 16 unit-square samples; for the sun,
 * unit directions uniform in its cone's solid angle (cap = 1 - cos alpha).
 * The disk and the cone use the concentric map (Shirley & Chiu 1997), which
 * keeps strata compact: the larger of |x|, |y| is the radius, the angle is
 * pi/4 times their ratio from the nearer axis. The cone takes the disk's
 * point (a, b), radius r, to cos(theta) = 1 - r^2 cap, which is uniform in
 * solid angle, and its sine r sqrt(cap (2 - r^2 cap)) along (a, b) / r. */
/* Inlined, so it is built for the caller's target (trace_tile's clones). */
static inline __attribute__((always_inline)) void
light_points(const struct scene_light *L, float cap, const float *u, const float *v, float *qx, float *qy,
             float *qz)
{
    float a[16], b[16];
    if (L->shape == LIGHT_RECT) {
#pragma omp simd
        for (int i = 0; i < 16; i++) {
            a[i] = (u[i] - 0.5f) * L->width;
            b[i] = (v[i] - 0.5f) * L->height;
        }
    } else {
        const float radius = L->shape == LIGHT_SUN ? 1.0f : L->radius;
#pragma omp simd
        for (int i = 0; i < 16; i++) {
            float x = 2.0f * u[i] - 1.0f, y = 2.0f * v[i] - 1.0f;
            int x_major = fabsf(x) > fabsf(y);
            float r = x_major ? x : y, minor = x_major ? y : x;
            float angle = r != 0.0f ? (float)M_PI_4 * (minor / r) : 0.0f;
            float c = cos_quarter(angle), s = sin_quarter(angle);
            a[i] = radius * r * (x_major ? c : s);
            b[i] = radius * r * (x_major ? s : c);
        }
    }
    const struct vec3 p = L->pos, x = L->x, y = L->y, z = L->z;
    if (L->shape == LIGHT_SUN) {
#pragma omp simd
        for (int i = 0; i < 16; i++) {
            const float c = (a[i] * a[i] + b[i] * b[i]) * cap, sin_r = sqrtf(cap * (2.0f - c));
            qx[i] = z.x * (1.0f - c) + (x.x * a[i] + y.x * b[i]) * sin_r;
            qy[i] = z.y * (1.0f - c) + (x.y * a[i] + y.y * b[i]) * sin_r;
            qz[i] = z.z * (1.0f - c) + (x.z * a[i] + y.z * b[i]) * sin_r;
        }
        return;
    }
#pragma omp simd
    for (int i = 0; i < 16; i++) {
        qx[i] = p.x + x.x * a[i] + y.x * b[i];
        qy[i] = p.y + x.y * a[i] + y.y * b[i];
        qz[i] = p.z + x.z * a[i] + y.z * b[i];
    }
}

static void on_embree_error(void *user, enum RTCError code, const char *what)
{
    (void)user;
    log_error("Embree: %s: %s", cull_embree_error_text(code), what ? what : "");
}

/* One Embree device per process, its error callback installed once
 * (STYLE.md item 10): made on first use, released by gt_shutdown(). */
static RTCDevice device;

static RTCDevice embree_device(void)
{
    if (device)
        return device;
    device = rtcNewDevice(NULL);
    if (!device)
        log_error("Embree: cannot create a device: %s", cull_embree_error_text(rtcGetDeviceError(NULL)));
    else
        rtcSetDeviceErrorFunction(device, on_embree_error, NULL);
    return device;
}

void gt_shutdown(void)
{
    if (device)
        rtcReleaseDevice(device);
    device = NULL;
}

/* Per lane (the inner index), the occluders of cull.h, structure of arrays. */
struct lane_occluders {
    float nx[CULL_MAX_OCCLUDERS][16], ny[CULL_MAX_OCCLUDERS][16], nz[CULL_MAX_OCCLUDERS][16];
    float d[CULL_MAX_OCCLUDERS][16], so[CULL_MAX_OCCLUDERS][16], inv_so[CULL_MAX_OCCLUDERS][16];
    float ex[4][CULL_MAX_OCCLUDERS][16], ey[4][CULL_MAX_OCCLUDERS][16], ez[4][CULL_MAX_OCCLUDERS][16];
};

struct tracer {
    const struct scene *scene;
    const struct light_frustum *frustum;
    struct gt_desc desc;
    RTCScene rtc;
    struct cull *cull;
    float eps;
    int strata;  /* n, with N = n * n */
};

/* Camera ray through the centre of pixel (x, y), y = 0 the top row. The
 * direction is unnormalised with unit depth along the view axis, so t is
 * view depth and tnear = znear matches GL's near-plane clipping. */
static struct vec3 camera_dir(const struct scene_camera *c, int x, int y, int w, int h)
{
    float t = tanf(0.5f * c->yfov_rad), aspect = (float)w / (float)h;
    float sx = (2.0f * ((float)x + 0.5f) / (float)w - 1.0f) * t * aspect;
    float sy = (1.0f - 2.0f * ((float)y + 0.5f) / (float)h) * t;
    return v3_add(v3_add(v3_scale(c->x, sx), v3_scale(c->y, sy)), v3_scale(c->z, -1.0f));
}

/* Built twice, for AVX2 and for the baseline, and picked at load time: the
 * lane loops run 8 floats wide where the CPU can. */
__attribute__((target_clones("avx2", "default")))
/* Returns the shadow rays traced; *samples: the light samples resolved
 * (above the horizon of a live pixel), traced or decided without a ray. */
static long long trace_tile(const struct tracer *tr, int tx, int ty, struct gt_image *out,
                           long long *samples)
{
    const struct scene_camera *cam = &tr->scene->camera;
    const struct scene_light *L = &tr->scene->light;
    const int w = tr->desc.width, h = tr->desc.height;
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;

    struct RTCRayHit16 prim;
    _Alignas(64) int valid[16];  /* Embree loads packet masks with aligned 16-wide loads */
    int pixel[16];
    for (int i = 0; i < 16; i++) {
        int x = tx + i % TILE, y = ty + i / TILE;
        valid[i] = x < w && y < h ? -1 : 0;
        pixel[i] = valid[i] ? y * w + x : -1;
        struct vec3 d = valid[i] ? camera_dir(cam, x, y, w, h) : v3(0, 0, -1);
        prim.ray.org_x[i] = cam->pos.x, prim.ray.org_y[i] = cam->pos.y, prim.ray.org_z[i] = cam->pos.z;
        prim.ray.dir_x[i] = d.x, prim.ray.dir_y[i] = d.y, prim.ray.dir_z[i] = d.z;
        prim.ray.tnear[i] = cam->znear;
        prim.ray.tfar[i] = INFINITY;
        prim.ray.time[i] = 0.0f;
        prim.ray.mask[i] = 0xffffffffu;
        prim.ray.id[i] = (unsigned)i;
        prim.ray.flags[i] = 0;
        prim.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
    }
    rtcIntersect16(valid, tr->rtc, &ctx, &prim);

    /* Per-lane constants of the packet, structure-of-arrays. */
    float ox[16], oy[16], oz[16], nx[16], ny[16], nz[16];
    uint32_t lane_seed[16];
    int live[16];
    struct RTCRay16 ray;
    for (int i = 0; i < 16; i++) {
        live[i] = valid[i] && prim.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID;
        ox[i] = oy[i] = oz[i] = nx[i] = ny[i] = nz[i] = 0.0f;
        lane_seed[i] = 0;
        if (valid[i]) {
            out->distance[pixel[i]] = -1.0f;
            int j = pixel[i];
            out->v[j] = out->v_weighted[j] = out->h[j] = out->e[j] = out->noise[j] = out->mask[j] = 0.0f;
        }
        if (live[i]) {
            struct vec3 d = v3(prim.ray.dir_x[i], prim.ray.dir_y[i], prim.ray.dir_z[i]);
            struct vec3 p = v3_add(cam->pos, v3_scale(d, prim.ray.tfar[i]));
            struct vec3 n = v3_normalize(v3(prim.hit.Ng_x[i], prim.hit.Ng_y[i], prim.hit.Ng_z[i]));
            if (v3_dot(n, d) > 0.0f)
                n = v3_scale(n, -1.0f);
            out->distance[pixel[i]] = prim.ray.tfar[i] * v3_length(d);
            struct vec3 o = v3_add(p, v3_scale(n, tr->eps));
            ox[i] = o.x, oy[i] = o.y, oz[i] = o.z;
            nx[i] = n.x, ny[i] = n.y, nz[i] = n.z;
            lane_seed[i] = hash32((uint32_t)pixel[i] ^ hash32(tr->desc.seed));
            live[i] = light_frustum_inside(tr->frustum, p);
        }
        /* Fields that stay the same for every stratum. */
        ray.org_x[i] = ox[i], ray.org_y[i] = oy[i], ray.org_z[i] = oz[i];
        ray.tnear[i] = 0.0f;
        ray.time[i] = 0.0f;
        ray.mask[i] = 0xffffffffu;
        ray.id[i] = (unsigned)i;
        ray.flags[i] = 0;
    }

    /* Per lane, the patches that can block its samples (cull.h), as
     * structure of arrays; a lane short of the tile's most gets patches
     * that never cross a segment (every sample on their positive side). */
    struct lane_occluders occ;
    int slots = 0, known[16];
    for (int i = 0; i < 16; i++) {
        struct cull_occluder o[CULL_MAX_OCCLUDERS];
        const int count = live[i] && tr->cull && !tr->desc.trace_all
                              ? cull_occluders(tr->cull, v3(ox[i], oy[i], oz[i]), v3(nx[i], ny[i], nz[i]), o)
                              : -1;
        known[i] = count >= 0;  /* its occluders are known: samples can be decided */
        for (int j = 0; j < CULL_MAX_OCCLUDERS; j++) {
            const bool real = j < count;
            occ.nx[j][i] = real ? o[j].n.x : 0.0f, occ.ny[j][i] = real ? o[j].n.y : 0.0f;
            occ.nz[j][i] = real ? o[j].n.z : 0.0f, occ.d[j][i] = real ? o[j].d : -FLT_MAX;
            occ.so[j][i] = real ? o[j].so : 1.0f, occ.inv_so[j][i] = real ? 1.0f / o[j].so : 1.0f;
            for (int k = 0; k < 4; k++) {
                occ.ex[k][j][i] = real ? o[j].edge[k].x : 0.0f;
                occ.ey[k][j][i] = real ? o[j].edge[k].y : 0.0f;
                occ.ez[k][j][i] = real ? o[j].edge[k].z : 0.0f;
            }
        }
        slots = count > slots ? count : slots;
    }
    const float margin = tr->cull ? cull_margin(tr->cull) : 0.0f;
    /* The sun: samples are directions, rays go to infinity, the weight is
     * cos(theta_p) alone (its radiance arrives from a solid angle). */
    const int sun = L->shape == LIGHT_SUN;
    const float cap = sun ? (float)light_sun_cap(L->half_angle) : 0.0f;

    const int n = tr->strata;
    const float inv_n = 1.0f / (float)n;
    /* Locals, not L->z: the compiler cannot prove L does not alias `ray`
     * (whose address goes to Embree), and would not vectorise. */
    const float lzx = L->z.x, lzy = L->z.y, lzz = L->z.z;
    /* Per lane: samples above the horizon and unblocked ones, in all and in
     * the checkerboard half A; the cos cos / r^2 weights of both. */
    int above[16] = {0}, visible[16] = {0}, above_a[16] = {0}, visible_a[16] = {0}, decided[16], open[16];
    float weight_vis[16] = {0}, weight_all[16] = {0};
    long long rays = 0;
    for (int k = 0; k < n * n; k++) {
        const int su = k % n, sv = k / n, half_a = !((su + sv) & 1);
        float u[16], v[16], qx[16], qy[16], qz[16], w_sample[16];
        _Alignas(64) int active[16];
        /* Branch-free passes over the lanes, so the compiler vectorises them. */
#pragma omp simd
        for (int i = 0; i < 16; i++) {
            /* One hash, 16 bits of jitter per axis: 1/65536 of a stratum. */
            uint32_t h = hash32(lane_seed[i] + (uint32_t)k * 0x9e3779b9u);
            u[i] = ((float)su + (float)(h >> 16) * (1.0f / 65536.0f)) * inv_n;
            v[i] = ((float)sv + (float)(h & 0xffffu) * (1.0f / 65536.0f)) * inv_n;
        }
        light_points(L, cap, u, v, qx, qy, qz);
        /* The patches' verdict on each lane's segment (cull.h): blocked when
         * it crosses one inside; open when it misses them all; else traced. */
        int blocked[16] = {0}, unsure[16] = {0};
        for (int j = 0; j < slots; j++) {
#pragma omp simd
            for (int i = 0; i < 16; i++) {
                float dx = qx[i] - ox[i], dy = qy[i] - oy[i], dz = qz[i] - oz[i];
                float sq = occ.nx[j][i] * qx[i] + occ.ny[j][i] * qy[i] + occ.nz[j][i] * qz[i] - occ.d[j][i];
                float so = occ.so[j][i];
                int across = (so > 0.0f ? sq < -margin : sq > margin);
                int on_plane = fabsf(sq) <= margin;
                /* t e > margin  <=>  e > margin / t, 1 / t = 1 - sq / so */
                float limit = margin * (1.0f - sq * occ.inv_so[j][i]);
                int inside = 1, outside = 0;
                for (int k = 0; k < 4; k++) {
                    float e = occ.ex[k][j][i] * dx + occ.ey[k][j][i] * dy + occ.ez[k][j][i] * dz;
                    inside &= e > limit;
                    outside |= e < -limit;
                }
                blocked[i] |= across & inside;
                unsure[i] |= on_plane | (across & !inside & !outside);
            }
        }
        int any = 0;
#pragma omp simd reduction(+ : any)
        for (int i = 0; i < 16; i++) {
            float dx = sun ? qx[i] : qx[i] - ox[i], dy = sun ? qy[i] : qy[i] - oy[i];
            float dz = sun ? qz[i] : qz[i] - oz[i];
            float dist2 = dx * dx + dy * dy + dz * dz;
            float n_d = nx[i] * dx + ny[i] * dy + nz[i] * dz;  /* |d| cos(theta_p) */
            float l_d = lzx * dx + lzy * dy + lzz * dz;        /* |d| cos(theta_light) */
            /* Above p's horizon and in front of the one-sided light. */
            int ok = live[i] & (n_d > 0.0f) & (sun | (l_d > 0.0f));
            float w = sun ? n_d : n_d * l_d / (dist2 * dist2);  /* cos cos / r^2, no sqrt needed */
            w_sample[i] = ok ? w : 0.0f;
            weight_all[i] += w_sample[i];
            above[i] += ok;
            above_a[i] += ok & half_a;
            ray.dir_x[i] = dx, ray.dir_y[i] = dy, ray.dir_z[i] = dz;
            /* the light itself is not geometry; rtcOccluded16 resets it */
            ray.tfar[i] = sun ? INFINITY : 1.0f;
            decided[i] = known[i] & (blocked[i] | !unsure[i]);
            open[i] = ok & !blocked[i];
            active[i] = -(ok & !decided[i]);
            any += ok & !decided[i];
        }
        if (any) {
            rtcOccluded16(active, tr->rtc, &ctx, &ray);
            rays += any;
        }
#pragma omp simd
        for (int i = 0; i < 16; i++) {
            /* tfar = -inf when occluded */
            int seen = decided[i] ? open[i] : active[i] & (ray.tfar[i] >= 0.0f);
            visible[i] += seen;
            visible_a[i] += seen & half_a;
            weight_vis[i] += seen ? w_sample[i] : 0.0f;
        }
    }
    /* the light's area, or the sun's solid angle 2 pi (1 - cos alpha) */
    const float area = sun ? 2.0f * (float)M_PI * cap
                       : L->shape == LIGHT_RECT ? L->width * L->height : (float)M_PI * L->radius * L->radius;
    *samples = 0;
    for (int i = 0; i < 16; i++) {
        if (!live[i])
            continue;
        *samples += above[i];
        const int j = pixel[i], na = above_a[i], nb = above[i] - above_a[i];
        out->h[j] = (float)above[i] / (float)(n * n);
        out->e[j] = weight_all[i] * area / (float)(n * n);
        out->v[j] = above[i] ? (float)visible[i] / (float)above[i] : 0.0f;
        out->v_weighted[j] = weight_all[i] > 0 ? weight_vis[i] / weight_all[i] : 0.0f;
        /* V = (na V_a + nb V_b) / (na + nb). With the halves' errors
         * independent, of variance ~ 1/n_x, Var(V) / Var(V_a - V_b) =
         * na nb / (na + nb)^2: with equal halves, (V_a - V_b) / 2. */
        if (na && nb) {
            float va = (float)visible_a[i] / (float)na, vb = (float)(visible[i] - visible_a[i]) / (float)nb;
            out->noise[j] = (va - vb) * sqrtf((float)na * (float)nb) / (float)above[i];
        }
        out->mask[j] = out->h[j] >= GT_MIN_H ? 1.0f : 0.0f;
    }
    return rays;
}

static RTCScene build_scene(RTCDevice dev, const struct scene *s)
{
    RTCScene rtc = rtcNewScene(dev);
    rtcSetSceneFlags(rtc, RTC_SCENE_FLAG_NONE);
    rtcSetSceneBuildQuality(rtc, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *v = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                       3 * sizeof(float), s->vertex_count);
    uint32_t *ix = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                           3 * sizeof(uint32_t), s->triangle_count);
    if (!v || !ix) {
        rtcReleaseGeometry(g);
        rtcReleaseScene(rtc);
        return NULL;
    }
    memcpy(v, s->positions, s->vertex_count * 3 * sizeof(float));
    memcpy(ix, s->indices, s->triangle_count * 3 * sizeof(uint32_t));
    rtcCommitGeometry(g);
    rtcAttachGeometry(rtc, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(rtc);
    return rtc;
}

static void progress(double start_ms, long long done, long long total, long long samples)
{
    double s = (util_now_ms() - start_ms) * 1e-3;
    double eta = done > 0 ? s * (double)(total - done) / (double)done : 0;
    log_progress("ground truth: %3.0f%%  %6.1f M samples/s  ETA %4.0f s", 100.0 * (double)done / (double)total,
                 s > 0 ? (double)samples / s * 1e-6 : 0.0, eta);
}

enum gt_render_result gt_render(const struct scene *s, const struct light_frustum *f, const struct gt_desc *d,
                                struct gt_image *out)
{
    struct tracer tr = {.scene = s, .frustum = f, .desc = *d};
    desc_defaults(&tr.desc);
    if (tr.desc.width <= 0 || tr.desc.height <= 0) {
        log_error("ground truth: no image size (%d x %d)", tr.desc.width, tr.desc.height);
        return GT_RENDER_FAILED;
    }
    tr.strata = (int)lround(sqrt((double)tr.desc.samples));
    if (tr.strata * tr.strata != tr.desc.samples) {
        log_error("ground truth: %d samples is not a square n*n", tr.desc.samples);
        return GT_RENDER_FAILED;
    }
    tr.eps = GT_OFFSET_SCALE * scene_extent(s);

    RTCDevice dev = embree_device();
    if (!dev || !(tr.rtc = build_scene(dev, s)))
        return GT_RENDER_FAILED;
    /* The samples decided without a ray are an area light's (cull.h's
     * pyramid reaches a finite light); the sun traces every one. */
    if (s->light.shape != LIGHT_SUN && !(tr.cull = cull_build(dev, s))) {
        rtcReleaseScene(tr.rtc);
        return GT_RENDER_FAILED;
    }

    const int w = tr.desc.width, h = tr.desc.height;
    memset(out, 0, sizeof *out);
    out->width = w;
    out->height = h;
    size_t count = (size_t)w * (size_t)h;
    float **planes[] = {&out->v, &out->v_weighted, &out->h, &out->e, &out->noise, &out->distance,
                        &out->mask};
    for (size_t i = 0; i < sizeof planes / sizeof *planes; i++)
        *planes[i] = xmalloc(count * sizeof(float));

    const int tiles_x = (w + TILE - 1) / TILE, tiles_y = (h + TILE - 1) / TILE;
    const long long tiles = (long long)tiles_x * tiles_y;
    const bool show = !tr.desc.quiet;
    atomic_llong done = 0, rays = 0, samples = 0;
    double start = util_now_ms(), last_report = start;
    bool reported = false;

#pragma omp parallel for schedule(dynamic, 4)
    for (long long t = 0; t < tiles; t++) {
        if (tr.desc.cancel && atomic_load(tr.desc.cancel))
            continue;  /* an OpenMP loop cannot break: the remaining tiles are skipped */
        long long resolved;
        long long r = trace_tile(&tr, (int)(t % tiles_x) * TILE, (int)(t / tiles_x) * TILE, out, &resolved);
        atomic_fetch_add(&rays, r);
        atomic_fetch_add(&samples, resolved);
        long long now_done = atomic_fetch_add(&done, 1) + 1;
        if (show && omp_get_thread_num() == 0) {
            double now = util_now_ms();
            if (now - start > 1000.0 && now - last_report > 250.0) {
                progress(start, now_done, tiles, atomic_load(&samples));
                last_report = now;
                reported = true;
            }
        }
    }
    if (reported) {
        progress(start, tiles, tiles, atomic_load(&samples));
        log_progress_done();
    }

    out->seconds = (util_now_ms() - start) * 1e-3;
    out->shadow_rays = atomic_load(&rays);
    out->samples = atomic_load(&samples);
    out->msamples_per_second = out->seconds > 0 ? (double)out->samples / out->seconds * 1e-6 : 0;
    rtcReleaseScene(tr.rtc);
    cull_free(tr.cull);
    return tr.desc.cancel && atomic_load(tr.desc.cancel) ? GT_CANCELLED : GT_RENDERED;
}

void gt_image_free(struct gt_image *g)
{
    free(g->v), free(g->v_weighted), free(g->h), free(g->e), free(g->noise);
    free(g->distance), free(g->mask);
    memset(g, 0, sizeof *g);
}

double gt_noise_floor(const float *noise, const float *mask, size_t count)
{
    double sum = 0;
    long n = 0;
    for (size_t i = 0; i < count; i++)
        if (mask[i] > 0.5f) {
            sum += (double)noise[i] * noise[i];
            n++;
        }
    return n ? sqrt(sum / (double)n) : NAN;
}

/* The cache key (docs/design.md §6) in words: what the entry's pixels depend
 * on. Its hash names the file; the entry also records the words, so a file
 * copied over another entry is refused rather than used. */
static char *cache_key(const struct scene *s, const struct light_frustum *f, const struct gt_desc *d)
{
    uint64_t frustum = util_hash(UTIL_HASH_INIT, f, sizeof *f);
    return util_printf("shadowbench ground truth v%d: scene %s (bytes %016llx), %dx%d, %d samples, "
                       "seed %u, frustum %016llx", GT_VERSION, s->name, (unsigned long long)s->hash,
                       d->width, d->height, d->samples, d->seed, (unsigned long long)frustum);
}

/* The channels of a cache entry, bound to g's planes. */
#define GT_CACHE_CHANNELS 7
static void cache_channels(struct gt_image *g, struct exr_channel ch[GT_CACHE_CHANNELS])
{
    const struct exr_channel c[GT_CACHE_CHANNELS] = {
        {"V", g->v}, {"V_weighted", g->v_weighted}, {"H", g->h}, {"E", g->e},
        {"noise", g->noise}, {"distance", g->distance}, {"mask", g->mask}};
    memcpy(ch, c, sizeof c);
}

/* Reads the entry at path into out when it records key. Returns 0, -ENOENT
 * when there is none, -1 when it is unusable (logged). */
static int cache_read(const char *path, const char *key, const struct gt_desc *d, struct gt_image *out)
{
    struct exr_channel ch[GT_CACHE_CHANNELS];
    char *recorded = NULL;
    cache_channels(out, ch);
    int rc = image_read_exr(path, d->width, d->height, ch, GT_CACHE_CHANNELS, &recorded);
    if (rc == 0 && (!recorded || strcmp(recorded, key) != 0)) {
        log_warn("%s: records another key (%s), not this one (%s)", path,
                 recorded ? recorded : "none", key);
        for (int i = 0; i < GT_CACHE_CHANNELS; i++)
            free(ch[i].data);
        rc = -1;
    }
    free(recorded);
    /* The pixels too: a damaged entry with the right key must not be
     * scored against. V, V_weighted and H are shares, E is finite and not
     * negative, the noise (a signed difference of shares) within 1, the
     * mask 0 or 1, a distance -1 (no surface) or not negative. */
    const size_t count = (size_t)d->width * (size_t)d->height;
    for (size_t i = 0; rc == 0 && i < count; i++) {
        const float v[GT_CACHE_CHANNELS] = {ch[0].data[i], ch[1].data[i], ch[2].data[i], ch[3].data[i],
                                            ch[4].data[i], ch[5].data[i], ch[6].data[i]};
        const bool ok = v[0] >= 0 && v[0] <= 1 && v[1] >= 0 && v[1] <= 1 && v[2] >= 0 && v[2] <= 1 &&
                        v[3] >= 0 && isfinite(v[3]) && fabsf(v[4]) <= 1 && (v[5] >= 0 || v[5] == -1) &&
                        (v[6] == 0 || v[6] == 1);
        if (!ok) {
            for (int c = 0; c < GT_CACHE_CHANNELS; c++)
                free(ch[c].data);
            log_warn("%s: pixel (%zu, %zu) holds values no ground truth has (V %g, V_weighted %g, H %g, E %g, "
                     "noise %g, distance %g, mask %g)", path, i % (size_t)d->width, i / (size_t)d->width,
                     (double)v[0], (double)v[1], (double)v[2], (double)v[3], (double)v[4], (double)v[5],
                     (double)v[6]);
            rc = -1;
        }
    }
    if (rc == 0) {
        *out = (struct gt_image){.width = d->width, .height = d->height, .v = ch[0].data,
                                 .v_weighted = ch[1].data, .h = ch[2].data, .e = ch[3].data,
                                 .noise = ch[4].data, .distance = ch[5].data, .mask = ch[6].data,
                                 .cached = true};
    }
    return rc;
}

/* The lock of the cache entry at path (docs/scale-out.md): "<path>.lock",
 * held (flock, exclusive) while the entry is read, or traced and written.
 * Shards on other machines share the cache through their file system, so
 * one traces a truth while the others wait for it, and none reads an entry
 * being written (it is renamed into place whole, too). Returns the open
 * lock, or -1 where it cannot be taken (logged as a warning: the cache is
 * then used without it, as before locks). */
static int cache_lock(const char *path, const char *scene)
{
    char *name = util_printf("%s.lock", path);
    int fd = open(name, O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (fd < 0 && (errno == EACCES || errno == EROFS))  /* a cache only read here: its lock, if made */
        fd = open(name, O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
    int rc = fd < 0 ? -1 : 0;
    if (fd >= 0 && (rc = flock(fd, LOCK_EX | LOCK_NB)) != 0 && errno == EWOULDBLOCK) {
        log_info("ground truth %s: another shadowbench is tracing it (%s): waiting for it", scene, name);
        while ((rc = flock(fd, LOCK_EX)) != 0 && errno == EINTR)
            ;
    }
    if (rc != 0) {  /* a file system without locks, a folder that is not ours */
        log_warn("%s: cannot lock (%s): the cache is used unlocked", name, strerror(errno));
        if (fd >= 0)
            close(fd);
        fd = -1;
    }
    free(name);
    return fd;
}

/* Removes what writers killed before their rename left in the cache: an
 * entry's temporary, "<scene>-<16 hex digits>.exr.tmp.<pid>", whose
 * entry's lock is free or was never made (its writer holds it while
 * writing; a pid says nothing of a process on another machine). Nothing
 * else in the folder is touched. */
/* The length of the entry name that file name is a temporary of
 * ("<scene>-<16 hex digits>.exr" before ".tmp.<pid>"), or 0: not one. */
static size_t cache_temp_entry(const char *name)
{
    static const char tail[] = "-0123456789abcdef.exr";  /* its shape: "-", 16 hex digits, ".exr" */
    const size_t tail_len = sizeof tail - 1;
    const char *mark = NULL;  /* the last ".tmp.", followed by a pid */
    for (const char *m = strstr(name, UTIL_TEMP_SUFFIX); m; m = strstr(m + 1, UTIL_TEMP_SUFFIX))
        mark = m;
    const char *pid = mark ? mark + strlen(UTIL_TEMP_SUFFIX) : "";
    const size_t entry = mark ? (size_t)(mark - name) : 0;
    if (!*pid || strspn(pid, "0123456789") != strlen(pid) || name[0] == '.' || entry <= tail_len)
        return 0;
    const char *t = name + entry - tail_len;  /* where its tail begins */
    return t[0] == '-' && strspn(t + 1, "0123456789abcdef") >= 16 && strncmp(t + 17, ".exr", 4) == 0 ? entry : 0;
}

static void cache_sweep(const char *cache_dir)
{
    DIR *d = opendir(cache_dir);
    for (struct dirent *e; d && (e = readdir(d));) {
        const size_t entry = cache_temp_entry(e->d_name);
        if (!entry)
            continue;
        char *temp = util_printf("%s/%s", cache_dir, e->d_name);
        char *lock = util_printf("%s/%.*s.lock", cache_dir, (int)entry, e->d_name);
        const int fd = open(lock, O_RDWR | O_CLOEXEC | O_NOFOLLOW);
        if ((fd < 0 && errno == ENOENT) || (fd >= 0 && flock(fd, LOCK_EX | LOCK_NB) == 0))
            unlink(temp);
        if (fd >= 0)
            close(fd);
        free(temp), free(lock);
    }
    if (d)
        closedir(d);
}

int gt_obtain(const struct scene *s, const struct light_frustum *f, const struct gt_desc *desc,
              const char *cache_dir, struct gt_image *out)
{
    struct gt_desc d = *desc;
    desc_defaults(&d);
    char *key = cache_key(s, f, &d), *path = NULL;
    if (cache_dir)
        path = util_printf("%s/%s-%016llx.exr", cache_dir, s->name,
                           (unsigned long long)util_hash(UTIL_HASH_INIT, key, strlen(key)));
    memset(out, 0, sizeof *out);
    static char swept[4096];  /* what writers killed before their rename left, once per cache */
    if (cache_dir && strcmp(swept, cache_dir) != 0) {
        cache_sweep(cache_dir);
        snprintf(swept, sizeof swept, "%s", cache_dir);
    }
    const int lock = path && util_mkdirs(cache_dir) == 0 ? cache_lock(path, s->name) : -1;
    log_errors_as_warnings(true);  /* an unusable entry is rendered again: not an error of the run */
    int rc = path ? cache_read(path, key, &d, out) : -ENOENT;
    log_errors_as_warnings(false);
    if (rc == 0) {
        log_info("ground truth %s: from cache %s", s->name, path);
    } else {
        if (rc != -ENOENT)
            log_warn("%s: unusable cache entry, rendering again", path);
        log_info("ground truth %s: %dx%d, %d light samples per pixel", s->name, d.width, d.height,
                 d.samples);
        rc = gt_render(s, f, &d, out);
        if (rc == 0) {
            log_info("ground truth %s: %.1f M light samples (%.1f M traced, the rest decided "
                     "without a ray) in %.2f s = %.1f M samples/s", s->name, (double)out->samples * 1e-6,
                     (double)out->shadow_rays * 1e-6, out->seconds, out->msamples_per_second);
            struct exr_channel ch[GT_CACHE_CHANNELS];
            cache_channels(out, ch);
            log_errors_as_warnings(true);  /* a cache that cannot be written costs time, not the result */
            if (path && (util_mkdirs(cache_dir) != 0 ||
                         image_write_exr(path, d.width, d.height, ch, GT_CACHE_CHANNELS, key) != 0))
                log_warn("ground truth %s: not cached", s->name);
            log_errors_as_warnings(false);
        }
    }
    if (lock >= 0)
        close(lock);  /* the entry is written (or will not be): the next one reads it */
    free(key);
    free(path);
    return rc;
}
