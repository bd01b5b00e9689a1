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
//   the scene inside shadowbench's fitted window (innerConeAngle;
//   outerConeAngle 0.1 % wider in tangent, for smoothstep's sake), and its
//   square map covers more than the window: coarser texels, by the factors
//   docs/engines.md gives per scene. Its near and far are range / 1000 and
//   range; the range is the distance of the fitted frustum's farthest
//   point in that cone, 1 % beyond (the linear falloff must leave every
//   scored point lit);
// - a sun becomes a directional light with one cascade, whose map
//   PlayCanvas fits itself: a square about the bounding sphere of the view
//   frustum from the camera's near plane to shadowDistance, snapped to
//   texels, its depth range the casters' boxes. shadowDistance is the
//   farthest depth the camera sees (the geometry clipped to the view
//   frustum, as shadowbench's own fit takes it), 0.1 % beyond;
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

let current = null;  // { url, asset, root, camera, meshes, triangles }

function loadContainer(url) {
    return new Promise((resolve, reject) => {
        app.assets.loadFromUrl(url, 'container',
                               (err, asset) => (err ? reject(new Error(String(err))) : resolve(asset)));
    });
}

// The scene's triangles in world space, 9 floats each: what the spot's cone
// must hold, what the sun's shadowDistance must reach.
function worldTriangles(meshInstances) {
    const out = [];
    const p = new pc.Vec3();
    for (const mi of meshInstances) {
        const positions = [], indices = [];
        const n = mi.mesh.getPositions(positions);
        if (!mi.mesh.getIndices(indices))
            for (let i = 0; i < n; i++)
                indices.push(i);
        const world = mi.node.getWorldTransform();
        const v = [];
        for (let i = 0; i < n; i++) {
            world.transformPoint(p.set(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]), p);
            v.push(p.x, p.y, p.z);
        }
        for (const i of indices)
            out.push(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
    }
    return Float32Array.from(out);
}

async function load(url) {
    if (current && current.url === url)
        return current;
    if (current) {  /* one scene at a time: its entities, materials and meshes go with it */
        current.root.destroy();
        for (const mi of current.meshes)
            for (const m of Object.values(mi.sbMaterials))
                m.destroy();
        app.assets.remove(current.asset);
        current.asset.unload();
    }
    current = null;
    const asset = await loadContainer(url);
    const root = asset.resource.instantiateRenderEntity();
    /* the scene's light is the request's (KHR_lights_punctual too) */
    for (const l of root.findComponents('light'))
        l.entity.destroy();
    const camera = root.findComponents('camera')[0];
    if (!camera)
        throw new Error('the scene has no camera');
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
    current = { url, asset, root, camera, meshes, triangles: worldTriangles(meshes) };
    return current;
}

// The farthest view depth of the scene's geometry inside the camera's
// frustum (near plane and sides; its far plane aside), as shadowbench's
// own sun fit takes it (harness/scene/light_frustum.c, see()).
function farthestSeen(triangles, camera, aspect) {
    const w = camera.entity.getWorldTransform();
    const eye = w.getTranslation(new pc.Vec3());
    const x = w.getX(new pc.Vec3()).normalize(), y = w.getY(new pc.Vec3()).normalize();
    const f = w.getZ(new pc.Vec3()).normalize().mulScalar(-1);
    const ty = Math.tan(0.5 * camera.fov * pc.math.DEG_TO_RAD), tx = ty * aspect;
    /* planes n . p >= d, normals inwards: near, top, bottom, right, left */
    const planes = [[f, f.dot(eye) + camera.nearClip]];
    for (const [axis, t] of [[y, ty], [y.clone().mulScalar(-1), ty], [x, tx], [x.clone().mulScalar(-1), tx]]) {
        const n = f.clone().mulScalar(t).sub(axis);
        planes.push([n, n.dot(eye)]);
    }
    let far = -Infinity;
    for (let t = 0; t < triangles.length; t += 9) {
        let poly = [0, 1, 2].map((k) => new pc.Vec3(triangles[t + 3 * k], triangles[t + 3 * k + 1],
                                                      triangles[t + 3 * k + 2]));
        for (const [n, d] of planes) {
            const next = [];
            for (let i = 0; i < poly.length; i++) {
                const a = poly[i], b = poly[(i + 1) % poly.length];
                const sa = n.dot(a) - d, sb = n.dot(b) - d;
                if (sa >= 0)
                    next.push(a);
                if ((sa >= 0) !== (sb >= 0))
                    next.push(new pc.Vec3().lerp(a, b, sa / (sa - sb)));
            }
            poly = next;
        }
        for (const q of poly)
            far = Math.max(far, f.dot(q) - f.dot(eye));
    }
    if (!(far > 0))
        throw new Error('the camera sees no geometry for the sun to shadow');
    return far;
}

const vec = (a) => new pc.Vec3(a[0], a[1], a[2]);
const DEG = 180 / Math.PI;

// The tangent of the smallest cone about the spot's axis that holds every
// point of the scene inside shadowbench's fitted window: each triangle in
// the light's frame, clipped to the front of its near plane, projected,
// clipped to the window (at unit depth); the farthest corner from the axis
// (a convex polygon's farthest point is a corner). At most the window's
// farthest corner.
function spotCone(triangles, L) {
    const [l, r, b, t] = L.window.map((v) => v / L.near);
    const dot = (a, i) => a[0] * (triangles[i] - L.eye[0]) + a[1] * (triangles[i + 1] - L.eye[1]) +
                          a[2] * (triangles[i + 2] - L.eye[2]);
    /* half-planes a u + b v <= c of the window */
    const edges = [[-1, 0, -l], [1, 0, r], [0, -1, -b], [0, 1, t]];
    let k = 0;
    for (let i = 0; i < triangles.length; i += 9) {
        let poly = [0, 3, 6].map((o) => [dot(L.x, i + o), dot(L.y, i + o), -dot(L.z, i + o)]);
        const front = [];
        for (let j = 0; j < 3; j++) {
            const a = poly[j], c = poly[(j + 1) % 3], ia = a[2] >= L.near, ic = c[2] >= L.near;
            if (ia)
                front.push(a);
            if (ia !== ic) {
                const s = (L.near - a[2]) / (c[2] - a[2]);
                front.push([a[0] + s * (c[0] - a[0]), a[1] + s * (c[1] - a[1]), L.near]);
            }
        }
        poly = front.map(([x, y, d]) => [x / d, y / d]);
        for (const [eu, ev, ec] of edges) {
            const next = [];
            for (let j = 0; j < poly.length; j++) {
                const a = poly[j], c = poly[(j + 1) % poly.length];
                const sa = ec - eu * a[0] - ev * a[1], sc = ec - eu * c[0] - ev * c[1];
                if (sa >= 0)
                    next.push(a);
                if ((sa >= 0) !== (sc >= 0))
                    next.push([a[0] + (c[0] - a[0]) * sa / (sa - sc), a[1] + (c[1] - a[1]) * sa / (sa - sc)]);
            }
            poly = next;
        }
        for (const [u, v] of poly)
            k = Math.max(k, Math.hypot(u, v));
    }
    return k;
}

// PCSS's penumbraSize for the scene's light (docs/engines.md): where the
// engine's penumbra model equals the light's.
function penumbraSize(L, mapSize) {
    if (L.kind === 'directional')
        return Math.tan(L.half_angle);
    const a = L.shape === 'disk' ? L.radius : 0.25 * (L.size[0] + L.size[1]);
    return 3 * mapSize * a / (2 * L.near * L.far);
}

// The scene's light as PlayCanvas's nearest light, its shadow set up by the cell.
function makeLight(L, p, technique, mapSize, triangles, far) {
    const want = TYPES[technique][p.format ?? '32f'];
    const entity = new pc.Entity('sb-light');
    const sun = L.kind === 'directional';
    entity.addComponent('light', { type: sun ? 'directional' : 'spot', color: new pc.Color(1, 1, 1), intensity: 1,
                                   castShadows: true, affectSpecularity: false, shadowResolution: mapSize });
    const light = entity.light;
    /* the entity's axes: x the light's, -y its direction (-z), -z the shadow camera's up (its +y) */
    const m = new pc.Mat4();
    m.data.set([L.x[0], L.x[1], L.x[2], 0, L.z[0], L.z[1], L.z[2], 0, -L.y[0], -L.y[1], -L.y[2], 0, 0, 0, 0, 1]);
    entity.setPosition(vec(L.eye));
    entity.setRotation(new pc.Quat().setFromMat4(m));
    light.shadowType = want;
    if (light.shadowType !== want)
        throw new Error(`PlayCanvas turned shadow type ${want} into ${light.shadowType} on this device`);
    if (sun) {
        light.numCascades = 1;
        light.cascadeBlend = 0;
        light.shadowDistance = far * 1.001;
    } else {
        const k = spotCone(triangles, L);
        if (!(k > 0))
            throw new Error('nothing in front of the light for its cone to hold');
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
}

export async function render(req) {
    if (!TYPES[req.technique])
        throw new Error(`PlayCanvas has no technique ${req.technique}`);
    const p = req.params, { width: w, height: h } = req;
    const { camera, meshes, triangles } = await load(req.sceneUrl);
    app.setCanvasResolution(pc.RESOLUTION_FIXED, w, h);
    camera.enabled = true;
    camera.aspectRatioMode = pc.ASPECT_MANUAL;
    camera.aspectRatio = w / h;
    camera.toneMapping = pc.TONEMAP_NONE;
    camera.gammaCorrection = pc.GAMMA_NONE;
    camera.clearColor = new pc.Color(1, -1, 0, 0);
    const far = req.light.kind === 'directional' ? farthestSeen(triangles, camera, w / h) : 0;
    const light = makeLight(req.light, p, req.technique, req.map_size, triangles, far);
    const color = new pc.Texture(device, { name: 'sb-target', width: w, height: h, format: pc.PIXELFORMAT_RGBA32F,
                                           mipmaps: false, minFilter: pc.FILTER_NEAREST, magFilter: pc.FILTER_NEAREST,
                                           addressU: pc.ADDRESS_CLAMP_TO_EDGE, addressV: pc.ADDRESS_CLAMP_TO_EDGE });
    const target = new pc.RenderTarget({ name: 'sb-target', colorBuffer: color, depth: true, stencil: false });
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
    const bind = () => device.setFramebuffer(target.impl._glFrameBuffer);
    const pixel = readOnePixel(gl);
    const wait = () => {
        bind();
        pixel();
    };
    const rows = new Float32Array(w * h * 4), out = new Float32Array(w * h * req.outputs.length);
    let ms = [];
    try {
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
    } finally {
        camera.renderTarget = null;
        camera.enabled = false;
        target.destroy();
        color.destroy();
        light.destroy();
    }
    return { version, renderer: rendererString(gl), ms, data: base64(out) };
}

window.sbRender = render;
