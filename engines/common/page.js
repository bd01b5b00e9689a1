// What every engine's page shares (docs/engines.md): the reply's image as
// base64 of float32 rows, top row first, and the frame times.

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
