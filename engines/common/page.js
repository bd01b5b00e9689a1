// What every engine's page shares (docs/engines.md): the reply's image as
// base64 of float32 rows, top row first, the frame times, and the camera
// distance's GLSL.

// rows: a Float32Array of h rows of w * channels floats, bottom row first
// (GL's readPixels); channel c of each pixel is copied to out at offset,
// top row first.
export function takeChannel(rows, w, h, channels, c, out, offset) {
    for (let y = 0; y < h; y++) {
        const src = (h - 1 - y) * w * channels, dst = offset + y * w;
        for (let x = 0; x < w; x++)
            out[dst + x] = rows[src + x * channels + c];
    }
}

// How an adapter renders output `what` of a request (harness/engine/engine.h):
// with which of its two materials (the shadow term, or the engine's lit
// diffuse one), with the receivers' shadows on or off, and which channel
// of the float target (shadow factor, camera distance) it reads.
export function outputPass(what) {
    const passes = { shadow: ['shadow', true, 0], distance: ['shadow', true, 1], lit: ['lit', true, 0],
                     unlit: ['lit', false, 0] };
    if (!(what in passes))
        throw new Error(`no output ${what}`);
    const [material, receive, channel] = passes[what];
    return { material, receive, channel };
}

export function base64(floats) {
    const bytes = new Uint8Array(floats.buffer, floats.byteOffset, floats.byteLength);
    let s = '';
    for (let i = 0; i < bytes.length; i += 0x8000)
        s += String.fromCharCode.apply(null, bytes.subarray(i, i + 0x8000));
    return btoa(s);
}

// The WebGL2 context's renderer string (UNMASKED where the browser gives it).
export function rendererString(gl) {
    const info = gl.getExtension('WEBGL_debug_renderer_info');
    return String(info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER));
}

// Milliseconds of each of `frames` frames after `warmup` untimed ones: one
// frame is draw(), then wait(), which returns once the frame is finished
// (a one-pixel readPixels of what it drew).
export function timeFrames(draw, wait, warmup, frames) {
    const ms = [];
    for (let i = 0; i < warmup + frames; i++) {
        const t0 = performance.now();
        draw();
        wait();
        if (i >= warmup)
            ms.push(performance.now() - t0);
    }
    return ms;
}

// A wait for timeFrames: one pixel of the bound framebuffer, read as float.
export function readOnePixel(gl) {
    const pixel = new Float32Array(4);
    return () => gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.FLOAT, pixel);
}

// The camera distance of the surface a pixel sees, for the coverage test
// against the ray tracer's: the pixel centre's exact ray cut with the plane
// of the triangle drawn there (a corner of it, flat, and its normal from the
// position's derivatives). The interpolated position itself is off by up to
// a third of a pixel on SwiftShader for triangles clipped at a near plane
// much closer than their size (sun_parallel_planes).
//
// The vertex shader's part: the flat varying sbCorner, set to the vertex's
// world position (the GLSL expression world).
export function distanceVertexGlsl(world) {
    return { declaration: 'flat varying vec3 sbCorner;', main: `sbCorner = ${world};` };
}

// The fragment shader's part: sbCorner and sbDistance(), given the names the
// shader has for the interpolated world position (world), the camera's
// world position (eye), the target's size in pixels (size, a vec2) and a
// matrix from clip space back (inverse): to world space (the inverse of
// projection times view), or, where the name of the view matrix is given
// (view), to view space (the inverse projection), the ray then turned to
// world space by the view's rotation. The caller declares the uniforms.
export function distanceGlsl({ world, eye, size, inverse, view = null }) {
    const ray = view ? `transpose(mat3(${view})) * (p.xyz / p.w)` : `p.xyz / p.w - ${eye}`;
    return `
flat varying vec3 sbCorner;
float sbDistance() {
    vec4 p = ${inverse} * vec4(2.0 * gl_FragCoord.xy / ${size} - 1.0, 0.0, 1.0);
    vec3 ray = normalize(${ray});
    vec3 n = cross(dFdx(${world}), dFdy(${world}));
    return dot(sbCorner - ${eye}, n) / dot(ray, n);
}`;
}
