// Shared by every technique: the shadow-map products, the receiver's
// description (ShadowInput) and the depth conventions of DESIGN.md §5.
//
// Depth conventions: `depth` is linear light-space planar depth rescaled to
// [0, 1] between the frustum's near and far planes; the D32F map stores
// hardware depth with reversed Z (1 at near, 0 at far), converted by
// sm_linear_depth().

#include "shadow_block.glsl"

layout(binding = 0) uniform sampler2D sm_depth;  // D32F, nearest, border = far

struct ShadowInput {
    vec3 pos_world;          // receiver point
    vec3 normal_world;       // geometric normal, facing the camera
    vec2 uv;                 // shadow-map coordinates of the receiver
    float depth;             // linear depth in [0, 1] (near..far)
    float depth_world;       // planar depth from the light (world units)
    float cos_light;         // cosine between normal and direction to the light centre
    float texel_depth_slope; // depth change (linear units) across one texel at this slope
    vec2 frag_coord;         // window position, for per-pixel rotations
};

// Hardware depth (reversed Z) -> linear depth in [0, 1].
float sm_linear_depth(float d_hw)
{
    float n = sm.near_world, f = sm.far_world;
    float z = n * f / (d_hw * (f - n) + n);
    return (z - n) / (f - n);
}

// tan(theta) is capped at 10 (theta ~ 84 deg) so grazing receivers keep a
// finite slope bias.
ShadowInput sm_make_input(vec3 p, vec3 n)
{
    ShadowInput s;
    vec4 c = sm.light_view_proj * vec4(p, 1.0);
    s.pos_world = p;
    s.normal_world = n;
    s.uv = c.xy / c.w * 0.5 + 0.5;
    s.depth_world = c.w;  // planar depth: clip w of a perspective projection
    s.depth = (c.w - sm.near_world) / (sm.far_world - sm.near_world);
    s.cos_light = dot(n, normalize(sm.light_pos_world.xyz - p));
    float texel_world = max(sm.near_window_world.x, sm.near_window_world.y) * sm.texel_size_uv.x
                        * c.w / sm.near_world;
    float cos_t = clamp(s.cos_light, 0.0995, 1.0);
    float tan_t = sqrt(1.0 - cos_t * cos_t) / cos_t;
    s.texel_depth_slope = texel_world * tan_t / (sm.far_world - sm.near_world);
    s.frag_coord = gl_FragCoord.xy;
    return s;
}

// Inside the light frustum, and so covered by the map?
bool sm_inside(ShadowInput s)
{
    return s.depth_world > 0.0 && all(greaterThanEqual(s.uv, vec2(0.0)))
        && all(lessThanEqual(s.uv, vec2(1.0))) && s.depth >= 0.0 && s.depth <= 1.0;
}
