// Shared by every technique: the shadow-map products, the receiver's
// description (ShadowInput) and the depth conventions of docs/design.md §5. The
// PCF family's tap machinery is shadow_taps.glsl, the PCSS geometry
// pcss_geometry.glsl: a technique includes what it uses.
//
// Depth conventions: `depth` is linear light-space planar depth rescaled to
// [0, 1] between the frustum's near and far planes; the D32F map stores
// hardware depth with reversed Z (1 at near, 0 at far), converted by
// sm_linear_depth() and back by sm_hw_depth(). Hardware depth is an affine
// function of the map's uv over any plane (it is affine in 1/z), linear depth
// is not: so receiver planes are fitted in hardware depth.

#include "depth.glsl"

// The texture products' samplers, declared by the layer from its product
// table at the bindings it gives them (SM_PRODUCT_SAMPLERS): sm_depth (D32F,
// nearest) and sm_depth_compare (the same texture, linear, GEQUAL), sm_moments
// (RG32F (d, d²)), sm_evsm (RGBA32F warped moments) and sm_msm (RGBA32F (w,
// w², w³, w⁴)), the last three filtered and mipmapped (techniques/technique.h,
// SM_PRODUCTS). Past the map's edge each continues as its edge texels (the
// edge policy, techniques/shadowmap.h): texture reads get it from the wrap
// mode, a texelFetch must clamp its coordinate to the map.
SM_PRODUCT_SAMPLERS

// Fetch counting (docs/metrics.md: fetches_per_pixel, expensive_fraction).
// A program's counting variant (SM_COUNT_FETCHES 1: compiled for scoring,
// never timed) adds up every read of a shadow-map product through
// SM_FETCHED(n), one per read instruction whatever the texels the unit
// filters (a texture or texelFetch, a bilinear comparison, a storage-buffer
// element), and a technique notes with SM_SHORTCUT() that it decided the
// pixel without its full filter (an early-out). Without counting both are
// nothing.
#if SM_COUNT_FETCHES
float sm_fetches;
bool sm_shortcut;
#define SM_FETCHED(n) sm_fetches += float(n)
#define SM_SHORTCUT() sm_shortcut = true
#else
#define SM_FETCHED(n)
#define SM_SHORTCUT()
#endif
// return v, an early-out's answer (a statement)
#define SM_EARLY_OUT(v) \
    { \
        SM_SHORTCUT(); \
        return v; \
    }

struct ShadowInput {
    vec3 pos_world;          // receiver point
    vec3 normal_world;       // geometric normal, facing the camera
    vec2 uv;                 // shadow-map coordinates of the receiver
    vec2 uv_dx, uv_dy;       // their screen-space derivatives (for filtered lookups)
    float depth;             // linear depth in [0, 1] (near..far)
    float depth_world;       // planar depth from the light (world units)
    float depth_hw;          // hardware depth (reversed Z) of the receiver
    vec2 depth_hw_gradient;  // d(depth_hw)/d(uv) of the receiver's plane; 0 if degenerate
    float cos_light;         // cosine between normal and direction to the light centre
    float texel_depth_slope; // depth change (linear units) across one texel at this slope
    vec2 frag_coord;         // window position, for per-pixel rotations
    float camera_distance;   // from the camera (world units)
};

// Receiver-plane depth bias (Isidoro 2006, "Shadow mapping: GPU-based tips
// and techniques"): the chain rule through the screen-space Jacobian of
// (u, v) gives the receiver's depth gradient in the map's uv. Needs
// derivatives, so it runs in uniform control flow, in sm_make_input.
vec2 sm_depth_gradient(vec2 uv, float depth_hw)
{
    vec3 dx = dFdx(vec3(uv, depth_hw)), dy = dFdy(vec3(uv, depth_hw));
    float det = dx.x * dy.y - dx.y * dy.x;
    if (abs(det) < 1e-20)
        return vec2(0.0);  // edge-on to the light: no usable plane
    vec2 g = vec2(dy.y * dx.z - dx.y * dy.z, dx.x * dy.z - dy.x * dx.z) / det;
    return all(lessThan(abs(g), vec2(1e10))) ? g : vec2(0.0);
}

// The surface's geometric normal at p, flipped to face the camera: the
// ground truth's convention (docs/design.md §6), so both shade the same side. A
// triangle too small for screen-space derivatives falls back to the vertex
// normal rather than giving NaN.
vec3 sm_facing_normal(vec3 p, vec3 vertex_normal, vec3 camera_pos)
{
    vec3 c = cross(dFdx(p), dFdy(p));
    vec3 n = dot(c, c) > 0.0 ? normalize(c) : normalize(vertex_normal);
    return dot(n, camera_pos - p) < 0.0 ? -n : n;
}

// The direction from p to the light: its centre, or the sun's direction.
vec3 sm_to_light(vec3 p)
{
    return normalize(sm.light_pos_world.xyz - p * sm.light_pos_world.w);
}

// The map's texel in world units (along the window's wider side) at
// planar depth depth_world: a perspective map's grows with the depth.
float sm_texel_world_at(float depth_world)
{
    return max(sm.near_window_world.x, sm.near_window_world.y) * sm.texel_size_uv.x
           * (sm_sun() ? 1.0 : depth_world / sm.near_world);
}

// A world point's map uv and hardware depth.
vec3 sm_project(vec3 p)
{
    vec4 c = sm.light_view_proj * vec4(p, 1.0);
    return vec3(c.xy / c.w * 0.5 + 0.5, c.z / c.w);
}

// The light's size as the engines' presets take it (docs/presets.md): an
// area light's radius, a rect light's the radius of the disk of its area;
// the sun's tan of its half angle.
float sm_light_radius()
{
    vec2 extent = sm.light_size_uv * sm.near_window_world;  // the sun's: 2 tan(alpha) per unit of depth
    if (sm_sun())
        return 0.5 * extent.x;
    return SM_LIGHT_SHAPE == SM_LIGHT_RECT ? sqrt(extent.x * extent.y / 3.14159265) : 0.5 * extent.x;
}

// tan(theta) is capped at 10 (theta ~ 84 deg) so grazing receivers keep a
// finite slope bias.
ShadowInput sm_make_input(vec3 p, vec3 n, vec3 camera_pos)
{
    ShadowInput s;
    vec4 c = sm.light_view_proj * vec4(p, 1.0);
    s.pos_world = p;
    s.normal_world = n;
    s.uv = c.xy / c.w * 0.5 + 0.5;
    s.uv_dx = dFdx(s.uv);
    s.uv_dy = dFdy(s.uv);
    // planar depth: clip w of a perspective projection, -z in the sun's view
    s.depth_world = sm_sun() ? -(sm.light_view * vec4(p, 1.0)).z : c.w;
    s.depth = (s.depth_world - sm.near_world) / (sm.far_world - sm.near_world);
    s.depth_hw = c.z / c.w;
    s.depth_hw_gradient = sm_depth_gradient(s.uv, s.depth_hw);
    // to the light: homogeneous, the area light's centre or the sun's direction
    s.cos_light = dot(n, sm_to_light(p));
    float texel_world = sm_texel_world_at(c.w);
    float cos_t = clamp(s.cos_light, 0.0995, 1.0);
    float tan_t = sqrt(1.0 - cos_t * cos_t) / cos_t;
    s.texel_depth_slope = texel_world * tan_t / (sm.far_world - sm.near_world);
    s.frag_coord = gl_FragCoord.xy;
    s.camera_distance = length(p - camera_pos);
    return s;
}

// Inside the light frustum, and so covered by the map?
bool sm_inside(ShadowInput s)
{
    return (s.depth_world > 0.0 || sm_sun()) && all(greaterThanEqual(s.uv, vec2(0.0)))
        && all(lessThanEqual(s.uv, vec2(1.0))) && s.depth >= 0.0 && s.depth <= 1.0;
}

// The receiver program is compiled per light shape: the harness defines
// SM_LIGHT_SHAPE (SM_LIGHT_RECT, SM_LIGHT_DISK or SM_LIGHT_SUN, whose cone
// crosses a plane in a disk), so the choice of pattern costs nothing per
// tap.
const bool SM_RECT_LIGHT = SM_LIGHT_SHAPE == SM_LIGHT_RECT;
