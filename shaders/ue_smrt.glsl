// ue_smrt: Unreal Engine 5's shadow-map ray tracing (see techniques/ue.c).
#include "shadow_taps.glsl"

// One ray's march from its far end back to its start, through the map:
// start and end as (uv, hardware depth) of their projections (the ray is
// interpolated between them, as UE interpolates in the map's space),
// samples at t = ((m - 1 - i + offset) / m)^2 and one at the start. A
// sample whose stored surface lies more than a step in front of the ray
// is behind an occluder: the last trusted surface, extended along its
// depth slope (at most max_slope a unit of t), stands for it. A hit: the
// surface (stored or extended) in front of the ray by less than a step.
bool ue_ray_hits(vec3 start, vec3 end, int m, float offset, float max_slope)
{
    float history = -1.0, history_t = 0.0, slope = 0.0, prev_ref = 0.0;
    bool first = true;
    for (int i = 0; i <= m; i++) {
        float u = i < m ? (float(m - 1 - i) + offset) / float(m) : 0.0;
        float t = u * u;
        vec3 q = mix(start, end, t);  // off the map: its edge texels (the edge policy)
        float stored = sm_depth_nearest(q.xy), ref = q.z;
        if (first) {
            first = false;
            history = stored, history_t = t, prev_ref = ref;
            if (stored > ref)
                return true;
            continue;
        }
        float tol = 1.05 * abs(ref - prev_ref);
        float used;
        if (stored - ref > tol) {
            used = history + slope * (t - history_t);  // behind an occluder: extrapolate
        } else {
            if (stored != history && t != history_t)
                slope = clamp((stored - history) / (t - history_t), -max_slope, max_slope);
            history = stored, history_t = t;
            used = stored;
        }
        float d = ref - used;
        if (d < 0.0 && d > -tol)
            return true;
        prev_ref = ref;
    }
    return false;
}

float shadow_visibility(ShadowInput s)
{
    const int rays = UE_SMRT_RAY_COUNT, m = UE_SMRT_SAMPLES_PER_RAY;
    // the start: the receiver moved off its surface by the normal bias
    // (texels at the receiver) and towards the light by the depth bias
    vec3 to_light = sm_to_light(s.pos_world);
    vec3 p = s.pos_world + s.normal_world * UE_SMRT_NORMAL_BIAS * sm_texel_world(s)
             + to_light * UE_SMRT_CONSTANT_BIAS * (sm.far_world - sm.near_world);
    // a tangent frame round the direction to the light
    vec3 axis = to_light;
    vec3 tangent = normalize(abs(axis.z) < 0.999 ? cross(axis, vec3(0.0, 0.0, 1.0)) : cross(axis, vec3(1.0, 0.0, 0.0)));
    vec3 bitangent = cross(axis, tangent);
    float radius = UE_SMRT_LIGHT_SIZE_SCALE * sm_light_radius();  // the sun's: tan(half angle)
    float dist = length(sm.light_pos_world.xyz - s.pos_world);
    float max_slope;
    // the sun's: UE's 5 is in its centimetres, 0.05 of the scenes' metres,
    // as hardware depth a unit of t
    if (sm_sun())
        max_slope = (UE_SMRT_EXTRAPOLATE_MAX_SLOPE < 0.0 ? 0.05 : UE_SMRT_EXTRAPOLATE_MAX_SLOPE)
                    / (sm.far_world - sm.near_world);
    float frame = UE_SMRT_ANIMATE_NOISE != 0 ? sm_noise_frame : 0.0;
    float offset = sm_blue_noise_at(s.frag_coord, frame).x;
    float missed = 0.0;
    for (int k = 0; k < rays; k++) {
        // the ray's point on the light: blue noise moved by the R2 step of the ray
        vec2 e = sm_blue_noise_at(s.frag_coord + floor(fract(float(k) * vec2(0.7548776662, 0.5698402910))
                                  * float(SM_BLUE_NOISE_SIDE)), frame);
        vec2 d = sm_square_to_disk(2.0 * e - 1.0);
        vec3 start = sm_project(p), end;
        if (sm_sun()) {
            // a direction in the sun's cone (a disk of radius sin(half
            // angle) across it), the ray as long as ray_length_scale times
            // the distance to the camera, cut at the map's near plane
            float sin_a = sin(atan(radius));
            vec3 dir = normalize(axis + sin_a * (d.x * tangent + d.y * bitangent));
            float length_max = (s.depth_world - sm.near_world) / max(dot(dir, axis), 1e-3);
            float len = min(UE_SMRT_RAY_LENGTH_SCALE * s.camera_distance, length_max);
            end = sm_project(p + dir * len);
        } else {
            // a point of the light's disk as seen from the receiver, the
            // ray stopping at most 75 % of the way, sooner the farther its
            // direction turns from the light's centre (max_ray_angle)
            vec3 target = sm.light_pos_world.xyz + radius * (d.x * tangent + d.y * bitangent);
            vec3 dir = normalize(target - p);
            float cos_t = dot(dir, axis), sin_t = sqrt(max(1.0 - cos_t * cos_t, 0.0));
            float len = dist * 0.75 * clamp(1.5 / (cos_t + sin_t / tan(UE_SMRT_MAX_RAY_ANGLE)), 0.0, 1.0);
            end = sm_project(p + dir * len);
        }
        if (!sm_sun())
            max_slope = (UE_SMRT_EXTRAPOLATE_MAX_SLOPE < 0.0 ? 0.05 : UE_SMRT_EXTRAPOLATE_MAX_SLOPE)
                        * abs(end.z - start.z);
        missed += ue_ray_hits(start, end, m, offset, max_slope) ? 0.0 : 1.0;
    }
    return missed / float(rays);
}
