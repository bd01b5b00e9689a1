/* The shipped scenes. Each isolates one phenomenon with only the geometry it
 * needs (y is up, the ground is y = 0, units are arbitrary but consistent);
 * the comment above each builder says what it shows and why the geometry is
 * what it is. */
#include "scene_library.h"
#include "base/log.h"
#include "base/util.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void ground(struct mesh_builder *m, float x0, float z0, float x1, float z1)
{
    mesh_add_quad(m, v3(x0, 0, z0), v3(0, 0, z1 - z0), v3(x1 - x0, 0, 0));  /* normal +y */
}

/* A horizontal plate at height y (normal +y, seen from both sides). */
static void plate(struct mesh_builder *m, float x0, float z0, float x1, float z1, float y)
{
    mesh_add_quad(m, v3(x0, y, z0), v3(0, 0, z1 - z0), v3(x1 - x0, 0, 0));
}

/* A unit box and a sphere floating at different heights over a ground
 * plane, under a 1.2 x 1.2 rect light 6 units up: two penumbrae of
 * different widths (the higher sphere's is wider) on a flat receiver. */
static int floating_box_sphere(struct mesh_builder *m, struct gltf_scene_desc *d)
{
    static const char *const motions[] = {"caster_shift:sphere=0.25", NULL};
    mesh_begin_part(m, "ground");
    ground(m, -6, -6, 6, 6);
    mesh_begin_part(m, "box");
    mesh_add_box(m, v3(-2.0f, 1.0f, -0.5f), v3(-1.0f, 2.0f, 0.5f));
    mesh_begin_part(m, "sphere");
    mesh_add_sphere(m, v3(1.5f, 2.6f, 0.0f), 0.6f, 48);
    *d = (struct gltf_scene_desc){
        .description = "A box (bottom 1 above the ground) and a sphere (bottom 2 above) over a "
                       "ground plane under a 1.2 x 1.2 rect light.",
        .shows = "penumbra width growing with the blocker-receiver distance; the basic "
                 "end-to-end case",
        .camera_pos = v3(0.0f, 7.0f, 8.5f), .camera_target = v3(0.0f, 0.5f, 0.0f),
        .camera_yfov_rad = 0.75f, .camera_znear = 0.1f,
        .light_pos = v3(0.5f, 6.0f, 0.0f), .light_target = v3(0.5f, 0.0f, 0.0f),
        .light_width = 1.2f, .light_height = 1.2f,
        .motions = motions,
    };
    return 0;
}

void scene_parallel_planes(struct mesh_builder *m, struct gltf_scene_desc *d, float light_width,
                           bool disk)
{
    ground(m, -6, -6, 6, 6);
    plate(m, -8, -8, 0, 8, PP_H_BLOCK);  /* the half-plane x < 0, edge along z */
    *d = (struct gltf_scene_desc){
        .description = disk ? "A disk light 4 above a receiver plane; an occluder half-plane 2 "
                              "above it, its straight edge parallel to both."
                            : "A square light 4 above a receiver plane; an occluder half-plane 2 "
                              "above it, its straight edge parallel to both.",
        .shows = disk ? "the closed-form case for a disk light: the penumbra is the visible "
                        "circular segment of the light, 1 unit wide"
                      : "the closed-form case: a linear penumbra ramp 1 unit wide; the "
                        "PCSS model is exact here",
        .camera_pos = v3(0.0f, 1.2f, 3.0f), .camera_target = v3(0.0f, 0.0f, 0.0f),
        .camera_yfov_rad = 0.5f, .camera_znear = 0.05f,
        .light_pos = v3(0, PP_H_LIGHT, 0), .light_target = v3(0, 0, 0),
        .light_disk = disk, .light_width = light_width, .light_height = light_width,
        .light_radius = 0.5f * light_width,
    };
}

static int parallel_planes(struct mesh_builder *m, struct gltf_scene_desc *d)
{
    scene_parallel_planes(m, d, 1.0f, false);
    return 0;
}

static int parallel_planes_disk(struct mesh_builder *m, struct gltf_scene_desc *d)
{
    scene_parallel_planes(m, d, 1.0f, true);
    return 0;
}

/* A thin pole standing on the ground, lit from the side by a light of about
 * its own height's size: at the foot the blocker touches the receiver and the
 * shadow is hard; towards the tip's shadow the blocker-receiver distance
 * grows, the penumbra widens past the pole's width and the shadow fades out.
 * A fixed kernel (pcf) blurs the foot and stays too hard at the tip. */
static int contact_hardening(struct mesh_builder *m, struct gltf_scene_desc *d)
{
    ground(m, -3, -3, 6, 3);
    mesh_add_box(m, v3(-0.12f, 0.0f, -0.12f), v3(0.12f, 2.5f, 0.12f));
    *d = (struct gltf_scene_desc){
        .description = "A pole 2.5 tall and 0.24 thick on the ground; a 1.2 x 1.2 rect light up "
                       "and to the side casts its shadow along the ground.",
        .shows = "contact hardening: a hard shadow at the pole's foot, widening and fading "
                 "towards the tip's shadow",
        .camera_pos = v3(1.3f, 3.4f, 5.2f), .camera_target = v3(1.3f, 0.5f, 0.0f),
        .camera_yfov_rad = 0.8f, .camera_znear = 0.05f,
        .light_pos = v3(-3.0f, 5.0f, 0.0f), .light_target = v3(1.5f, 0.0f, 0.0f),
        .light_width = 1.2f, .light_height = 1.2f,
    };
    return 0;
}

/* Two plates far apart in depth under a tilted light: A (height 3, wholly
 * in front of the light's plane, so the map's near plane stays at a sane
 * 0.3) hides the left part of B (height 1) in the map, and A's edge there projects onto
 * the receiver inside B's umbra (x in 0.4..1.2). A filter region in the map
 * there holds both depths: the variance is large, so VSM's Chebyshev bound is
 * high in a true umbra (light bleeding), and a PCSS blocker search averages
 * the two depths into one that belongs to neither. */
static int overlapping_occluders(struct mesh_builder *m, struct gltf_scene_desc *d)
{
    static const char *const motions[] = {"caster_shift:lower_plate=0.25", NULL};
    mesh_begin_part(m, "ground");
    ground(m, -4, -3, 4, 3);
    mesh_begin_part(m, "upper_plate");
    plate(m, -3, -3, -1.4f, 3, 3.0f);    /* A: x in -3..-1.4, all in front of the light */
    mesh_begin_part(m, "lower_plate");
    plate(m, -0.8f, -1, 0.4f, 1, 1.0f);  /* B: x in -0.8..0.4 */
    *d = (struct gltf_scene_desc){
        .description = "Two plates, one 3 and one 1 above the ground, overlapping as the 0.5 x 0.5 "
                       "rect light sees them.",
        .shows = "VSM light bleeding where occluders far apart in depth overlap; PCSS averaging "
                 "two blocker depths",
        .camera_pos = v3(0.6f, 2.5f, 2.5f), .camera_target = v3(0.5f, 0.0f, 0.0f),
        .camera_yfov_rad = 0.6f, .camera_znear = 0.05f,
        .light_pos = v3(-2, 4, 0), .light_target = v3(0.5f, 0, 0),
        .light_width = 0.5f, .light_height = 0.5f,
        .motions = motions,
    };
    return 0;
}

/* A long plane lit at about 8 degrees of elevation, with one low box on it.
 * Seen from the light the plane is nearly edge-on: one shadow-map texel
 * spans a long stretch of it, over which the plane's depth changes by much
 * more than a texel's worth, so a comparison without enough bias shadows the
 * plane itself (acne) and a bias large enough to prevent that detaches the
 * box's shadow from its foot (peter-panning). */
static int grazing_receiver(struct mesh_builder *m, struct gltf_scene_desc *d)
{
    ground(m, -4, -3, 10, 3);
    mesh_add_box(m, v3(0.0f, 0.0f, -0.5f), v3(0.6f, 0.5f, 0.5f));
    *d = (struct gltf_scene_desc){
        .description = "A 0.6 x 0.5 x 1 box on a long plane; a 0.5 x 0.5 rect light 1.4 above "
                       "the plane and 10 away lights it at about 8 degrees.",
        .shows = "shadow acne against bias (peter-panning) on a receiver at a grazing angle to "
                 "the light",
        .camera_pos = v3(1.5f, 4.0f, 4.0f), .camera_target = v3(1.5f, 0.0f, 0.0f),
        .camera_yfov_rad = 0.8f, .camera_znear = 0.05f,
        .light_pos = v3(-10.0f, 1.4f, 0.0f), .light_target = v3(4.0f, 0.0f, 0.0f),
        .light_width = 0.5f, .light_height = 0.5f,
    };
    return 0;
}

/* A grid of thin bars (0.03 wide, 0.25 apart) 1.2 above the ground under a
 * 0.8 x 0.8 light 5 up: each bar's penumbra (0.25 wide) is eight times the
 * bar and as wide as a gap, so the truth under the grid is an even partial
 * shadow with a faint ripple. A bar is a few texels of the 1024^2 map: hard
 * shadows alias it, a blocker search finds bars in some taps and gaps in
 * others, and the moments of bars and gaps give VSM a wide variance. */
static int thin_features(struct mesh_builder *m, struct gltf_scene_desc *d)
{
    ground(m, -3, -3, 3, 3);
    const int bars = 9;
    const float w = 0.03f, pitch = 0.25f, half = 0.5f * pitch * (float)(bars - 1) + w, y = 1.2f;
    for (int i = 0; i < bars; i++) {
        float c = -0.5f * pitch * (float)(bars - 1) + pitch * (float)i;
        mesh_add_box(m, v3(c - 0.5f * w, y, -half), v3(c + 0.5f * w, y + w, half));  /* along z */
        mesh_add_box(m, v3(-half, y + w, c - 0.5f * w), v3(half, y + 2 * w, c + 0.5f * w));  /* along x */
    }
    *d = (struct gltf_scene_desc){
        .description = "A 9 x 9 grid of bars 0.03 thick at a 0.25 pitch, 1.2 above the ground, "
                       "under a 0.8 x 0.8 rect light 5 up.",
        .shows = "high-frequency occluders: aliasing, light leaking through small gaps, a "
                 "blocker search that sees bars and gaps",
        .camera_pos = v3(1.6f, 3.0f, 3.0f), .camera_target = v3(1.0f, 0.0f, 0.0f),
        .camera_yfov_rad = 0.8f, .camera_znear = 0.05f,
        .light_pos = v3(-2.5f, 5.0f, 0.0f), .light_target = v3(1.0f, 0.0f, 0.0f),
        .light_width = 0.8f, .light_height = 0.8f,
    };
    return 0;
}

/* A 5 x 5 light only 4 above the ground over a unit box floating 1 to 2
 * up: every penumbra is wider than the box, so there is no umbra at all.
 * The PCSS blocker search spans a large part of the map (sparse taps), and
 * the int32 SAT must give up fixed-point bits for such wide boxes. */
static int large_light(struct mesh_builder *m, struct gltf_scene_desc *d)
{
    ground(m, -6, -6, 6, 6);
    mesh_add_box(m, v3(-0.5f, 1.0f, -0.5f), v3(0.5f, 2.0f, 0.5f));
    *d = (struct gltf_scene_desc){
        .description = "A unit box floating 1 above the ground under a 5 x 5 rect light 4 up.",
        .shows = "very wide penumbrae with no umbra: blocker-search range and sampling limits, "
                 "SAT precision for wide boxes",
        .camera_pos = v3(0.0f, 6.0f, 6.5f), .camera_target = v3(0.0f, 0.3f, 0.0f),
        .camera_yfov_rad = 0.8f, .camera_znear = 0.1f,
        .light_pos = v3(0.0f, 4.0f, 0.0f), .light_target = v3(0.0f, 0.0f, 0.0f),
        .light_width = 5.0f, .light_height = 5.0f,
    };
    return 0;
}

/* Two spheres and a torus resting on the ground, lit from above and to the
 * side: each casts a shadow with contact on the ground and shadows itself
 * (the terminator, where the light sets below the surface's own horizon;
 * the torus also shadows its own inner ring). A receiver-plane bias assumes
 * a flat receiver under each kernel, which these are not. */
static int curved_receivers(struct mesh_builder *m, struct gltf_scene_desc *d)
{
    ground(m, -4, -4, 4, 4);
    mesh_add_sphere(m, v3(-1.3f, 0.7f, 0.0f), 0.7f, 64);
    mesh_add_sphere(m, v3(0.2f, 0.35f, 1.0f), 0.35f, 48);
    mesh_add_torus(m, v3(1.2f, 0.28f, -0.6f), 0.7f, 0.28f, 64, 24);
    *d = (struct gltf_scene_desc){
        .description = "Spheres of radius 0.7 and 0.35 and a torus (radii 0.7, 0.28) resting on "
                       "the ground, under a 1 x 1 rect light up and to the side.",
        .shows = "self-shadowing of curved surfaces and their terminators; receiver-plane bias "
                 "on curved receivers",
        .camera_pos = v3(0.0f, 3.4f, 5.2f), .camera_target = v3(0.0f, 0.3f, 0.0f),
        .camera_yfov_rad = 0.8f, .camera_znear = 0.05f,
        .light_pos = v3(-2.5f, 4.5f, 1.5f), .light_target = v3(0.5f, 0.0f, -0.3f),
        .light_width = 1.0f, .light_height = 1.0f,
    };
    return 0;
}

/* A light 3 above a ground that reaches far beyond the widest frustum the
 * shadow map takes (a 75-degree half-angle: 11.2 out at the ground), and a
 * plate 1.5 up that crosses the frustum's edge (5.6 out at its height).
 * Near the map's edge the blocker search and filter kernels read past it
 * (where the map continues its edge texels: the edge policy), and part of
 * the plate is not in the map at all, though it shadows ground that is. */
static int map_border(struct mesh_builder *m, struct gltf_scene_desc *d)
{
    ground(m, -16, -16, 16, 16);
    plate(m, 4.0f, -2.0f, 8.0f, 2.0f, 1.5f);
    *d = (struct gltf_scene_desc){
        .description = "A 1 x 1 rect light 3 above a ground plane 32 wide; a 4 x 4 plate 1.5 up, "
                       "4 to 8 out, crossing the edge of the shadow map's frustum.",
        .shows = "an occluder at the edge of the shadow map: kernels that read past the border, "
                 "a caster partly outside the map",
        .camera_pos = v3(7.8f, 7.0f, 8.0f), .camera_target = v3(7.8f, 0.0f, 0.0f),
        .camera_yfov_rad = 0.9f, .camera_znear = 0.05f,
        .light_pos = v3(0.0f, 3.0f, 0.0f), .light_target = v3(0.0f, 0.0f, 0.0f),
        .light_width = 1.0f, .light_height = 1.0f,
    };
    return 0;
}

/* ---- the sun (docs/scenes.md): a directional light of angular diameter
 * 2 alpha; a straight edge at height h above a receiver facing the sun
 * casts a penumbra 2 h tan(alpha) wide. ---- */

/* The sun's direction (towards it) at an elevation and an azimuth from -x
 * towards -z, in degrees: light_pos and light_target for a look-at. */
static void place_sun(struct gltf_scene_desc *d, float elevation_deg, float azimuth_deg, double angular_diameter_deg)
{
    const float e = elevation_deg * (float)M_PI / 180, a = azimuth_deg * (float)M_PI / 180;
    d->light_pos = v3(-10 * cosf(e) * cosf(a), 10 * sinf(e), -10 * cosf(e) * sinf(a));
    d->light_target = v3(0, 0, 0);
    d->sun_angular_diameter_deg = angular_diameter_deg;
}

float scene_sun_penumbra_width(double angular_diameter_deg)
{
    return 2.0f * PP_H_BLOCK * (float)tan(0.5 * angular_diameter_deg * M_PI / 180);
}

void scene_sun_parallel_planes(struct mesh_builder *m, struct gltf_scene_desc *d, double angular_diameter_deg)
{
    /* A 2 m plate over the ground, the camera framing the penumbra (W wide)
     * as parallel_planes frames its own: every length of that view scaled
     * by W, so the ramp fills the image at any angle. */
    const float w = scene_sun_penumbra_width(angular_diameter_deg);
    mesh_begin_part(m, "ground");
    ground(m, -3, -3, 3, 3);
    mesh_begin_part(m, "plate");  /* the half-plane x < 0, edge along z */
    plate(m, -4, -4, 0, 4, PP_H_BLOCK);
    *d = (struct gltf_scene_desc){
        .description = "The sun straight above a receiver plane; an occluder half-plane 2 above it, its "
                       "straight edge parallel to both.",
        .shows = "the closed-form case for the sun: the penumbra is the visible circular segment of its "
                 "disk, 2 h tan(alpha) wide; the PCSS model is exact here",
        .camera_pos = v3(0.0f, 1.2f * w, 3.0f * w), .camera_target = v3(0.0f, 0.0f, 0.0f),
        .camera_yfov_rad = 0.5f, .camera_znear = 0.05f * w,
        .light_pos = v3(0, 10, 0), .light_target = v3(0, 0, 0),
        .sun_angular_diameter_deg = angular_diameter_deg,
    };
}

static int sun_parallel_planes(struct mesh_builder *m, struct gltf_scene_desc *d)
{
    scene_sun_parallel_planes(m, d, SCENE_SUN_DEG);
    return 0;
}

/* A pole 3 tall and 0.1 thick on the ground under a sun 50 degrees up:
 * its shadow runs 2.5 along the ground. At the foot the blocker touches
 * the receiver; along the shadow the height above it grows to 3.9 along
 * the sun's rays at the tip, where the penumbra is 2 * 3.9 tan(alpha) wide
 * across the shadow: 3.6 cm under the real sun (0.53 degrees), 7 to 10
 * of the default 1024^2 map's texels (5.2 x 3.5 mm here); at the foot,
 * under one. */
static void sun_pole(struct mesh_builder *m, struct gltf_scene_desc *d, double angular_diameter_deg)
{
    ground(m, -1.0f, -2.0f, 5.0f, 2.5f);
    mesh_add_box(m, v3(-0.05f, 0.0f, -0.05f), v3(0.05f, 3.0f, 0.05f));
    *d = (struct gltf_scene_desc){
        .camera_pos = v3(1.2f, 2.6f, 4.0f), .camera_target = v3(1.2f, 0.0f, 0.4f),
        .camera_yfov_rad = 0.7f, .camera_znear = 0.05f,
    };
    place_sun(d, 50, 20, angular_diameter_deg);
}

static int sun_contact(struct mesh_builder *m, struct gltf_scene_desc *d)
{
    sun_pole(m, d, SCENE_SUN_DEG);
    d->description = "A pole 3 tall and 0.1 thick on the ground under the real sun (0.53 degrees across), "
                     "50 degrees up.";
    d->shows = "the sun's contact hardening: a penumbra under a texel wide at the foot, a few texels at "
               "the tip's shadow";
    return 0;
}

static int sun_wide(struct mesh_builder *m, struct gltf_scene_desc *d)
{
    sun_pole(m, d, 5.0);
    d->description = "The pole of sun_contact under a sun 5 degrees across (an overcast or stylised sun), "
                     "50 degrees up.";
    d->shows = "a wide sun: penumbrae ten times sun_contact's, growing from the foot to 0.34 wide at the "
               "tip's shadow";
    return 0;
}

/* A low box on a long receiver under the real sun 7 degrees above the
 * horizon: the ground's depth in the map changes by many texels' worth
 * across one texel, so a comparison without enough bias shadows the
 * ground itself (acne), and a bias large enough to prevent it detaches
 * the box's 4 m shadow from its foot (peter-panning). */
static int sun_grazing(struct mesh_builder *m, struct gltf_scene_desc *d)
{
    ground(m, -2.0f, -3.0f, 12.0f, 6.0f);
    mesh_add_box(m, v3(0.0f, 0.0f, -0.5f), v3(0.6f, 0.5f, 0.5f));
    *d = (struct gltf_scene_desc){
        .description = "A 0.6 x 0.5 x 1 box on a long plane under the real sun (0.53 degrees across), 7 "
                       "degrees above the horizon.",
        .shows = "shadow acne against bias (peter-panning) under a low sun",
        .camera_pos = v3(2.4f, 3.2f, 6.0f), .camera_target = v3(2.4f, 0.0f, 0.3f),
        .camera_yfov_rad = 0.9f, .camera_znear = 0.05f,
    };
    place_sun(d, 7, 10, SCENE_SUN_DEG);
    return 0;
}

/* ---- cascades (docs/cascades.md): a 200 m ground seen from eye height
 * (1.7 m) along it, large enough to need cascades; each scene one way
 * they fail. ---- */

/* The ground from 40 m behind the camera (the casters behind it) to 200 m
 * ahead, 120 m across, and the camera looking along it. */
static void cascade_ground(struct mesh_builder *m, struct gltf_scene_desc *d)
{
    mesh_begin_part(m, "ground");
    ground(m, -60.0f, -200.0f, 60.0f, 40.0f);
    *d = (struct gltf_scene_desc){
        .camera_pos = v3(0.0f, 1.7f, 0.0f), .camera_target = v3(0.0f, 0.0f, -10.0f),
        .camera_yfov_rad = 0.9f, .camera_znear = 0.1f,
    };
}

/* A pole 14 m tall beside the view under a 3-degree sun behind the
 * camera (10 degrees to its left), 35 degrees up: its shadow runs from 12 m to 32 m away along the
 * view, so it crosses a split there (three cascades over 200 m split at
 * 0.11 of it, 22 m: docs/cascades.md runs it so), and its penumbra, 2 h
 * tan(alpha) / sin(35) across at the pole's height h above the ground,
 * is 0.3 to 0.9 m wide where it crosses: several pixels, so a width that
 * jumps at the split shows. The wide sun is what makes it measurable at
 * that distance; the real sun's is a pixel. */
static int cascade_seam(struct mesh_builder *m, struct gltf_scene_desc *d)
{
    cascade_ground(m, d);
    mesh_begin_part(m, "pole");
    mesh_add_box(m, v3(-2.15f, 0.0f, -12.15f), v3(-1.85f, 14.0f, -11.85f));
    place_sun(d, 35, -80, 3.0);  /* 10 degrees off the view's axis: no face of the pole edge-on to it */
    d->description = "A 14 m pole 2 m left of a 200 m view from eye height, under a 3-degree sun behind the "
                     "camera, 35 degrees up: its shadow runs along the view from 12 m to 32 m.";
    d->shows = "a seam at a cascade split: the penumbra's width keeps its world size across it, or jumps "
               "(--cascade-width texel)";
    return 0;
}

/* Pickets at 2, 4, ..., 128 m along the view, each scaled with its
 * distance (4% of it wide, 10% tall) and set 10% of it further right than
 * the one before, so that each casts the same shadow on the screen and
 * none hides another; the real sun from the front right, 40 degrees up,
 * casting each shadow towards the camera. With one map over 200 m a texel
 * is some 20 cm everywhere, while a pixel grows with distance: near
 * pickets' shadows span many pixels per texel (blocky), far ones few. The
 * error against distance shows it, and what cascades buy. */
static int cascade_distance(struct mesh_builder *m, struct gltf_scene_desc *d)
{
    cascade_ground(m, d);
    mesh_begin_part(m, "pickets");
    int k = 0;
    for (float z = 2.0f; z <= 128.0f; z *= 2.0f, k++) {
        const float x = (-0.33f + 0.1f * (float)k) * z, w = 0.02f * z;
        mesh_add_box(m, v3(x - w, 0.0f, -z - w), v3(x + w, 0.1f * z, -z + w));
    }
    place_sun(d, 40, 135, SCENE_SUN_DEG);
    d->description = "Pickets at 2, 4, ..., 128 m along a 200 m view from eye height, each scaled with its "
                     "distance, under the real sun from the front right, 40 degrees up.";
    d->shows = "perspective aliasing: the error against distance from the camera, one map against cascades";
    return 0;
}

/* A 40 m tower 25 m behind the camera under the real sun 15 degrees up,
 * behind it: its shadow runs 150 m along the view, its penumbra some
 * 0.4 m wide where the camera sees it 20 m away (the tower's top is 45 m
 * up the sun's ray from there). The tower is far outside the near
 * cascades' slices: with --depth-clamp on, their near planes sit at
 * their receivers and the tower is pancaked onto them, so the PCSS
 * family finds its blocker far too close to the receiver and hardens the
 * penumbra. */
static int cascade_pancake(struct mesh_builder *m, struct gltf_scene_desc *d)
{
    cascade_ground(m, d);
    mesh_begin_part(m, "tower");
    mesh_add_box(m, v3(5.0f, 0.0f, 24.0f), v3(7.0f, 40.0f, 26.0f));
    place_sun(d, 15, -90, SCENE_SUN_DEG);
    d->description = "A 40 m tower 25 m behind the camera of a 200 m view from eye height, under the real sun "
                     "15 degrees up behind it: its shadow runs 150 m along the view.";
    d->shows = "pancaking: a caster outside a cascade's depth range, clamped onto its near plane "
               "(--depth-clamp on), gives the PCSS family a wrong blocker depth";
    return 0;
}

/* A 2 m square plate 1.5 m above the ground, 8 m away, under the real
 * sun from the left, 40 degrees up, its shadow 1.8 m to its right; its
 * motion moves it along the view (the sun's x axis), 2.5 texels of one map
 * over the view a frame (half a metre), so that its shadow leaves the
 * near cascade of two split at 0.04 of the view (8 m; docs/cascades.md
 * runs it so) for the far one, whose texels are some twenty times as
 * wide: its error steps up at once. A horizontal plate, so that no face is
 * edge-on to the sun. */
static int cascade_pop(struct mesh_builder *m, struct gltf_scene_desc *d)
{
    static const char *const motions[] = {"caster_shift:block=2.5", NULL};
    cascade_ground(m, d);
    mesh_begin_part(m, "block");
    plate(m, -3.0f, -9.0f, -1.0f, -7.0f, 1.5f);
    place_sun(d, 40, 0, SCENE_SUN_DEG);
    d->description = "A 2 m plate 1.5 m up, 8 m along a 200 m view from eye height, under the real sun from the "
                     "left, 40 degrees up; its motion moves it along the view.";
    d->shows = "pop: a caster crossing a cascade split, its error stepping at once (stability's caster_shift:block)";
    d->motions = motions;
    return 0;
}

/* A fence of twelve posts (2 m tall, 25 cm thick) along the view, 3 to 36 m away, under the
 * real sun 25 degrees up from the front left: crisp shadow edges across
 * the ground. Its motions move the camera by a quarter pixel and turn it
 * by 0.02 degrees a frame: each refits the sun's maps, and without
 * snapping their texel grid slides under the edges (shimmer). */
static int cascade_shimmer(struct mesh_builder *m, struct gltf_scene_desc *d)
{
    static const char *const motions[] = {"camera_shift=0.25", "camera_yaw=0.02", NULL};
    cascade_ground(m, d);
    mesh_begin_part(m, "fence");
    for (int k = 1; k <= 12; k++)
        mesh_add_box(m, v3(-1.625f, 0.0f, -3.0f * (float)k - 0.125f), v3(-1.375f, 2.0f, -3.0f * (float)k + 0.125f));
    place_sun(d, 25, 30, SCENE_SUN_DEG);
    d->description = "A fence of twelve 2 m posts along a 200 m view from eye height, 3 to 36 m away, under "
                     "the real sun 25 degrees up from the front left.";
    d->shows = "shimmer: the camera moving by sub-texel steps and turning slowly, with snapping on and off "
               "(stability's camera_shift and camera_yaw)";
    d->motions = motions;
    return 0;
}

/* Reads the vertices and triangles of a Wavefront OBJ ("v x y z" and
 * "f a b c" lines, 1-based, optional /texture/normal parts ignored). */
static int read_obj(const char *path, float **pos, size_t *vertex_count, uint32_t **tri,
                    size_t *tri_count)
{
    char *text = NULL;
    size_t size;
    int err = util_read_file(path, &text, &size);
    if (err) {
        log_error("%s: cannot read: %s (install Debian's glmark2-data)", path, strerror(-err));
        return -1;
    }
    size_t nv = 0, nt = 0, cap_v = 0, cap_t = 0;
    float *p = NULL;
    uint32_t *t = NULL;
    int rc = 0;
    for (char *line = strtok(text, "\n"); line && !rc; line = strtok(NULL, "\n")) {
        if (line[0] == 'v' && line[1] == ' ') {
            if (nv == cap_v)
                p = xrealloc(p, sizeof(float) * 3 * (cap_v = cap_v ? 2 * cap_v : 4096));
            if (sscanf(line + 2, "%f %f %f", &p[3 * nv], &p[3 * nv + 1], &p[3 * nv + 2]) != 3)
                rc = -1;
            nv++;
        } else if (line[0] == 'f' && line[1] == ' ') {
            long a, b, c;
            if (sscanf(line + 2, "%ld%*[^ ] %ld%*[^ ] %ld", &a, &b, &c) != 3 &&
                sscanf(line + 2, "%ld %ld %ld", &a, &b, &c) != 3)
                rc = -1;
            if (nt == cap_t)
                t = xrealloc(t, sizeof(uint32_t) * 3 * (cap_t = cap_t ? 2 * cap_t : 8192));
            t[3 * nt] = (uint32_t)(a - 1), t[3 * nt + 1] = (uint32_t)(b - 1), t[3 * nt + 2] = (uint32_t)(c - 1);
            nt++;
        }
    }
    free(text);
    for (size_t i = 0; i < 3 * nt && !rc; i++)
        rc = t[i] >= nv ? -1 : 0;
    if (rc || nt == 0) {
        log_error("%s: not a triangle mesh this reader understands", path);
        free(p), free(t);
        return -1;
    }
    *pos = p, *vertex_count = nv, *tri = t, *tri_count = nt;
    return 0;
}

/* The Stanford Bunny (Turk & Levoy, Stanford 3D Scanning Repository, 1994),
 * as Debian's glmark2-data ships it, scaled to 1.5 tall and set on the
 * ground, under a 1 x 1 light up and to the side: a scanned surface of some
 * detail (ears, folds, an open base) casting on the ground and onto itself. */
static int stanford_bunny(struct mesh_builder *m, struct gltf_scene_desc *d)
{
    float *p;
    uint32_t *t;
    size_t nv, nt;
    if (read_obj(SCENE_BUNNY_OBJ, &p, &nv, &t, &nt) != 0)
        return -1;
    struct vec3 lo = v3(INFINITY, INFINITY, INFINITY), hi = v3(-INFINITY, -INFINITY, -INFINITY);
    for (size_t i = 0; i < nv; i++) {
        lo = v3_min(lo, v3(p[3 * i], p[3 * i + 1], p[3 * i + 2]));
        hi = v3_max(hi, v3(p[3 * i], p[3 * i + 1], p[3 * i + 2]));
    }
    const float s = 1.5f / (hi.y - lo.y);
    const struct vec3 c = v3(0.5f * (lo.x + hi.x), lo.y, 0.5f * (lo.z + hi.z));
    ground(m, -4, -4, 4, 4);
    size_t base = m->vertex_count;
    for (size_t i = 0; i < nv; i++)
        mesh_add_vertex(m, v3_scale(v3_sub(v3(p[3 * i], p[3 * i + 1], p[3 * i + 2]), c), s));
    for (size_t i = 0; i < 3 * nt; i++)
        mesh_add_index(m, (uint32_t)(base + t[i]));
    free(p), free(t);
    *d = (struct gltf_scene_desc){
        .description = "The Stanford Bunny (Stanford 3D Scanning Repository; the 69 666-triangle "
                       "mesh of Debian's glmark2-data), 1.5 tall, on the ground under a 1 x 1 "
                       "rect light.",
        .shows = "a real scanned mesh: ears and folds shadowing the ground and the bunny itself",
        .camera_pos = v3(0.6f, 1.9f, 3.0f), .camera_target = v3(0.3f, 0.55f, 0.0f),
        .camera_yfov_rad = 0.75f, .camera_znear = 0.05f,
        .light_pos = v3(-2.0f, 4.5f, 1.5f), .light_target = v3(0.5f, 0.0f, -0.3f),
        .light_width = 1.0f, .light_height = 1.0f,
    };
    return 0;
}

const struct scene_recipe scene_recipes[] = {
    {"cascade_distance", cascade_distance},
    {"cascade_pancake", cascade_pancake},
    {"cascade_pop", cascade_pop},
    {"cascade_seam", cascade_seam},
    {"cascade_shimmer", cascade_shimmer},
    {"contact_hardening", contact_hardening},
    {"curved_receivers", curved_receivers},
    {"floating_box_sphere", floating_box_sphere},
    {"grazing_receiver", grazing_receiver},
    {"large_light", large_light},
    {"map_border", map_border},
    {"overlapping_occluders", overlapping_occluders},
    {"parallel_planes", parallel_planes},
    {"parallel_planes_disk", parallel_planes_disk},
    {"stanford_bunny", stanford_bunny},
    {"sun_contact", sun_contact},
    {"sun_grazing", sun_grazing},
    {"sun_parallel_planes", sun_parallel_planes},
    {"sun_wide", sun_wide},
    {"thin_features", thin_features},
    {NULL, NULL},
};

int scene_recipe_write(const struct scene_recipe *r, const char *dir)
{
    struct mesh_builder m = {0};
    struct gltf_scene_desc d;
    int rc = r->build(&m, &d);
    if (rc == 0) {
        char *path = util_printf("%s/%s.gltf", dir, r->name);
        rc = gltf_write(path, &m, &d);
        free(path);
    }
    mesh_free(&m);
    return rc;
}
