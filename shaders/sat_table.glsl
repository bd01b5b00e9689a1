// The summed-area table a shader builds or reads (sat_build.comp, sat.glsl):
// SAT_CHANNELS 2 (the default) is the moments_sat product, 4 the msm_sat
// product. SAT_UVEC is an entry as stored, SAT_IVEC and SAT_VEC its signed
// and float forms, SAT_BINDING its storage-buffer binding, SAT_TABLE its
// fields in the block (format, scale, max_box_texels). The includer
// declares the buffer (read-write or readonly):
//     layout(std430, binding = SAT_BINDING) buffer SatBuffer { SAT_UVEC sat[]; };
#ifndef SAT_CHANNELS
#define SAT_CHANNELS 2
#endif
#if SAT_CHANNELS == 4
#define SAT_UVEC uvec4
#define SAT_IVEC ivec4
#define SAT_VEC vec4
#define SAT_BINDING SM_BINDING_MSM_SAT
#define SAT_TABLE sm.sat[SM_SAT_SLOT_MSM_SAT]
#else
#define SAT_UVEC uvec2
#define SAT_IVEC ivec2
#define SAT_VEC vec2
#define SAT_BINDING SM_BINDING_MOMENTS_SAT
#define SAT_TABLE sm.sat[SM_SAT_SLOT_MOMENTS_SAT]
#endif
