// The PlayCanvas adapter (docs/engines.md): renders a cell with PlayCanvas's
// own glTF loader, lights and shadow renderer and hands back its shadow
// factor alone.
//
// The set-up choices a PlayCanvas user has to make, made as shadowbench's
// own passes make them, and where PlayCanvas does not let them be made so:
// - clustered lighting off (scene.clusteredLightingEnabled = false): the
//   forward path, where each light has its own map, shadowType and
//   shadowResolution (clustered, a spot's shadow goes to a shared atlas at
//   a size set by its size on screen, with one type for every light);
// - the scene loaded as a container asset (GlbParser), its camera the first
//   one in the hierarchy with its vertical fov, aspect W/H; the file's own
//   KHR_lights_punctual light removed (the request's light is the scene's);
// - flat normals where the file has none: the loader gives such a mesh
//   averaged vertex normals and its material flatShading (the triangle's
//   winding normal from the position's derivatives, in the fragment
//   shader), and the adapter's materials keep that flag: normalOffsetBias
//   offsets along it;
// - both faces drawn, into the map and by the camera (material.cull =
//   CULLFACE_NONE); shadow_side=engine keeps the file's culling, which the
//   caster pass uses too (a one-sided plate seen from behind the light is
//   not in the map);
// - an area light becomes a spot light at its centre looking along its -Z
//   (the entity's -Y, PlayCanvas's spot direction; the entity's -Z, which is
//   the shadow camera's up, the light's +Y). PlayCanvas's spot shadow
//   camera is symmetric, its fov twice outerConeAngle, and the light reaches
//   only inside the cone (the shadow is not evaluated outside it), so the
//   cone is the smallest about the light's axis that holds every point of
//   the scene inside shadowbench's fitted window (the request's cone_tan:
//   innerConeAngle; outerConeAngle 0.1 % wider in tangent, for smoothstep's
//   sake), and its square map covers more than the window: coarser texels,
//   by the factors the reply's texel_ratio gives. Its near and far are
//   range / 1000 and range; the range is the distance of the fitted
//   frustum's farthest point in that cone, 1 % beyond (the linear falloff
//   must leave every scored point lit);
// - a sun becomes a directional light with one cascade, whose map
//   PlayCanvas fits itself: a square about the bounding sphere of the view
//   frustum from the camera's near plane to shadowDistance, snapped to
//   texels, its depth range the casters' boxes. shadowDistance is the
//   farthest depth the camera sees (the request's view_far, as
//   shadowbench's own fit takes it), 0.1 % beyond;
// - PCSS's penumbraSize from the scene's light (light_size_scale times):
//   the sun's tan(half-angle); an area light's 3 mapSize a / (2 near far),
//   a its disk's radius or its rect's mean half-side, near and far the
//   fitted frustum's (techniques/playcanvas.c, docs/engines.md).
//
// The shadow term alone: a StandardMaterial whose shader chunks
// (material.shaderChunks, 2.x's API) keep PlayCanvas's own
// lightFunctionLightPS with one line added, which copies `shadow` (the
// light's shadow factor, after shadowIntensity, as it multiplies dAtten)
// to a global, and replace outputPS (empty by default, after tone mapping
// and gamma) to write it and the camera distance to a float target, with
// no blending.
import * as pc from 'playcanvas';
import { base64, distanceGlsl, distanceVertexGlsl, outputPass, readOnePixel, rendererString, takeChannel,
         timeFrames } from '../common/page.js';

const TYPES = {
    playcanvas_pcf1: { '32f': pc.SHADOW_PCF1_32F, '16f': pc.SHADOW_PCF1_16F },
    playcanvas_pcf3: { '32f': pc.SHADOW_PCF3_32F, '16f': pc.SHADOW_PCF3_16F },
    playcanvas_pcf5: { '32f': pc.SHADOW_PCF5_32F, '16f': pc.SHADOW_PCF5_16F },
    playcanvas_vsm: { '32f': pc.SHADOW_VSM_32F, '16f': pc.SHADOW_VSM_16F },
    playcanvas_pcss: { '32f': pc.SHADOW_PCSS_32F },
};
const BLUR_MODES = { gaussian: pc.BLUR_GAUSSIAN, box: pc.BLUR_BOX };

let app = null, device = null, gl = null, version = null;

export async function install() {
    const canvas = document.getElementById('canvas');
    app = new pc.Application(canvas, { graphicsDeviceOptions: {
        antialias: false, alpha: false, premultipliedAlpha: false, preserveDrawingBuffer: false, stencil: false,
        powerPreference: 'high-performance' } });
    device = app.graphicsDevice;
    gl = device.gl;
    if (!(gl instanceof WebGL2RenderingContext))
        throw new Error('no WebGL2');
    if (!device.textureFloatRenderable)
        throw new Error('no EXT_color_buffer_float: float targets cannot be read back');
    /* frames are drawn when a cell asks (app.start() would draw on every animation frame) */
    app.setCanvasFillMode(pc.FILLMODE_NONE);
    app.setCanvasResolution(pc.RESOLUTION_FIXED, canvas.width, canvas.height);
    app.scene.clusteredLightingEnabled = false;
    app.scene.ambientLight = new pc.Color(0, 0, 0);
    version = `${pc.version} (${pc.revision})`;
}

// The shadow-term material's chunks. The camera distance, for the coverage
// test (engines/common/page.js), from PlayCanvas's world position, the
// camera's position and the inverse view-projection. Only the forward
// pass: the caster pass shares the material.
const CORNER = distanceVertexGlsl('vPositionW');
const VS_DECLARATION = `
#ifdef FORWARD_PASS
${CORNER.declaration}
#endif`;
const VS_END = `
#ifdef FORWARD_PASS
${CORNER.main}
#endif`;
const DISTANCE_GLSL = distanceGlsl({ world: 'vPositionW', eye: 'sbEye', size: 'sbSize',
                                     inverse: 'sbInverseViewProjection' });
const PS_DECLARATION = `
#ifdef FORWARD_PASS
uniform mat4 sbInverseViewProjection;
uniform vec2 sbSize;
uniform vec3 sbEye;
float sbShadow = 1.0;${DISTANCE_GLSL}
#endif`;
const OUTPUT = `
gl_FragColor = vec4(sbShadow, sbDistance(), 0.0, 1.0);`;
const SHADOW_LINE = 'shadow = mix(1.0, shadow, light{i}_shadowIntensity);';

// PlayCanvas's own light function, the shadow factor kept as it is applied.
function lightFunction() {
    const chunk = pc.ShaderChunks.get(device, pc.SHADERLANGUAGE_GLSL).get('lightFunctionLightPS');
    if (!chunk || chunk.split(SHADOW_LINE).length !== 2)
        throw new Error("PlayCanvas's lightFunctionLightPS is not the one this adapter edits");
    return chunk.replace(SHADOW_LINE, `${SHADOW_LINE}\n\t\tsbShadow = shadow;`);
}

// A plain lit diffuse material: white, no specular, no fog, no tone mapping.
function diffuseMaterial(name, flat) {
    const m = new pc.StandardMaterial();
    m.name = name;
    m.diffuse = new pc.Color(1, 1, 1);
    m.specular = new pc.Color(0, 0, 0);
    m.useMetalness = false;
    m.useFog = false;
    m.useSkybox = false;
    m.useTonemap = false;
    m.blendType = pc.BLEND_NONE;
    m.flatShading = flat;
    return m;
}

function shadowTermMaterial(flat) {
    const m = diffuseMaterial('sb-shadow-term', flat);
    const chunks = m.getShaderChunks(pc.SHADERLANGUAGE_GLSL);
    chunks.set('litUserDeclarationVS', VS_DECLARATION);
    chunks.set('litUserMainEndVS', VS_END);
    chunks.set('litUserDeclarationPS', PS_DECLARATION);
    chunks.set('lightFunctionLightPS', lightFunction());
    chunks.set('outputPS', OUTPUT);
    m.shaderChunksVersion = pc.CHUNKAPI_2_8;
    m.update();
    return m;
}

let current = null;  // { url, asset, root, camera, meshes }

function loadContainer(url) {
    return new Promise((resolve, reject) => {
        app.assets.loadFromUrl(url, 'container',
                               (err, asset) => (err ? reject(new Error(String(err))) : resolve(asset)));
    });
}

// Releases a loaded scene: its entities, materials and meshes.
function release(asset, root, meshes) {
    root.destroy();
    for (const mi of meshes)
        for (const m of Object.values(mi.sbMaterials))
            m.destroy();
    app.assets.remove(asset);
    asset.unload();
}

async function load(url) {
    if (current && current.url === url)
        return current;
    if (current)  /* one scene at a time */
        release(current.asset, current.root, current.meshes);
    current = null;
    const asset = await loadContainer(url);
    const root = asset.resource.instantiateRenderEntity();
    /* the scene's light is the request's (KHR_lights_punctual too) */
    for (const l of root.findComponents('light'))
        l.entity.destroy();
    const camera = root.findComponents('camera')[0];
    if (!camera) {
        release(asset, root, []);
        throw new Error('the scene has no camera');
    }
    const meshes = [];
    for (const r of root.findComponents('render')) {
        r.castShadows = r.receiveShadows = true;
        for (const mi of r.meshInstances) {
            /* each mesh its own pair of materials, for the scene's life: the loader's flat shading (no
             * normals in the file) and culling (for shadow_side=engine) */
            const file = mi.material;
            mi.sbFileCull = file.cull;
            mi.sbMaterials = { shadow: shadowTermMaterial(file.flatShading),
                               lit: diffuseMaterial('sb-lit', file.flatShading) };
            meshes.push(mi);
        }
    }
    app.root.addChild(root);
    app.root.syncHierarchy();
    current = { url, asset, root, camera, meshes };
    return current;
}

const vec = (a) => new pc.Vec3(a[0], a[1], a[2]);
const DEG = 180 / Math.PI;

// PCSS's penumbraSize for the scene's light (docs/engines.md): where the
// engine's penumbra model equals the light's.
function penumbraSize(L, mapSize) {
    if (L.kind === 'directional')
        return Math.tan(L.half_angle);
    const a = L.shape === 'disk' ? L.radius : 0.25 * (L.size[0] + L.size[1]);
    return 3 * mapSize * a / (2 * L.near * L.far);
}

// The cell's shadow type, and what the light needs from the request,
// checked before anything is created.
function shadowType(technique, p, L) {
    if (!TYPES[technique])
        throw new Error(`PlayCanvas has no technique ${technique}`);
    const format = p.format ?? '32f', type = TYPES[technique][format];
    if (type === undefined)
        throw new Error(`PlayCanvas's ${technique} has no format ${format}`);
    if (L.kind === 'directional' && !(L.view_far > 0))
        throw new Error('the camera sees no geometry for the sun to shadow');
    if (L.kind !== 'directional' && !(L.cone_tan > 0))
        throw new Error('nothing in front of the light for its cone to hold');
    return type;
}

// The scene's light as PlayCanvas's nearest light, its shadow set up by the
// cell; nothing is left behind if PlayCanvas refuses the shadow type.
function makeLight(L, p, type, mapSize) {
    const entity = new pc.Entity('sb-light');
    try {
        const sun = L.kind === 'directional';
        entity.addComponent('light', { type: sun ? 'directional' : 'spot', color: new pc.Color(1, 1, 1),
                                       intensity: 1, castShadows: true, affectSpecularity: false,
                                       shadowResolution: mapSize });
        const light = entity.light;
        /* the entity's axes: x the light's, -y its direction (-z), -z the shadow camera's up (its +y) */
        const m = new pc.Mat4();
        m.data.set([L.x[0], L.x[1], L.x[2], 0, L.z[0], L.z[1], L.z[2], 0, -L.y[0], -L.y[1], -L.y[2], 0,
                    0, 0, 0, 1]);
        entity.setPosition(vec(L.eye));
        entity.setRotation(new pc.Quat().setFromMat4(m));
        light.shadowType = type;
        if (light.shadowType !== type)
            throw new Error(`PlayCanvas turned shadow type ${type} into ${light.shadowType} on this device`);
        if (sun) {
            light.numCascades = 1;
            light.cascadeBlend = 0;
            light.shadowDistance = L.view_far * 1.001;
        } else {
            const k = L.cone_tan;
            light.innerConeAngle = Math.atan(k) * DEG;
            light.outerConeAngle = Math.atan(k * 1.001) * DEG;
            light.range = 1.01 * L.far * Math.sqrt(1 + k * k);
        }
        if (p.bias !== undefined)
            light.shadowBias = p.bias;
        if (p.normal_bias !== undefined)
            light.normalOffsetBias = p.normal_bias;
        if (p.vsm_blur_size !== undefined) {
            light.vsmBlurSize = p.vsm_blur_size;
            light.vsmBlurMode = BLUR_MODES[p.vsm_blur_mode];
            light.vsmBias = p.vsm_bias;
        }
        if (p.light_size_scale !== undefined) {
            light.penumbraSize = p.light_size_scale * penumbraSize(L, mapSize);
            light.penumbraFalloff = p.penumbra_falloff;
            light.shadowSamples = p.shadow_samples;
            light.shadowBlockerSamples = p.shadow_blocker_samples;
        }
        app.root.addChild(entity);
        return entity;
    } catch (e) {
        entity.destroy();
        throw e;
    }
}

// The light's map's texel over shadowbench's fitted map's at the same map
// size, along the light's x and y (the request's window: l, r, b, t at
// near). A spot's square map spans its outer cone; the sun's is the square
// PlayCanvas fits about the view, 2 orthoHeight a side, read from its
// shadow camera after a frame through accessors PlayCanvas marks internal
// (LightComponent#light, CameraComponent#camera, Light#getRenderData: no
// public one says the fit); null where they no longer say it.
function texelRatio(L, entity, camera) {
    const [l, r, b, t] = L.window;
    let side;
    if (L.kind === 'directional') {
        const data = entity.light.light?.getRenderData?.(camera.camera, 0);
        side = 2 * data?.shadowCamera?.orthoHeight;
    } else {
        side = 2 * Math.tan(entity.light.outerConeAngle / DEG) * L.near;
    }
    return side > 0 && Number.isFinite(side) ? [side / (r - l), side / (t - b)] : null;
}

export async function render(req) {
    const L = req.light, p = req.params, { width: w, height: h } = req;
    const type = shadowType(req.technique, p, L);
    const { camera, meshes } = await load(req.sceneUrl);
    app.setCanvasResolution(pc.RESOLUTION_FIXED, w, h);
    const rows = new Float32Array(w * h * 4), out = new Float32Array(w * h * req.outputs.length);
    let light = null, color = null, target = null, ms = [], texel_ratio = null;
    try {
        camera.enabled = true;
        camera.aspectRatioMode = pc.ASPECT_MANUAL;
        camera.aspectRatio = w / h;
        camera.toneMapping = pc.TONEMAP_NONE;
        camera.gammaCorrection = pc.GAMMA_NONE;
        camera.clearColor = new pc.Color(1, -1, 0, 0);
        light = makeLight(L, p, type, req.map_size);
        color = new pc.Texture(device, { name: 'sb-target', width: w, height: h, format: pc.PIXELFORMAT_RGBA32F,
                                         mipmaps: false, minFilter: pc.FILTER_NEAREST,
                                         magFilter: pc.FILTER_NEAREST, addressU: pc.ADDRESS_CLAMP_TO_EDGE,
                                         addressV: pc.ADDRESS_CLAMP_TO_EDGE });
        target = new pc.RenderTarget({ name: 'sb-target', colorBuffer: color, depth: true, stencil: false });
        camera.renderTarget = target;
        app.root.syncHierarchy();
        const inverse = new pc.Mat4().mul2(camera.projectionMatrix, camera.viewMatrix).invert();
        const eye = camera.entity.getPosition();
        const use = (kind, receive) => {
            for (const mi of meshes) {
                const m = mi.sbMaterials[kind];
                m.cull = p.shadow_side === 'engine' ? mi.sbFileCull : pc.CULLFACE_NONE;
                m.setParameter('sbInverseViewProjection', inverse.data);
                m.setParameter('sbSize', [w, h]);
                m.setParameter('sbEye', [eye.x, eye.y, eye.z]);
                mi.material = m;
                mi.receiveShadow = receive;
            }
        };
        const draw = () => {
            app.update(0);
            app.render();
        };
        /* the target's framebuffer, bound by hand: Texture#read, the public readback, is asynchronous (a
         * pixel-pack buffer whose fence it polls every 16 ms), which a frame's time cannot wait on, and
         * GraphicsDevice#setRenderTarget only records the target (updateBegin, which binds it, is internal) */
        const bind = () => device.setFramebuffer(target.impl._glFrameBuffer);
        const pixel = readOnePixel(gl);
        const wait = () => {
            bind();
            pixel();
        };
        for (let k = 0; k < req.outputs.length; k++) {
            const pass = outputPass(req.outputs[k]);
            use(pass.material, pass.receive);
            draw();  /* untimed: programs compiled, the shadow map allocated */
            wait();
            if (k === 0)
                ms = timeFrames(draw, wait, req.warmup, req.frames);
            bind();
            gl.readPixels(0, 0, w, h, gl.RGBA, gl.FLOAT, rows);
            takeChannel(rows, w, h, 4, pass.channel, out, k * w * h);
        }
        texel_ratio = texelRatio(L, light, camera);
    } finally {
        camera.renderTarget = null;
        camera.enabled = false;
        target?.destroy();
        color?.destroy();
        light?.destroy();
    }
    return { version, renderer: rendererString(gl), ms, data: base64(out), ...(texel_ratio && { texel_ratio }) };
}

window.sbRender = render;
