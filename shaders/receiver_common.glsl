// The camera passes' shared part (receiver.frag, penumbra_mask.frag): the
// cascades' uniforms and each cascade's weight at a view depth
// (docs/cascades.md).
uniform vec3 u_camera_pos;
uniform vec3 u_camera_fwd;
uniform int u_cascade;        // this pass's
uniform int u_cascade_count;  // 1: one map, weight 1 everywhere
uniform float u_cascade_z[SM_CASCADES_MAX + 1];  // the slices' view depths
uniform float u_cascade_band[SM_CASCADES_MAX];   // each slice's blend band, at its far end

// Cascade c's weight at view depth z: 1 inside its slice, falling to 0
// over its band (where c + 1 rises), rising over the band of c - 1.
float cascade_weight(int c, float z)
{
    float lo = u_cascade_z[c], hi = u_cascade_z[c + 1];
    float w_in = c > 0 && u_cascade_band[c - 1] > 0.0 ? clamp(1.0 - (lo - z) / u_cascade_band[c - 1], 0.0, 1.0)
                                                      : float(z > lo || c == 0);
    float w_out = u_cascade_band[c] > 0.0 ? clamp((hi - z) / u_cascade_band[c], 0.0, 1.0) : float(z <= hi);
    return w_in * w_out;
}

// This pass's weight at world point p.
float cascade_weight_at(vec3 p)
{
    return u_cascade_count > 1 ? cascade_weight(u_cascade, dot(p - u_camera_pos, u_camera_fwd)) : 1.0;
}
