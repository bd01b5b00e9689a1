#version 450 core
// The viewer's unshadowed shading: the irradiance E at a surface point
// from the area light at unit radiance, counting only the part of the light
// above the point's tangent plane and in front of the light (it emits
// towards its -z). The ground truth estimates the same integral by
// sampling (its E, harness/truth/groundtruth.c); here it is closed form:
// the light as a polygon (a rect's 4 corners, a disk as a 64-gon), clipped
// to the tangent plane, then Lambert's formula
//   E = 1/2 sum_i angle(r_i, r_i+1) * dot(n, normalize(cross(r_i, r_i+1)))
// with r_i the vertices relative to the point, and the normal the ground
// truth's (the geometric one, facing the camera). The sun is a disk of
// radius tan(alpha) at unit distance along its direction: the same cone.
#include "shadow_common.glsl"

in vec3 v_pos_world;
in vec3 v_normal_world;

uniform vec3 u_camera_pos;

uniform vec3 u_light_pos, u_light_x, u_light_y, u_light_z;
uniform float u_light_half_width, u_light_half_height;  // rect
uniform float u_light_radius;                           // disk; the sun: tan(alpha)
uniform int u_light_disk;                               // a disk or the sun
uniform int u_light_sun;

layout(location = 0) out float o_irradiance;

#define DISK_SIDES 64
#define MAX_VERTS (DISK_SIDES + 2)

void main()
{
    vec3 p = v_pos_world;
    vec3 n = sm_facing_normal(p, v_normal_world, u_camera_pos);
    vec3 light_pos = u_light_sun != 0 ? p + u_light_z : u_light_pos;
    if (dot(p - light_pos, u_light_z) >= 0.0) {  // behind the light
        o_irradiance = 0.0;
        return;
    }
    vec3 poly[MAX_VERTS];
    int count;
    if (u_light_disk != 0) {
        count = DISK_SIDES;
        // the polygon of the same area as the disk
        float r = u_light_radius * sqrt(6.28318530718 / (DISK_SIDES * sin(6.28318530718 / DISK_SIDES)));
        for (int i = 0; i < DISK_SIDES; i++) {
            float a = 6.28318530718 * float(i) / DISK_SIDES;
            poly[i] = light_pos + r * (cos(a) * u_light_x + sin(a) * u_light_y) - p;
        }
    } else {
        count = 4;
        vec3 x = u_light_half_width * u_light_x, y = u_light_half_height * u_light_y;
        poly[0] = light_pos - x - y - p;
        poly[1] = light_pos + x - y - p;
        poly[2] = light_pos + x + y - p;
        poly[3] = light_pos - x + y - p;
    }
    // clip to the tangent plane, dot(n, r) >= 0 (Sutherland-Hodgman)
    vec3 clipped[MAX_VERTS];
    int kept = 0;
    for (int i = 0; i < count; i++) {
        vec3 a = poly[i], b = poly[(i + 1) % count];
        float da = dot(n, a), db = dot(n, b);
        if (da >= 0.0 && kept < MAX_VERTS)
            clipped[kept++] = a;
        if ((da >= 0.0) != (db >= 0.0) && kept < MAX_VERTS)
            clipped[kept++] = a + (b - a) * (da / (da - db));
    }
    float e = 0.0;
    for (int i = 0; i < kept; i++) {
        vec3 a = normalize(clipped[i]), b = normalize(clipped[(i + 1) % kept]);
        vec3 c = cross(a, b);
        float len = length(c);
        if (len > 1e-7)
            e += atan(len, dot(a, b)) * dot(n, c / len);  // the angle, accurate when small
    }
    o_irradiance = 0.5 * abs(e);
}
