// Reading Filament's frames back as float (docs/engines.md, "Float readback
// and the camera distance"). Filament's JS Renderer cannot read back an
// RGBA32F colour or a DEPTH32F depth texture, so the WebGL calls Filament
// makes are watched (which texture has which format, which framebuffer
// holds which textures), and after the frame its framebuffer is read with
// readPixels as float, and its depth with a small WebGL2 pass of this
// module's own (depth -> camera distance), every GL binding either touches
// saved first and restored after (Filament caches GL state). Filament's
// WebGL backend runs its commands in Engine.execute(), on the page's
// thread, so a frame is complete when that returns.

// Watches ctx (before Filament gets it): for each texture Filament
// allocates, its format and size, and for each framebuffer, which textures
// are attached, with a sequence number; a deleted texture or framebuffer
// is forgotten. find() gives the newest framebuffer holding a colour and a
// depth texture of the asked formats and size: the RenderTarget's.
export function watch(ctx) {
    const textures = new Map(), framebuffers = new Map();
    let seq = 0;
    const storage = ctx.texStorage2D;
    ctx.texStorage2D = function (target, levels, format, w, h) {
        storage.call(this, target, levels, format, w, h);
        if (target === this.TEXTURE_2D)
            textures.set(this.getParameter(this.TEXTURE_BINDING_2D), { format, w, h });
    };
    const attach = ctx.framebufferTexture2D;
    ctx.framebufferTexture2D = function (target, attachment, textarget, texture, level) {
        attach.call(this, target, attachment, textarget, texture, level);
        const fb = this.getParameter(target === this.READ_FRAMEBUFFER ? this.READ_FRAMEBUFFER_BINDING
                                                                        : this.DRAW_FRAMEBUFFER_BINDING);
        if (!fb)
            return;
        const entry = framebuffers.get(fb) || {};
        entry[attachment] = texture;
        entry.seq = ++seq;
        framebuffers.set(fb, entry);
    };
    const deleteTexture = ctx.deleteTexture;
    ctx.deleteTexture = function (texture) {
        deleteTexture.call(this, texture);
        textures.delete(texture);
    };
    const deleteFramebuffer = ctx.deleteFramebuffer;
    ctx.deleteFramebuffer = function (fb) {
        deleteFramebuffer.call(this, fb);
        framebuffers.delete(fb);
    };
    return {
        find(colorFormat, depthFormat, w, h) {
            let best = null;
            for (const [fb, e] of framebuffers) {
                const c = textures.get(e[ctx.COLOR_ATTACHMENT0]), d = textures.get(e[ctx.DEPTH_ATTACHMENT]);
                if (c && d && c.format === colorFormat && d.format === depthFormat && c.w === w && c.h === h &&
                    d.w === w && d.h === h && (!best || e.seq > best.seq))
                    best = { fb, depth: e[ctx.DEPTH_ATTACHMENT], seq: e.seq };
            }
            return best;
        },
    };
}

// Runs f with the GL state it may change saved first and restored after,
// exactly (Filament's backend caches its bindings and enables).
function withSavedState(g, f) {
    const enables = [g.BLEND, g.CULL_FACE, g.DEPTH_TEST, g.SCISSOR_TEST, g.STENCIL_TEST, g.POLYGON_OFFSET_FILL,
                     g.RASTERIZER_DISCARD, g.SAMPLE_ALPHA_TO_COVERAGE, g.SAMPLE_COVERAGE, g.DITHER];
    const packs = [g.PACK_ALIGNMENT, g.PACK_ROW_LENGTH, g.PACK_SKIP_PIXELS, g.PACK_SKIP_ROWS];
    const saved = {
        enabled: enables.map((e) => g.isEnabled(e)),
        read: g.getParameter(g.READ_FRAMEBUFFER_BINDING), draw: g.getParameter(g.DRAW_FRAMEBUFFER_BINDING),
        program: g.getParameter(g.CURRENT_PROGRAM), vao: g.getParameter(g.VERTEX_ARRAY_BINDING),
        viewport: g.getParameter(g.VIEWPORT), mask: g.getParameter(g.COLOR_WRITEMASK),
        active: g.getParameter(g.ACTIVE_TEXTURE), pack: g.getParameter(g.PIXEL_PACK_BUFFER_BINDING),
        packs: packs.map((p) => [p, g.getParameter(p)]),
    };
    g.activeTexture(g.TEXTURE0);
    saved.texture = g.getParameter(g.TEXTURE_BINDING_2D);
    saved.sampler = g.getParameter(g.SAMPLER_BINDING);
    try {
        g.bindBuffer(g.PIXEL_PACK_BUFFER, null);
        g.pixelStorei(g.PACK_ALIGNMENT, 4), g.pixelStorei(g.PACK_ROW_LENGTH, 0);
        g.pixelStorei(g.PACK_SKIP_PIXELS, 0), g.pixelStorei(g.PACK_SKIP_ROWS, 0);
        return f();
    } finally {
        g.bindTexture(g.TEXTURE_2D, saved.texture);
        g.bindSampler(0, saved.sampler);
        g.activeTexture(saved.active);
        for (const [p, v] of saved.packs)
            g.pixelStorei(p, v);
        g.bindBuffer(g.PIXEL_PACK_BUFFER, saved.pack);
        g.colorMask(...saved.mask);
        g.viewport(...saved.viewport);
        g.bindVertexArray(saved.vao);
        g.useProgram(saved.program);
        g.bindFramebuffer(g.READ_FRAMEBUFFER, saved.read);
        g.bindFramebuffer(g.DRAW_FRAMEBUFFER, saved.draw);
        enables.forEach((e, i) => (saved.enabled[i] ? g.enable(e) : g.disable(e)));
    }
}

// Runs read (its readPixels) with framebuffer fb bound for reading, the
// GL state restored after.
export function readFramebuffer(g, fb, read) {
    withSavedState(g, () => {
        g.bindFramebuffer(g.READ_FRAMEBUFFER, fb);
        read();
    });
}

// The depth buffer holds Filament's reversed Z in [0, 1], 0.5 - 0.5 z/w of
// the camera's GL projection P (Camera.getProjectionMatrix: an infinite far
// plane, so d = near / view depth), so view depth is P[3][2] / (P[2][2] +
// 1 - 2 d); the distance along the pixel centre's ray is that times the
// ray's length per unit of view depth, as the ground truth measures it.
// d = 0 is the cleared far plane: nothing seen (-1).
const DISTANCE_VS = `#version 300 es
void main() { gl_Position = vec4(vec2(gl_VertexID & 1, gl_VertexID >> 1) * 4.0 - 1.0, 0.0, 1.0); }`;
const DISTANCE_FS = `#version 300 es
precision highp float;
uniform highp sampler2D depth;
uniform vec2 size, tanHalf, projection;
out vec4 color;
void main() {
    float d = texelFetch(depth, ivec2(gl_FragCoord.xy), 0).r;
    vec2 p = (2.0 * gl_FragCoord.xy / size - 1.0) * tanHalf;
    float z = projection.y / (projection.x + 1.0 - 2.0 * d);
    color = vec4(d > 0.0 ? z * sqrt(1.0 + dot(p, p)) : -1.0, 0.0, 0.0, 1.0);
}`;

// The depth -> distance pass on context g: its program, sampler, and a
// float target per size. The pass reads a depth texture into out (w x h
// floats, bottom row first), given the camera's tan(yfov / 2) (tanY) and
// its projection's P[2][2] (p22) and P[3][2] (p32).
export function distanceReader(g) {
    const shader = (type, text) => {
        const s = g.createShader(type);
        g.shaderSource(s, text);
        g.compileShader(s);
        if (!g.getShaderParameter(s, g.COMPILE_STATUS))
            throw new Error(`the distance pass does not compile: ${g.getShaderInfoLog(s)}`);
        return s;
    };
    const program = g.createProgram();
    g.attachShader(program, shader(g.VERTEX_SHADER, DISTANCE_VS));
    g.attachShader(program, shader(g.FRAGMENT_SHADER, DISTANCE_FS));
    g.linkProgram(program);
    if (!g.getProgramParameter(program, g.LINK_STATUS))
        throw new Error(`the distance pass does not link: ${g.getProgramInfoLog(program)}`);
    const at = (n) => g.getUniformLocation(program, n);
    const uniforms = { depth: at('depth'), size: at('size'), tanHalf: at('tanHalf'), projection: at('projection') };
    const sampler = g.createSampler();  /* a depth texture read as values: no comparison, nearest */
    g.samplerParameteri(sampler, g.TEXTURE_COMPARE_MODE, g.NONE);
    g.samplerParameteri(sampler, g.TEXTURE_MIN_FILTER, g.NEAREST);
    g.samplerParameteri(sampler, g.TEXTURE_MAG_FILTER, g.NEAREST);
    const vao = g.createVertexArray();
    let target = null;
    return (depth, w, h, cam, out) => withSavedState(g, () => {
        if (!target || target.w !== w || target.h !== h) {
            if (target)
                g.deleteFramebuffer(target.fb), g.deleteTexture(target.tex);
            const tex = g.createTexture();
            g.bindTexture(g.TEXTURE_2D, tex);
            g.texStorage2D(g.TEXTURE_2D, 1, g.R32F, w, h);
            const fb = g.createFramebuffer();
            g.bindFramebuffer(g.DRAW_FRAMEBUFFER, fb);
            g.framebufferTexture2D(g.DRAW_FRAMEBUFFER, g.COLOR_ATTACHMENT0, g.TEXTURE_2D, tex, 0);
            target = { w, h, tex, fb };
        }
        g.bindFramebuffer(g.DRAW_FRAMEBUFFER, target.fb);
        for (const e of [g.BLEND, g.CULL_FACE, g.DEPTH_TEST, g.SCISSOR_TEST, g.STENCIL_TEST, g.RASTERIZER_DISCARD,
                         g.SAMPLE_ALPHA_TO_COVERAGE, g.SAMPLE_COVERAGE, g.POLYGON_OFFSET_FILL])
            g.disable(e);
        g.colorMask(true, true, true, true);
        g.viewport(0, 0, w, h);
        g.useProgram(program);
        g.bindVertexArray(vao);
        g.bindTexture(g.TEXTURE_2D, depth);
        g.bindSampler(0, sampler);
        g.uniform1i(uniforms.depth, 0);
        g.uniform2f(uniforms.size, w, h);
        g.uniform2f(uniforms.tanHalf, cam.tanY * w / h, cam.tanY);
        g.uniform2f(uniforms.projection, cam.p22, cam.p32);
        g.drawArrays(g.TRIANGLES, 0, 3);
        g.bindFramebuffer(g.READ_FRAMEBUFFER, target.fb);
        g.readPixels(0, 0, w, h, g.RED, g.FLOAT, out);
    });
}
