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
// (N.L <= 0, or past a spot's reach), Filament computes no visibility, the
// factor is 1, and the reply's notice counts those pixels.
//
// Filament's JS bindings reach one shadow type, PCF (View::setShadowType
// and the soft and VSM options are not bound: techniques/filament.c), with
// the light's ShadowOptions, which 1.53.4 binds but cannot pass until the
// one binding type they wait for is supplied (glue.js).
//
// The set-up choices a Filament user has to make, made as shadowbench's
// own passes make them:
// - the scene is loaded by gltfio, its files fetched by the adapter (a file
//   that does not load fails the cell at once); the file's
//   KHR_lights_punctual light is not added to the scene (the scene's light
//   is the request's);
// - every material instance is gltfio's material as a white, fully rough
//   dielectric (baseColorFactor 1, metallicFactor 0: glTF's default
//   material is a metal, which has no diffuse term), no emissive, both
//   faces drawn and lit (culling off, double-sided: the normal turned to
//   face the camera, as the ground truth turns it), into the map too
//   (shadow_side=engine: gltfio's single-sided default, back faces culled);
// - flat normals where the file has none: gltfio computes them;
// - the file's camera (gltfio's): its vertical field of view, aspect W/H,
//   its near plane, its far plane at the farthest view depth it sees (the
//   request's view_far, 1 % beyond: Filament's sun map covers the view to
//   it), exposure exactly 1 (setExposureDirect; Filament's default is a
//   physical camera), GL's pixel centres;
// - no indirect light (an IndirectLight of intensity 0 and zero irradiance:
//   without one Filament lights with a default), no post-processing (no
//   tone mapping, no sRGB encoding, no dithering, no AA), no SSAO, no fog,
//   no screen-space contact shadows (Filament's defaults);
// - an area light becomes a SPOT at its centre along its -Z, whose inner
//   cone is the smallest around that axis that holds the scene inside
//   shadowbench's fitted window (the request's cone_tan; Filament's spot
//   map is the square around the outer cone, 0.1 % wider in tangent:
//   ShadowMap::updatePunctual), its falloff radius (the map's far plane)
//   the fitted far plane's farthest point in the cone, 1 % beyond;
// - a sun becomes a DIRECTIONAL light (a SUN would bend the light direction
//   towards the reflection) with Filament's own fit.
//
// The reply's texel_ratio: a spot's map against shadowbench's fitted one;
// the sun's has none (LiSPSM warps its map).
//
// Float readback: the view renders into a RenderTarget whose attachments
// are an RGBA32F colour and a DEPTH32F texture, which readback.js reads
// (the colour as float, the depth as the camera distance).
/* global Filament */
import { base64, outputPass, readOnePixel, rendererString, takeChannel, timeFrames } from '../common/page.js';
import { GLUE_DIR, SHADOW_OPTIONS, loadFilament } from './glue.js';
import { distanceReader, readFramebuffer, watch } from './readback.js';

let gl = null, engine = null, renderer = null, view = null, version = null, tracker = null, reader = null;
let loader = null;  // gltfio's asset loader, one for the page's life
let current = null;  // { url, asset, scene, ibl, renderables, materials, camera, near, tanY }

export async function install() {
    await loadFilament();
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
    /* one asset loader, as Filament's glue asks (createAssetLoader): each makes its own material provider,
     * whose materials live as long as it does */
    loader = engine.createAssetLoader();
    reader = distanceReader(gl);
}

// Runs make(builder), which ends in the builder's build(). The glue's
// build() deletes the builder (filament.js: the Builder prototypes' build);
// one that a call before it throws on is deleted here.
function build(builder, make) {
    try {
        return make(builder);
    } catch (e) {
        builder.delete();
        throw e;
    }
}

// Loads the asset's resources: its files (buffers, images) fetched here,
// each that fails to load one line at once, and handed with the data: URIs
// (which gltfio decodes itself) to a ResourceLoader, with the glue's image
// decoders (PNG and JPEG, KTX2), all deleted after. The glue's own
// asset.loadResources never calls back when a fetch fails (Filament.fetch
// has no failure path: the cell waited for the engine timeout), and keeps
// for the page's life a copy of every URI (getResourceUris' vector: a data:
// URI is as large as its buffer, 2 MB for the bunny each load), the fetched
// files (Filament.assets) and its KTX2 decoder.
async function loadResources(asset, url) {
    const list = asset._getResourceUris(), uris = [];
    for (let i = 0; i < list.size(); i++)
        uris.push(list.get(i));
    list.delete();
    const files = uris.filter((uri) => !uri.startsWith('data:'));
    const data = await Promise.all(files.map(async (uri) => {
        const response = await fetch(new URL(uri, url)).catch((e) => ({ ok: false, statusText: e.message }));
        if (!response.ok)
            throw new Error(`the scene's resource ${uri} did not load (${response.status ? `HTTP ${response.status}`
                                                                                      : response.statusText})`);
        return new Uint8Array(await response.arrayBuffer());
    }));
    const resources = new Filament.gltfio$ResourceLoader(engine, true);  /* normalizeSkinningWeights, the glue's */
    const stb = new Filament.gltfio$StbProvider(engine), ktx2 = new Filament.gltfio$Ktx2Provider(engine);
    try {
        resources.addStbProvider('image/jpeg', stb);
        resources.addStbProvider('image/png', stb);
        resources.addKtx2Provider('image/ktx2', ktx2);
        files.forEach((uri, k) => {
            const buffer = Filament.Buffer(data[k]);
            resources.addResourceData(uri, buffer);
            buffer.delete();
        });
        if (!resources.loadResources(asset))
            throw new Error("gltfio cannot load the scene's resources");
    } finally {
        resources.delete();
        stb.delete();
        ktx2.delete();
    }
}

// The asset's scene: its renderables, not its lights; gltfio's material
// instances made white, fully rough dielectrics, double-sided. What it has
// made is released if a step after it throws (a scene with no camera).
async function load(url) {
    if (current && current.url === url)
        return current;
    if (current)
        unload();
    const response = await fetch(url);
    if (!response.ok)
        throw new Error(`the scene file did not load (HTTP ${response.status})`);
    const asset = loader.createAsset(new Uint8Array(await response.arrayBuffer()));
    if (!asset)
        throw new Error('gltfio cannot read the scene file');
    const made = { asset, scene: null, ibl: null };
    try {
        await loadResources(asset, url);
        const cameras = asset.getCameraEntities();
        if (!cameras.length)
            throw new Error('the scene has no camera');
        const scene = made.scene = engine.createScene();
        const rm = engine.getRenderableManager();
        const renderables = asset.getRenderableEntities();
        const materials = [];
        for (const e of renderables) {
            scene.addEntity(e);
            const inst = rm.getInstance(e);
            for (let k = 0, n = rm.getPrimitiveCount(inst); k < n; k++) {
                const mi = rm.getMaterialInstanceAt(inst, k);
                mi.setFloat4Parameter('baseColorFactor', [1, 1, 1, 1]);
                mi.setFloatParameter('metallicFactor', 0);
                mi.setFloatParameter('roughnessFactor', 1);
                mi.setFloat3Parameter('emissiveFactor', [0, 0, 0]);
                materials.push(mi);
            }
            inst.delete();
        }
        /* no indirect light: Filament lights a scene without one with a default */
        made.ibl = build(Filament.IndirectLight.Builder(),
                         (b) => b.irradianceSh(1, new Float32Array([0, 0, 0])).intensity(0).build(engine));
        scene.setIndirectLight(made.ibl);
        const camera = engine.getCameraComponent(cameras[0]);
        /* the file's near plane and yfov, as gltfio set them (its [1][1] is 1 / tan(yfov / 2)) */
        current = { url, ...made, renderables, materials, camera, near: camera.getNear(),
                    tanY: 1 / camera.getCullingProjectionMatrix()[5] };
        return current;
    } catch (e) {
        release(made);
        throw e;
    }
}

// Releases what load() made of a scene.
function release({ asset, scene, ibl }) {
    if (scene)
        engine.destroyScene(scene);
    if (ibl)
        engine.destroyIndirectLight(ibl);
    loader.destroyAsset(asset);
}

function unload() {
    release(current);
    current = null;
}

// The largest shadow map Filament draws: LightManager::setShadowOptions
// clamps mapSize to [8, 2048], silently (techniques/filament.c refuses a
// map_size under 8; a run's --shadow-map-size reaches here as it is).
const MAX_MAP_SIZE = 2048;

// The cell's ShadowOptions: Filament's defaults, and the cell's parameters
// under Filament's names (techniques/filament.c); the map mapSize texels a
// side.
function shadowOptions(p, mapSize) {
    return { ...SHADOW_OPTIONS, mapSize, constantBias: p.constant_bias, normalBias: p.normal_bias,
             polygonOffsetConstant: p.polygon_offset_constant, polygonOffsetSlope: p.polygon_offset_slope,
             lispsm: p.lispsm, stable: p.stable };
}

// Where a spot reaches: its cone, the smallest about its axis that holds
// the scene inside shadowbench's fitted window (the request's cone_tan),
// the outer 0.1 % wider in tangent, so that smoothstep's fall lies outside
// every scored point; its falloff radius, the fitted far plane's farthest
// point in that cone, 1 % beyond (the least that lights every scored point;
// ShadowMap::updateSpot, as read, also ends the map there).
function spotReach(L) {
    const k = L.cone_tan;
    return { inner: k, outer: 1.001 * k, radius: 1.01 * L.far * Math.sqrt(1 + k * k) };
}

// The scene's light as Filament's nearest light, casting shadows with
// options: its entity, released if Filament refuses the light.
function makeLight(L, options) {
    const ahead = [-L.z[0], -L.z[1], -L.z[2]];
    const sun = L.kind === 'directional';
    const entity = Filament.EntityManager.get().create();
    try {
        build(Filament.LightManager.Builder(sun ? Filament.LightManager$Type.DIRECTIONAL
                                                : Filament.LightManager$Type.SPOT), (b) => {
            if (sun) {
                /* illuminance pi lux: a white Lambertian surface facing the light is 1 */
                b.intensity(Math.PI);
            } else {
                const reach = spotReach(L);
                /* SPOT: lumens / pi candela; a white Lambertian surface facing it at the frustum's middle
                 * depth is 1 */
                const middle = 0.5 * (L.near + L.far);
                b.position(L.eye).falloff(reach.radius).spotLightCone(Math.atan(reach.inner), Math.atan(reach.outer))
                    .intensity(Math.PI * Math.PI * middle * middle);
            }
            return b.direction(ahead).color([1, 1, 1]).castShadows(true).shadowOptions(options).build(engine, entity);
        });
        return entity;
    } catch (e) {
        destroyLight(entity);
        throw e;
    }
}

// Destroys a light: its component, its entity, and the entity's JS handle.
function destroyLight(entity) {
    engine.destroyEntity(entity);
    Filament.EntityManager.get().destroy(entity);
    entity.delete();
}

// What the cell asks, checked before anything is made. Filament's JS
// bindings (npm filament 1.53.4) bind neither View::setShadowType nor its
// soft or VSM options: a light's shadow is PCF, whatever the page asks.
function check(req) {
    const L = req.light;
    if (req.technique !== 'filament_pcf')
        throw new Error(`Filament has no technique ${req.technique}`);
    if (req.map_size > MAX_MAP_SIZE)
        throw new Error(`Filament draws shadow maps of at most ${MAX_MAP_SIZE} texels a side, not ${req.map_size}`);
    if (!(L.view_far > 0))
        throw new Error('the camera sees no geometry');
    if (L.kind !== 'directional' && !(L.cone_tan > 0))
        throw new Error('nothing in front of the light for its cone to hold');
}

export async function render(req) {
    const { width: w, height: h } = req;
    check(req);
    const { scene, camera, renderables } = await load(req.sceneUrl);
    /* shadow_side: both faces (double-sided, not culled), or gltfio's default for glTF's default material
     * (single-sided, back faces culled, into the map too) */
    const both = req.params.shadow_side !== 'engine';
    for (const mi of current.materials) {
        mi.setDoubleSided(both);
        mi.setCullingMode(both ? Filament.CullingMode.NONE : Filament.CullingMode.BACK);
    }
    /* the file's vertical field of view, aspect W/H; the far plane at the farthest view depth the camera
     * sees (the request's), 1 % beyond: Filament's directional shadow covers the view frustum to its far
     * plane (shadowFar 0), as shadowbench's own sun fit covers what the camera sees (gltfio's far plane for
     * a file with no zfar, 1e8, leaves it casting nothing) */
    camera.setProjectionFov(360 / Math.PI * Math.atan(current.tanY), w / h, current.near, 1.01 * req.light.view_far,
                            Filament.Camera$Fov.VERTICAL);
    const P = camera.getProjectionMatrix();
    const cam = { tanY: current.tanY, p22: P[10], p32: P[14] };
    camera.setExposureDirect(1.0);
    view.setCamera(camera);
    view.setScene(scene);
    view.setViewport([0, 0, w, h]);

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
    const pixel = readOnePixel(gl);
    const wait = () => readFramebuffer(gl, gpu.fb, pixel);
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
    const Tex = Filament.Texture, U = Filament.Texture$Usage, A = Filament.RenderTarget$AttachmentPoint;
    const texture = (format, usage) => build(Tex.Builder(), (b) => b.width(w).height(h).levels(1)
        .sampler(Filament.Texture$Sampler.SAMPLER_2D).format(format).usage(usage.value | U.SAMPLEABLE.value)
        .build(engine));
    let light = null, color = null, depth = null, target = null, ms = [];
    try {
        light = makeLight(req.light, shadowOptions(req.params, req.map_size));
        scene.addEntity(light);
        color = texture(Filament.Texture$InternalFormat.RGBA32F, U.COLOR_ATTACHMENT);
        depth = texture(Filament.Texture$InternalFormat.DEPTH32F, U.DEPTH_ATTACHMENT);
        target = build(Filament.RenderTarget.Builder(),
                       (b) => b.texture(A.COLOR, color).texture(A.DEPTH, depth).build(engine));
        view.setRenderTarget(target);
        renderer.setClearOptions({ clearColor: [0, 0, 0, 0], clear: true, discard: true });
        for (let k = 0; k < renders.length; k++) {
            receive(outputPass(renders[k]).receive);
            draw();  /* untimed: programs compiled, the shadow map allocated */
            wait();
            if (k === 0)  /* the lit render: gltfio's PBR material, not a shadow-term one (docs/engines.md) */
                ms = timeFrames(draw, wait, req.warmup, req.frames);
            rows[renders[k]] = new Float32Array(n * 4);
            readFramebuffer(gl, gpu.fb, () => gl.readPixels(0, 0, w, h, gl.RGBA, gl.FLOAT, rows[renders[k]]));
            /* the distance: asked, or the shadow's coverage (its notice counts covered pixels) */
            if (k === 0 && (want.has('distance') || want.has('shadow'))) {
                rows.distance = new Float32Array(n);
                reader(gpu.depth, w, h, cam, rows.distance);
            }
        }
    } finally {  /* what was made, in the reverse order */
        view.setRenderTarget(null);
        if (target)
            engine.destroyRenderTarget(target);
        if (depth)
            engine.destroyTexture(depth);
        if (color)
            engine.destroyTexture(color);
        if (light) {
            scene.remove(light);
            destroyLight(light);
        }
    }
    const out = new Float32Array(n * req.outputs.length);
    let notice;
    req.outputs.forEach((what, k) => {
        if (what === 'lit' || what === 'unlit')
            takeChannel(rows[what], w, h, 4, 0, out, k * n);
        else if (what === 'distance')
            takeChannel(rows.distance, w, h, 1, 0, out, k * n);
        else if (what === 'shadow') {
            takeChannel(shadowFactor(rows.lit, rows.unlit, n), w, h, 1, 0, out, k * n);
            notice = unlitNotice(unlitCovered(rows.unlit, rows.distance, w, h, req.light, camera, current.tanY));
        } else
            throw new Error(`no output ${what}`);
    });
    const texel_ratio = texelRatio(req.light, req.map_size);
    return { version, renderer: rendererString(gl), ms, data: base64(out), ...(texel_ratio && { texel_ratio }),
             ...(notice && { notice }) };
}

// A spot's map's texel over shadowbench's fitted map's at the same map size
// M, along the light's x and y: the square around the outer cone against
// the window [l, r] x [b, t] at near, drawn into M - 2 texels of M
// (Filament keeps a 1-texel border). The sun's has none: LiSPSM warps its
// map, whose texel then depends on depth.
function texelRatio(L, mapSize) {
    if (L.kind === 'directional')
        return null;
    const [l, r, b, t] = L.window;
    const side = 2 * spotReach(L).outer * L.near * mapSize / (mapSize - 2);
    return [side / (r - l), side / (t - b)];
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

// The pixels that show a surface (a distance, not -1) which the unshadowed
// render leaves dark, whose factor is then the adapter's 1, not Filament's:
// behind, where the light's centre is behind the surface (N.L <= 0), and,
// for a spot, outside, where the point lies past its reach (its cone holds
// the scene inside shadowbench's fitted window only: map_border's ground
// beyond it). The point is the pixel's along its ray (rows bottom first),
// taken to the light's frame.
function unlitCovered(unlit, distance, w, h, L, camera, tanY) {
    const M = camera.getModelMatrix(), reach = L.kind === 'directional' ? null : spotReach(L);
    const dot = (a, d) => a[0] * d[0] + a[1] * d[1] + a[2] * d[2];
    let behind = 0, outside = 0;
    for (let y = 0; y < h; y++)
        for (let x = 0; x < w; x++) {
            const i = y * w + x;
            if (unlit[4 * i] > 0 || !(distance[i] >= 0))
                continue;
            if (!reach) {
                behind++;
                continue;
            }
            const u = (2 * (x + 0.5) / w - 1) * tanY * w / h, v = (2 * (y + 0.5) / h - 1) * tanY;
            const z = distance[i] / Math.hypot(1, u, v);
            const d = [0, 1, 2].map((r) => M[r] * u * z + M[4 + r] * v * z - M[8 + r] * z + M[12 + r] - L.eye[r]);
            const along = -dot(L.z, d);
            const inside = along > 0 && Math.hypot(dot(L.x, d), dot(L.y, d)) <= reach.outer * along &&
                           Math.hypot(...d) <= reach.radius;
            behind += inside;
            outside += !inside;
        }
    return { behind, outside };
}

// The reply's notice (one line) for those pixels, or undefined.
function unlitNotice({ behind, outside }) {
    const where = [];
    if (behind)
        where.push(`its light is behind the surface: ${behind} covered pixels`);
    if (outside)
        where.push(`its spot does not reach (past the cone that holds shadowbench's fitted window): ${outside} ` +
                   'covered pixels');
    return where.length ? `Filament computes no shadow where ${where.join(', or where ')} given the factor 1`
                        : undefined;
}

window.sbRender = render;
