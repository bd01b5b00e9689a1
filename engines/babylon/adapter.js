// The Babylon.js adapter (docs/engines.md): renders a cell with Babylon's
// own glTF loader and ShadowGenerator and hands back its shadow factor alone.
//
// The set-up choices a Babylon user has to make, made as shadowbench's own
// passes make them:
// - a right-handed scene (scene.useRightHandedSystem), so the loader keeps
//   glTF's frame instead of mirroring it under a __root__ node;
// - both faces drawn, into the map and by the camera (backFaceCulling off;
//   shadow_side=engine keeps the file's one-sided culling, which drops a
//   single-sided plate seen from behind from the map);
// - the light's frustum fitted as shadowbench's: the ShadowGenerator's
//   view matrix looks along the light from its centre with world +Y as up
//   (ShadowGenerator._computeMatrices; straight down it nudges the
//   direction by 1e-13), so the projection given through the public
//   customProjectionMatrixBuilder is shadowbench's fitted frustum times the
//   turn from that view to the light's own (its +Y up): the map is
//   shadowbench's, texel for texel;
// - the near and far planes (shadowMinZ, shadowMaxZ) are the frustum's, which
//   Babylon's linear depth metric is normalised by;
//
// The shadow term alone: a material plugin (MaterialPluginBase) that, at
// CUSTOM_FRAGMENT_BEFORE_FRAGCOLOR, writes the `shadow` the light block
// computed and the camera distance to a float render target; image
// processing (tone mapping, colour curves) off.
/* global BABYLON */
import { base64, distanceGlsl, distanceVertexGlsl, outputPass, readOnePixel, rendererString, takeChannel,
         timeFrames } from '../common/page.js';

const FILTERS = { babylon_hard: 'none', babylon_poisson: 'poisson', babylon_pcf: 'pcf', babylon_pcss: 'pcss' };
const QUALITY = { high: 0, medium: 1, low: 2 };  // ShadowGenerator.QUALITY_*

let engine = null, gl = null, version = null;

export async function install() {
    const canvas = document.getElementById('canvas');
    engine = new BABYLON.Engine(canvas, false, { preserveDrawingBuffer: false, premultipliedAlpha: false,
                                                 antialias: false, stencil: false, disableWebGL2Support: false });
    gl = engine._gl;
    if (engine.webGLVersion < 2)
        throw new Error('no WebGL2');
    if (!gl.getExtension('EXT_color_buffer_float'))
        throw new Error('no EXT_color_buffer_float: float targets cannot be read back');
    version = BABYLON.Engine.Version;
}

// The camera distance for the coverage test (engines/common/page.js), from
// Babylon's world position and eye, and the inverse view-projection.
const CORNER = distanceVertexGlsl('vPositionW');
const DISTANCE_GLSL = distanceGlsl({ world: 'vPositionW', eye: 'vEyePosition.xyz', size: 'sbSize',
                                     inverse: 'sbInverseViewProjection' });
const termUniforms = { inverseViewProjection: BABYLON.Matrix.Identity(), size: new BABYLON.Vector2(1, 1) };

class ShadowTerm extends BABYLON.MaterialPluginBase {
    constructor(material) {
        super(material, 'ShadowbenchShadowTerm', 200, { SB_SHADOW_TERM: false });
        this._enable(true);
    }
    getClassName() { return 'ShadowbenchShadowTerm'; }
    prepareDefines(defines) { defines.SB_SHADOW_TERM = true; }
    getUniforms() {
        return { ubo: [{ name: 'sbInverseViewProjection', size: 16, type: 'mat4' },
                       { name: 'sbSize', size: 2, type: 'vec2' }],
                 fragment: 'uniform mat4 sbInverseViewProjection;\nuniform vec2 sbSize;' };
    }
    bindForSubMesh(ubo) {
        ubo.updateMatrix('sbInverseViewProjection', termUniforms.inverseViewProjection);
        ubo.updateFloat2('sbSize', termUniforms.size.x, termUniforms.size.y);
    }
    getCustomCode(shaderType) {
        if (shaderType === 'vertex')
            return { CUSTOM_VERTEX_DEFINITIONS: CORNER.declaration, CUSTOM_VERTEX_MAIN_END: CORNER.main };
        return {
            CUSTOM_FRAGMENT_DEFINITIONS: DISTANCE_GLSL,
            CUSTOM_FRAGMENT_BEFORE_FRAGCOLOR: 'color = vec4(shadow, sbDistance(), 0.0, 1.0);',
        };
    }
}

let current = null;  // { url, scene, camera, meshes }

async function load(url) {
    if (current && current.url === url)
        return current;
    if (current)
        current.scene.dispose();
    const scene = new BABYLON.Scene(engine);
    scene.useRightHandedSystem = true;
    scene.imageProcessingConfiguration.isEnabled = false;
    scene.ambientColor = new BABYLON.Color3(0, 0, 0);
    scene.clearColor = new BABYLON.Color4(1, -1, 0, 0);
    scene.skipFrustumClipping = true;
    const container = await BABYLON.LoadAssetContainerAsync(url, scene);
    container.addAllToScene();
    for (const l of scene.lights.slice())  /* the scene's light is the request's (KHR_lights_punctual too) */
        l.dispose();
    const camera = scene.cameras[0];
    if (!camera)
        throw new Error('the scene has no camera');
    scene.activeCamera = camera;
    const meshes = scene.meshes.filter((m) => m.getTotalVertices() > 0);
    for (const m of meshes) {
        if (!m.isVerticesDataPresent(BABYLON.VertexBuffer.NormalKind)) {
            /* flat normals, as glTF asks (normalBias needs them: without, Babylon drops it): each triangle its
             * own vertices, then each vertex its triangle's normal, wound as the right-handed scene is */
            m.convertToUnIndexedMesh();
            const normals = [];
            BABYLON.VertexData.ComputeNormals(m.getVerticesData(BABYLON.VertexBuffer.PositionKind), m.getIndices(),
                                              normals, { useRightHandedSystem: true });
            m.setVerticesData(BABYLON.VertexBuffer.NormalKind, normals);
        }
        m.sbFileCulling = m.material ? m.material.backFaceCulling : true;
        m.alwaysSelectAsActiveMesh = true;
        /* each mesh its own pair of materials, for the scene's life (the culling is per material) */
        const lit = new BABYLON.StandardMaterial('sb-lit', scene);
        lit.diffuseColor = new BABYLON.Color3(1, 1, 1);
        lit.specularColor = new BABYLON.Color3(0, 0, 0);
        const term = lit.clone('sb-shadow-term');
        new ShadowTerm(term);  /* a plugin registers itself with its material */
        m.sbMaterials = { lit, shadow: term };
    }
    current = { url, scene, camera, meshes };
    return current;
}

const vec = (a) => new BABYLON.Vector3(a[0], a[1], a[2]);

// GL's off-centre frustum (or box) of the window [l, r] x [b, t] at near
// (the box's at every depth) out to far, looking down -Z, clip z in
// [-1, 1]; as Babylon's column-major array.
function projection(L, f) {
    const [l, r, b, t] = L.window, n = L.near;
    if (L.kind === 'directional')
        return BABYLON.Matrix.FromArray([2 / (r - l), 0, 0, 0, 0, 2 / (t - b), 0, 0, 0, 0, -2 / (f - n), 0,
                                         -(r + l) / (r - l), -(t + b) / (t - b), -(f + n) / (f - n), 1]);
    return BABYLON.Matrix.FromArray([2 * n / (r - l), 0, 0, 0, 0, 2 * n / (t - b), 0, 0,
                                     (r + l) / (r - l), (t + b) / (t - b), -(f + n) / (f - n), -1,
                                     0, 0, -2 * f * n / (f - n), 0]);
}

// The light's own view: world -> its frame (x, y, z its axes, eye its centre).
function lightView(L) {
    const x = L.x, y = L.y, z = L.z, e = L.eye;
    const dot = (a) => -(a[0] * e[0] + a[1] * e[1] + a[2] * e[2]);
    return BABYLON.Matrix.FromArray([x[0], y[0], z[0], 0, x[1], y[1], z[1], 0, x[2], y[2], z[2], 0,
                                     dot(x), dot(y), dot(z), 1]);
}

// The scene's light as Babylon's nearest light, its frustum shadowbench's.
function makeLight(scene, L, p) {
    const eye = vec(L.eye), ahead = vec(L.z).negate();
    const light = L.kind === 'directional' ? new BABYLON.DirectionalLight('sb', ahead, scene)
                                           : new BABYLON.SpotLight('sb', eye, ahead, Math.PI * 0.99, 0, scene);
    light.position = eye;
    light.intensity = 0.5;  /* lit renders stay below StandardMaterial's clamp at 1 */
    light.specular = new BABYLON.Color3(0, 0, 0);
    /* the depth range, which Babylon's depth metric is normalised by: the fitted one, which babylon_pcss's
     * shadow_max_z_scale widens (its PCSS fades a shadow towards lit by the metric's gap between receiver
     * and blocker) */
    light.shadowMinZ = L.near;
    light.shadowMaxZ = L.near + (L.far - L.near) * (p.shadow_max_z_scale || 1);
    if (L.kind === 'directional')
        light.autoUpdateExtends = light.autoCalcShadowZBounds = false;
    /* the fitted frustum out to shadowMaxZ, turned from the generator's world-up view to the light's own */
    const ours = lightView(L).multiply(projection(L, light.shadowMaxZ));
    light.customProjectionMatrixBuilder = (view, renderList, result) => {
        const inverse = view.clone().invert();
        inverse.multiplyToRef(ours, result);
    };
    return light;
}

// The generator's biases; no darkness, no fade at the frustum's edge.
function setGenerator(g, p) {
    g.bias = p.bias;
    g.normalBias = p.normal_bias;
    g.darkness = 0;
    g.frustumEdgeFalloff = 0;
}

// contactHardeningLightSizeUVRatio from the scene's light. Babylon's PCSS
// (computeShadowWithPCSS) filters over a disk of radius
// ratio * (d_r - d_b) in map UV, d the depth metric
// (z - shadowMinZ) / (shadowMaxZ - shadowMinZ) of receiver and blocker.
// The true penumbra's half-width in UV is, for a spot whose light is L_uv
// wide in UV at the near plane n, L_uv * n * (z_r - z_b) / (2 z_b z_r),
// which one ratio matches where z_b z_r = n * far (taken here, far the
// fitted frustum's); for the sun, whose cone is S_uv wide in UV per world
// unit of depth, S_uv * (z_r - z_b) / 2, at every depth. Babylon's ratio is
// one number for both axes: the mean of the light's two UV sizes.
function derivedRatio(L, minZ, maxZ) {
    const uv = 0.5 * (L.size_uv[0] + L.size_uv[1]), range = maxZ - minZ;
    return L.kind === 'directional' ? 0.5 * uv * range : 0.5 * uv * range / L.far;
}

// The cell's filter, checked before anything is created.
function filterOf(technique) {
    const filter = FILTERS[technique];
    if (filter === undefined)
        throw new Error(`Babylon has no technique ${technique}`);
    return filter;
}

function setFilter(g, light, filter, p, L) {
    g.usePoissonSampling = g.usePercentageCloserFiltering = g.useContactHardeningShadow = false;
    if (filter === 'poisson')
        g.usePoissonSampling = true;
    else if (filter === 'pcf')
        g.usePercentageCloserFiltering = true;
    else if (filter === 'pcss') {
        g.useContactHardeningShadow = true;
        g.contactHardeningLightSizeUVRatio = p.light_size_uv_ratio > 0 ? p.light_size_uv_ratio
                                                                        : derivedRatio(L, light.shadowMinZ,
                                                                                       light.shadowMaxZ);
    }
    if (p.filtering_quality !== undefined)
        g.filteringQuality = QUALITY[p.filtering_quality];
}

export async function render(req) {
    const p = req.params, { width: w, height: h } = req;
    const filter = filterOf(req.technique);
    engine.setSize(w, h);
    const { scene, camera, meshes } = await load(req.sceneUrl);
    const use = (kind, receive) => {
        for (const m of meshes) {
            m.material = m.sbMaterials[kind];
            m.receiveShadows = receive;
            /* shadow_side=engine: the file's culling in the map (the depth pass culls by the material) */
            m.material.backFaceCulling = p.shadow_side === 'engine' ? m.sbFileCulling : false;
        }
    };
    const out = new Float32Array(w * h * req.outputs.length);
    let light = null, generator = null, target = null, ms = [];
    try {
        light = makeLight(scene, req.light, p);
        generator = new BABYLON.ShadowGenerator(req.map_size, light, true);
        setGenerator(generator, p);
        setFilter(generator, light, filter, p, req.light);
        const map = generator.getShadowMap();
        map.renderList = meshes;
        target = new BABYLON.RenderTargetTexture('sb-target', { width: w, height: h }, scene, false, true,
                                                 BABYLON.Constants.TEXTURETYPE_FLOAT, false,
                                                 BABYLON.Constants.TEXTURE_NEAREST_SAMPLINGMODE, true, false);
        camera.outputRenderTarget = target;  /* the camera draws into the float target, not the canvas */
        /* the camera's matrices at this size (before its first frame, its cached ones are not) */
        camera.getViewMatrix(true).multiply(camera.getProjectionMatrix(true))
            .invertToRef(termUniforms.inverseViewProjection);
        termUniforms.size.set(w, h);
        for (let k = 0; k < req.outputs.length; k++) {
            const pass = outputPass(req.outputs[k]);
            use(pass.material, pass.receive);
            /* every program compiled before a frame counts: Babylon skips a mesh whose shader is not ready */
            for (const m of meshes)
                await m.material.forceCompilationAsync(m);
            await generator.forceCompilationAsync();
            await scene.whenReadyAsync();
            const draw = () => scene.render();
            const pixel = readOnePixel(gl);
            const wait = () => {
                engine.bindFramebuffer(target.renderTarget);
                pixel();
                engine.unBindFramebuffer(target.renderTarget);
            };
            if (k === 0)
                ms = timeFrames(draw, wait, req.warmup, req.frames);
            else
                draw();
            const rows = await target.readPixels();
            takeChannel(new Float32Array(rows.buffer, rows.byteOffset, w * h * 4), w, h, 4,
                        pass.channel, out, k * w * h);
        }
    } finally {
        camera.outputRenderTarget = null;
        target?.dispose();
        generator?.dispose();
        light?.dispose();
    }
    /* the map is shadowbench's fitted one, texel for texel */
    return { version, renderer: rendererString(gl), ms, data: base64(out), texel_ratio: [1, 1] };
}

window.sbRender = render;
