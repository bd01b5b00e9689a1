// The Filament adapter (docs/engines.md): renders a cell with Filament's
// WebAssembly build, its glTF loader (gltfio) and its own materials and
// shadow code, and hands back its shadow factor.
//
// Filament ships compiled materials only (no matc in its npm package), so
// there is no shadow-term material to write: the shadow factor is the
// ratio of two renders with gltfio's own material, one light and nothing
// else, the receivers' shadows on (lit) and off (unlit). Every term of a
// light is multiplied by the one visibility (docs/engines.md, "Filament":
// the argument, from the shaders Filament compiles), so lit / unlit is
// that visibility wherever the unshadowed render is lit; where it is not
// (N.L <= 0), Filament computes no visibility, and the factor is 1.
//
// Filament's JS bindings reach one shadow type, PCF (View::setShadowType
// and the soft and VSM options are not bound: techniques/filament.c), with
// the light's ShadowOptions, which 1.53.4 binds but cannot pass: its
// value_object has a field, `transform`, whose C++ type
// (filament::math::quatf, a float quaternion) the bindings never register,
// so LightManager.Builder.shadowOptions throws embind's UnboundTypeError.
// The adapter supplies that one binding type and nothing else; Filament's
// code, its glue's behaviour and every other binding are untouched
// (loadFilament, supplyTransformType; docs/engines.md, "ShadowOptions").
//
// The set-up choices a Filament user has to make, made as shadowbench's
// own passes make them:
// - the scene is loaded by gltfio; the file's KHR_lights_punctual light is
//   not added to the scene (the scene's light is the request's);
// - every material instance is gltfio's material as a white, fully rough
//   dielectric (baseColorFactor 1, metallicFactor 0: glTF's default
//   material is a metal, which has no diffuse term), no emissive, both
//   faces drawn and lit (culling off, double-sided: the normal turned to
//   face the camera, as the ground truth turns it), into the map too
//   (shadow_side=engine: gltfio's single-sided default, back faces culled);
// - flat normals where the file has none: gltfio computes them;
// - the file's camera (gltfio's): its vertical field of view, aspect W/H,
//   its near plane, its far plane at the scene's farthest corner, exposure
//   exactly 1 (setExposureDirect; Filament's default is a physical
//   camera), GL's pixel centres;
// - no indirect light (an IndirectLight of intensity 0 and zero irradiance:
//   without one Filament lights with a default), no post-processing (no
//   tone mapping, no sRGB encoding, no dithering, no AA), no SSAO, no fog,
//   no screen-space contact shadows (Filament's defaults);
// - an area light becomes a SPOT at its centre along its -Z, whose outer
//   cone is the smallest around that axis that holds shadowbench's fitted
//   window (Filament's spot map is the square around the cone:
//   ShadowMap::updatePunctual), its inner cone just inside it, its falloff
//   radius (the map's far plane) the fitted frustum's farthest corner;
// - a sun becomes a DIRECTIONAL light (a SUN would bend the light direction
//   towards the reflection) with Filament's own fit.
//
// Float readback: the view renders into a RenderTarget whose attachments
// are an RGBA32F colour and a DEPTH32F texture. Filament's JS Renderer
// cannot read them; the WebGL calls Filament makes are watched (which
// texture has which format, which framebuffer holds which textures), and
// after the frame the adapter reads that framebuffer with readPixels as
// float, and the depth with a small WebGL2 pass of its own (depth -> camera
// distance), every GL binding it touches restored (Filament caches GL
// state). Filament's WebGL backend runs its commands in Engine.execute(),
// on this thread, so the frame is complete when it returns.
/* global Filament */
import { base64, outputPass, rendererString, takeChannel, timeFrames } from '../common/page.js';


let gl = null, engine = null, renderer = null, view = null, version = null, tracker = null, reader = null;
let current = null;  // { url, asset, scene, camera, renderables }

// Keeps, for each texture Filament allocates, its format and size, and
// for each framebuffer, which textures are attached, with a sequence
// number: the newest framebuffer holding a colour and a depth texture of
// the asked formats and size is the RenderTarget's.
function watch(ctx) {
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
    return {
        find(colorFormat, depthFormat, w, h) {
            let best = null;
            for (const [fb, e] of framebuffers) {
                const c = textures.get(e[ctx.COLOR_ATTACHMENT0]), d = textures.get(e[ctx.DEPTH_ATTACHMENT]);
                if (c && d && c.format === colorFormat && d.format === depthFormat && c.w === w && c.h === h &&
                    d.w === w && d.h === h && ctx.isFramebuffer(fb) && (!best || e.seq > best.seq))
                    best = { fb, depth: e[ctx.DEPTH_ATTACHMENT], seq: e.seq };
            }
            return best;
        },
    };
}

// Runs f with the GL state it may change saved first and restored after,
// exactly (Filament's backend caches its bindings and enables).
function withSavedState(f) {
    const g = gl;
    const enables = [g.BLEND, g.CULL_FACE, g.DEPTH_TEST, g.SCISSOR_TEST, g.STENCIL_TEST, g.POLYGON_OFFSET_FILL,
                     g.RASTERIZER_DISCARD, g.SAMPLE_ALPHA_TO_COVERAGE, g.SAMPLE_COVERAGE, g.DITHER];
    const saved = {
        enabled: enables.map((e) => g.isEnabled(e)),
        read: g.getParameter(g.READ_FRAMEBUFFER_BINDING), draw: g.getParameter(g.DRAW_FRAMEBUFFER_BINDING),
        program: g.getParameter(g.CURRENT_PROGRAM), vao: g.getParameter(g.VERTEX_ARRAY_BINDING),
        viewport: g.getParameter(g.VIEWPORT), mask: g.getParameter(g.COLOR_WRITEMASK),
        active: g.getParameter(g.ACTIVE_TEXTURE), pack: g.getParameter(g.PIXEL_PACK_BUFFER_BINDING),
        packs: [g.PACK_ALIGNMENT, g.PACK_ROW_LENGTH, g.PACK_SKIP_PIXELS, g.PACK_SKIP_ROWS].map((p) => [p, g.getParameter(p)]),
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

// The depth buffer holds Filament's reversed Z in [0, 1], 0.5 - 0.5 z/w of
// the camera's GL projection P (Camera.getProjectionMatrix: an infinite far
// plane, so d = near / view depth), so view depth is P[3][2] / (P[2][2] +
// 1 - 2 d); the distance along the pixel centre's ray is that times the
// ray's length per unit of view depth, as the ground truth measures it.
// d = 0 is the cleared far plane: nothing seen.
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

// The depth -> distance pass: its program, sampler, and a float target per size.
function distanceReader() {
    const g = gl;
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
    return (depth, w, h, cam, out) => withSavedState(() => {
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

// Reads the colour of framebuffer fb as float RGBA rows, bottom row first.
function readColor(fb, x, y, w, h, out) {
    withSavedState(() => {
        gl.bindFramebuffer(gl.READ_FRAMEBUFFER, fb);
        gl.readPixels(x, y, w, h, gl.RGBA, gl.FLOAT, out);
    });
}

// Where the page finds Filament's glue (filament.js) and its wasm.
const GLUE_DIR = '/engines/filament/node_modules/filament/';

// The glue's embind type registration, a function of the Emscripten
// closure that registers a binding type and completes whatever waits for
// it. The one edit the adapter makes to the glue is to put it on the
// module, before its definition (hoisted: the whole closure sees it).
const REGISTER_TYPE = 'function registerType(rawType,registeredInstance,options={}){';
const EXPOSE_REGISTER_TYPE = 'Module.sbRegisterType=registerType;';

// Loads Filament's glue with registerType exposed (checked: it must be
// found exactly once, or this is not the glue the adapter edits), as the
// classic script it is, and initialises Filament.
async function loadFilament() {
    const text = await (await fetch(GLUE_DIR + 'filament.js')).text();
    const found = text.split(REGISTER_TYPE).length - 1;
    if (found !== 1)
        throw new Error(`filament.js defines embind's registerType ${found} times, not once: not the glue this ` +
                        'adapter edits');
    const script = document.createElement('script');
    script.text = text.replace(REGISTER_TYPE, () => EXPOSE_REGISTER_TYPE + REGISTER_TYPE);
    document.head.appendChild(script);  /* a classic script runs as it is added */
    const factory = window.Filament;
    if (typeof factory !== 'function')
        throw new Error('filament.js, edited, did not define Filament');
    /* run from text, the glue has no script address (document.currentScript.src) to find its wasm beside:
     * Emscripten's Module.locateFile says where */
    window.Filament = Object.assign((module = {}) => factory({ ...module, locateFile: (file) => GLUE_DIR + file }),
                                    factory);
    await new Promise((resolve) => Filament.init([], resolve));
}

// Filament's ShadowOptions at its defaults (include/filament/LightManager.h
// of 1.53.4, struct ShadowOptions; docs/engines.md), every field the JS
// bindings register: embind passes a value_object whole (a missing field
// throws), and the glue's own Filament.shadowOptions() leaves out lispsm,
// shadowBulbRadius and transform. transform is the identity quaternion,
// (x, y, z, w) = (0, 0, 0, 1); it turns a directional light's shadow
// direction. Passed as they are, these render every pixel as no
// ShadowOptions at all does (measured: docs/engines.md).
const SHADOW_OPTIONS = Object.freeze({
    mapSize: 1024, shadowCascades: 1, constantBias: 0.001, normalBias: 1, shadowFar: 0, shadowNearHint: 1,
    shadowFarHint: 100, stable: false, lispsm: true, polygonOffsetConstant: 0.5, polygonOffsetSlope: 2,
    screenSpaceContactShadows: false, stepCount: 8, maxShadowDistance: 0.3, shadowBulbRadius: 0.02,
    transform: Object.freeze([0, 0, 0, 1]),
});

// Supplies the binding type ShadowOptions waits for. Which raw type that
// is, embind's own UnboundTypeError says (its id: the bindings are built
// without RTTI); the adapter goes on only when exactly one is unbound.
// Registering it completes the value_object and replaces the methods left
// as unbound-type throwers (Builder._shadowOptions,
// LightManager._setShadowOptions). The type is a float quaternion (16
// bytes; measured: of 16 floats written, the getter's copy brings back
// the first 4, and the C++ struct ends there, 88 bytes; LightManager.h:
// `math::quatf transform`), passed as embind's generic binding of an
// unregistered class passes one: a pointer to a heap copy (the glue's
// own __embind_register_value_object and simpleReadValueFromPointer).
function supplyTransformType() {
    const probe = () => {
        const b = Filament.LightManager.Builder(Filament.LightManager$Type.DIRECTIONAL);
        try {
            b.shadowOptions(SHADOW_OPTIONS);
            return null;
        } catch (e) {
            if (!(e instanceof Filament.UnboundTypeError))
                throw e;
            return e.message;
        } finally {
            b.delete();
        }
    };
    const message = probe();
    if (message === null)
        return;  /* a build that binds it itself */
    const m = /due to unbound types: (.*)$/.exec(message);
    const types = m ? m[1].split(', ') : [];
    if (types.length !== 1 || !/^0x[0-9a-f]+$/.test(types[0]))
        throw new Error(`ShadowOptions waits for other binding types than one quaternion: ${message}`);
    const M = Filament, QUAT_BYTES = 16;
    M.sbRegisterType(parseInt(types[0], 16), {
        name: 'filament::math::quatf',
        argPackAdvance: 8,
        /* to C++: a heap copy, freed once the call has copied it (the caller's destructors) */
        toWireType(destructors, q) {
            if (!Array.isArray(q) || q.length !== 4 || !q.every(Number.isFinite))
                throw new TypeError('a quaternion is 4 numbers, (x, y, z, w)');
            const p = M._malloc(QUAT_BYTES);
            M.HEAPF32.set(q, p >> 2);  /* after _malloc, which may grow the heap */
            destructors.push(M._free, p);
            return p;
        },
        /* from C++: the getter's heap copy, read, then freed */
        fromWireType(p) {
            const q = Array.from(M.HEAPF32.subarray(p >> 2, (p >> 2) + 4));
            M._free(p);
            return q;
        },
        /* a 32-bit pointer, as the glue's simpleReadValueFromPointer reads one */
        readValueFromPointer(pointer) { return this.fromWireType(M.HEAP32[pointer >> 2]); },
        destructorFunction: null,
    });
    const still = probe();
    if (still !== null)
        throw new Error(`ShadowOptions still cannot be passed: ${still}`);
}

export async function install() {
    await loadFilament();
    supplyTransformType();
    const pkg = await (await fetch(GLUE_DIR + 'package.json')).json();
    version = pkg.version;
    const canvas = document.getElementById('canvas');
    /* the context Filament.Engine.create asks for (its defaults): getContext hands it back to Filament,
     * watched, with float colour targets enabled */
    const options = { majorVersion: 2, minorVersion: 0, antialias: false, depth: true, alpha: false };
    gl = canvas.getContext('webgl2', options);
    if (!gl)
        throw new Error('no WebGL2');
    if (!gl.getExtension('EXT_color_buffer_float'))
        throw new Error('no EXT_color_buffer_float: float targets cannot be read back');
    tracker = watch(gl);
    engine = Filament.Engine.create(canvas, options);
    if (engine.context !== gl)
        throw new Error('Filament made a WebGL context of its own: its frames cannot be read back');
    renderer = engine.createRenderer();
    view = engine.createView();
    view.setPostProcessingEnabled(false);
    view.setAntiAliasing(Filament.View$AntiAliasing.NONE);
    view.setAmbientOcclusion(Filament.View$AmbientOcclusion.NONE);
    reader = distanceReader();
}

// The asset's scene: its renderables, not its lights; gltfio's material
// instances made white, fully rough dielectrics, double-sided.
async function load(url) {
    if (current && current.url === url)
        return current;
    if (current)
        unload();
    const loader = engine.createAssetLoader();
    const bytes = new Uint8Array(await (await fetch(url)).arrayBuffer());
    const asset = loader.createAsset(bytes);
    if (!asset)
        throw new Error('gltfio cannot read the scene file');
    await new Promise((resolve) => asset.loadResources(resolve, null, url, 1));
    const cameras = asset.getCameraEntities();
    if (!cameras.length)
        throw new Error('the scene has no camera');
    const scene = engine.createScene();
    const rm = engine.getRenderableManager();
    const renderables = asset.getRenderableEntities();
    for (const e of renderables) {
        scene.addEntity(e);
        const inst = rm.getInstance(e);
        for (let k = 0, n = rm.getPrimitiveCount(inst); k < n; k++) {
            const mi = rm.getMaterialInstanceAt(inst, k);
            mi.setFloat4Parameter('baseColorFactor', [1, 1, 1, 1]);
            mi.setFloatParameter('metallicFactor', 0);
            mi.setFloatParameter('roughnessFactor', 1);
            mi.setFloat3Parameter('emissiveFactor', [0, 0, 0]);
        }
        inst.delete();
    }
    /* no indirect light: Filament lights a scene without one with a default */
    const ibl = Filament.IndirectLight.Builder().irradianceSh(1, new Float32Array([0, 0, 0])).intensity(0)
        .build(engine);
    scene.setIndirectLight(ibl);
    const camera = engine.getCameraComponent(cameras[0]);
    /* the file's near plane and yfov, as gltfio set them (its [1][1] is 1 / tan(yfov / 2)) */
    const materials = [];
    for (const e of renderables) {
        const inst = rm.getInstance(e);
        for (let k = 0, n = rm.getPrimitiveCount(inst); k < n; k++)
            materials.push(rm.getMaterialInstanceAt(inst, k));
        inst.delete();
    }
    current = { url, loader, asset, scene, ibl, renderables, materials, camera, near: camera.getNear(),
                tanY: 1 / camera.getCullingProjectionMatrix()[5] };
    return current;
}

function unload() {
    engine.destroyScene(current.scene);
    engine.destroyIndirectLight(current.ibl);
    current.loader.destroyAsset(current.asset);
    current.loader.delete();
    current = null;
}

const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];

// The cell's ShadowOptions: Filament's defaults, and the cell's parameters
// under Filament's names (techniques/filament.c); the map mapSize texels a
// side, which Filament clamps to [8, 2048] (LightManager::setShadowOptions).
function shadowOptions(p, mapSize) {
    return { ...SHADOW_OPTIONS, mapSize, constantBias: p.constant_bias, normalBias: p.normal_bias,
             polygonOffsetConstant: p.polygon_offset_constant, polygonOffsetSlope: p.polygon_offset_slope,
             lispsm: p.lispsm, stable: p.stable };
}

// The scene's light as Filament's nearest light, casting shadows with options.
function makeLight(L, options) {
    const entity = Filament.EntityManager.get().create();
    const ahead = [-L.z[0], -L.z[1], -L.z[2]];
    let b;
    if (L.kind === 'directional') {
        /* illuminance pi lux: a white Lambertian surface facing the light is 1 */
        b = Filament.LightManager.Builder(Filament.LightManager$Type.DIRECTIONAL).intensity(Math.PI);
    } else {
        const [l, r, bt, t] = L.window;
        /* the window's farthest corner from the axis: the cone holds the window */
        const corner = Math.hypot(Math.max(-l, r), Math.max(-bt, t));
        const outer = Math.atan(corner / L.near);
        /* the light reaches the fitted far plane's farthest corner, a little beyond (the least that lights
         * every scored point; ShadowMap::updateSpot, as read, also ends the map there) */
        const radius = L.far * Math.hypot(1, corner / L.near) * 1.01;
        /* SPOT: lumens / pi candela; a white Lambertian surface facing it at the frustum's middle depth is 1 */
        const middle = 0.5 * (L.near + L.far);
        b = Filament.LightManager.Builder(Filament.LightManager$Type.SPOT)
            .position(L.eye).falloff(radius).spotLightCone(outer * 0.999, outer)
            .intensity(Math.PI * Math.PI * middle * middle);
    }
    b.direction(ahead).color([1, 1, 1]).castShadows(true).shadowOptions(options);
    b.build(engine, entity);
    return entity;
}

// Filament's JS bindings (npm filament 1.53.4) bind neither View::setShadowType
// nor its soft or VSM options: a light's shadow is PCF, whatever the page asks.
function checkTechnique(technique) {
    if (technique !== 'filament_pcf')
        throw new Error(`Filament has no technique ${technique}`);
}

// The distance from eye to the farthest corner of box, a little beyond.
function farthestCorner(box, eye) {
    let d = 0;
    for (let k = 0; k < 8; k++) {
        const c = [k & 1 ? box.max[0] : box.min[0], k & 2 ? box.max[1] : box.min[1], k & 4 ? box.max[2] : box.min[2]];
        d = Math.max(d, Math.hypot(c[0] - eye[0], c[1] - eye[1], c[2] - eye[2]));
    }
    return 1.01 * d;
}

export async function render(req) {
    const { width: w, height: h } = req;
    const { scene, camera, renderables } = await load(req.sceneUrl);
    checkTechnique(req.technique);
    /* shadow_side: both faces (double-sided, not culled), or gltfio's default for glTF's default material
     * (single-sided, back faces culled, into the map too) */
    const both = req.params.shadow_side !== 'engine';
    for (const mi of current.materials) {
        mi.setDoubleSided(both);
        mi.setCullingMode(both ? Filament.CullingMode.NONE : Filament.CullingMode.BACK);
    }
    /* the file's vertical field of view, aspect W/H; the far plane at the scene's farthest corner: gltfio's
     * for a file with no zfar is 1e8, with which Filament's directional shadow, fitted to the view
     * frustum's far end (shadowFar 0), casts nothing */
    const far = farthestCorner(current.asset.getBoundingBox(), camera.getPosition());
    camera.setProjectionFov(360 / Math.PI * Math.atan(current.tanY), w / h, current.near, far,
                            Filament.Camera$Fov.VERTICAL);
    const P = camera.getProjectionMatrix();
    const cam = { tanY: current.tanY, p22: P[10], p32: P[14] };
    camera.setExposureDirect(1.0);
    view.setCamera(camera);
    view.setScene(scene);
    view.setViewport([0, 0, w, h]);

    const light = makeLight(req.light, shadowOptions(req.params, req.map_size));
    scene.addEntity(light);
    const Tex = Filament.Texture, U = Filament.Texture$Usage;
    const color = Tex.Builder().width(w).height(h).levels(1).sampler(Filament.Texture$Sampler.SAMPLER_2D)
        .format(Filament.Texture$InternalFormat.RGBA32F).usage(U.COLOR_ATTACHMENT.value | U.SAMPLEABLE.value)
        .build(engine);
    const depth = Tex.Builder().width(w).height(h).levels(1).sampler(Filament.Texture$Sampler.SAMPLER_2D)
        .format(Filament.Texture$InternalFormat.DEPTH32F).usage(U.DEPTH_ATTACHMENT.value | U.SAMPLEABLE.value)
        .build(engine);
    const target = Filament.RenderTarget.Builder().texture(Filament.RenderTarget$AttachmentPoint.COLOR, color)
        .texture(Filament.RenderTarget$AttachmentPoint.DEPTH, depth).build(engine);
    view.setRenderTarget(target);
    renderer.setClearOptions({ clearColor: [0, 0, 0, 0], clear: true, discard: true });

    const rm = engine.getRenderableManager();
    const receive = (on) => {
        for (const e of renderables) {
            const inst = rm.getInstance(e);
            rm.setReceiveShadows(inst, on);
            rm.setCastShadows(inst, true);
            inst.delete();
        }
    };
    let gpu = null;
    const draw = () => {
        renderer.renderStandaloneView(view);
        engine.execute();
        if (!gpu) {
            gpu = tracker.find(gl.RGBA32F, gl.DEPTH_COMPONENT32F, w, h);
            if (!gpu)
                throw new Error("the RenderTarget's WebGL framebuffer was not found");
        }
    };
    const pixel = new Float32Array(4);
    const wait = () => readColor(gpu.fb, 0, 0, 1, 1, pixel);
    const n = w * h;
    const rows = { lit: null, unlit: null, distance: null };
    const want = new Set(req.outputs);
    /* the renders the outputs need: the shadow factor is lit / unlit */
    const renders = [];
    if (want.has('shadow') || want.has('lit'))
        renders.push('lit');
    if (want.has('shadow') || want.has('unlit'))
        renders.push('unlit');
    if (!renders.length)
        renders.push('lit');
    let ms = [];
    try {
        for (let k = 0; k < renders.length; k++) {
            receive(outputPass(renders[k]).receive);
            draw();  /* untimed: programs compiled, the shadow map allocated */
            wait();
            if (k === 0)
                ms = timeFrames(draw, wait, req.warmup, req.frames);
            rows[renders[k]] = new Float32Array(n * 4);
            readColor(gpu.fb, 0, 0, w, h, rows[renders[k]]);
            if (k === 0 && want.has('distance')) {
                rows.distance = new Float32Array(n);
                reader(gpu.depth, w, h, cam, rows.distance);
            }
        }
    } finally {
        view.setRenderTarget(null);
        engine.destroyRenderTarget(target);
        engine.destroyTexture(color);
        engine.destroyTexture(depth);
        scene.remove(light);
        engine.destroyEntity(light);
    }
    const out = new Float32Array(n * req.outputs.length);
    req.outputs.forEach((what, k) => {
        if (what === 'lit' || what === 'unlit')
            takeChannel(rows[what], w, h, 4, 0, out, k * n);
        else if (what === 'distance')
            takeChannel(rows.distance, w, h, 1, 0, out, k * n);
        else if (what === 'shadow')
            takeChannel(shadowFactor(rows.lit, rows.unlit, n), w, h, 1, 0, out, k * n);
        else
            throw new Error(`no output ${what}`);
    });
    return { version, renderer: rendererString(gl), ms, data: base64(out) };
}

// lit / unlit per pixel (red channel: the light and material are white);
// 1 where the unshadowed render is dark: Filament evaluates no visibility
// where N.L <= 0.
function shadowFactor(lit, unlit, n) {
    const v = new Float32Array(n);
    for (let i = 0; i < n; i++)
        v[i] = unlit[4 * i] > 0 ? lit[4 * i] / unlit[4 * i] : 1;
    return v;
}

window.sbRender = render;
