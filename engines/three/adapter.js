// The three.js adapter (docs/engines.md): renders a cell with three's own
// GLTFLoader and shadow code and hands back its shadow factor alone.
//
// The set-up choices a three user has to make, made as shadowbench's own
// passes make them:
// - both faces in the shadow map (material.shadowSide = DoubleSide; three's
//   default for a one-sided material draws its back faces only, and with
//   VSM the front faces: a single-sided plate then casts nothing);
// - flat normals where the file has none (the glTF rule; normalBias needs
//   them): the geometry made non-indexed, then computeVertexNormals;
// - the spot light's frustum fitted as shadowbench's light frustum: the
//   cone (light.angle) holds the fitted window, and setViewOffset picks that
//   window out of it, so the map's texels cover what shadowbench's do; the
//   shadow camera's up is the light's +Y (three's default up of +Y world
//   leaves a light looking straight down with a rotation set by rounding);
// - a sun becomes a DirectionalLight whose orthographic shadow camera is
//   shadowbench's one map over the view.
//
// The shadow term alone: a ShadowMaterial whose fragment shader, through
// onBeforeCompile, writes getShadowMask() (three's product of its lights'
// shadow factors: here the one light's) and the camera distance to a
// float target, with no tone mapping, no colour-space conversion and no
// blending.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { base64, distanceGlsl, distanceVertexGlsl, outputPass, readOnePixel, rendererString, takeChannel,
         timeFrames } from '../common/page.js';

const TYPES = { three_basic: THREE.BasicShadowMap, three_pcf: THREE.PCFShadowMap, three_vsm: THREE.VSMShadowMap };

let renderer = null, gl = null, version = null;
const loaded = new Map();  // scene URL -> { root, camera }

export async function install() {
    const pkg = await (await fetch('/engines/three/node_modules/three/package.json')).json();
    version = `${pkg.version} (r${THREE.REVISION})`;
    const canvas = document.getElementById('canvas');
    renderer = new THREE.WebGLRenderer({ canvas, antialias: false, alpha: false, premultipliedAlpha: false,
                                         powerPreference: 'high-performance' });
    gl = renderer.getContext();
    if (!(gl instanceof WebGL2RenderingContext))
        throw new Error('no WebGL2');
    if (!gl.getExtension('EXT_color_buffer_float'))
        throw new Error('no EXT_color_buffer_float: float targets cannot be read back');
    renderer.toneMapping = THREE.NoToneMapping;
    renderer.outputColorSpace = THREE.LinearSRGBColorSpace;
    renderer.shadowMap.enabled = true;
}

async function load(url) {
    if (loaded.has(url))
        return loaded.get(url);
    const gltf = await new GLTFLoader().loadAsync(url);
    if (!gltf.cameras.length)
        throw new Error('the scene has no camera');
    const root = gltf.scene;
    root.updateMatrixWorld(true);
    const meshes = [];
    /* the scene's light is shadowbench's (the request's): a light the file
     * also carries for engines (KHR_lights_punctual) would light it twice */
    const lights = [];
    root.traverse((o) => { if (o.isLight) lights.push(o); });
    for (const l of lights)
        l.removeFromParent();
    root.traverse((o) => {
        if (!o.isMesh)
            return;
        if (!o.geometry.getAttribute('normal')) {
            o.geometry = o.geometry.index ? o.geometry.toNonIndexed() : o.geometry;
            o.geometry.computeVertexNormals();
        }
        o.castShadow = o.receiveShadow = true;
        o.frustumCulled = false;
        /* each mesh its own pair of materials, kept for the page's life (its programs compiled once, not
         * in a timed frame), and its file's sidedness for shadow_side=engine */
        o.userData.sbFileSide = o.material.side;
        o.userData.sbMaterials = { shadow: shadowTermMaterial(),
                                   lit: new THREE.MeshLambertMaterial({ color: 0xffffff, side: THREE.DoubleSide }) };
        meshes.push(o);
    });
    const entry = { root, camera: gltf.cameras[0], meshes };
    loaded.set(url, entry);
    return entry;
}

// The camera distance (engines/common/page.js): from three's own view
// matrix and camera position, and the inverse projection.
const CORNER = distanceVertexGlsl('sbWorld');
const DISTANCE_GLSL = `
varying vec3 sbWorld;
uniform mat4 sbInverseProjection;
uniform vec2 sbSize;` + distanceGlsl({ world: 'sbWorld', eye: 'cameraPosition', size: 'sbSize',
                                     inverse: 'sbInverseProjection', view: 'viewMatrix' });

// The uniforms of the distance, shared by every shadow-term material and
// set for each cell.
const sbUniforms = { sbInverseProjection: { value: new THREE.Matrix4() }, sbSize: { value: new THREE.Vector2() } };

// The shadow-term material: three's shadow chunks, its output replaced.
function shadowTermMaterial() {
    const m = new THREE.ShadowMaterial({ side: THREE.DoubleSide, blending: THREE.NoBlending, transparent: false });
    m.onBeforeCompile = (shader) => {
        Object.assign(shader.uniforms, sbUniforms);
        shader.vertexShader = shader.vertexShader
            .replace('#include <common>', `#include <common>\nvarying vec3 sbWorld;\n${CORNER.declaration}`)
            .replace('#include <worldpos_vertex>', `#include <worldpos_vertex>
sbWorld = (modelMatrix * vec4(transformed, 1.0)).xyz;
${CORNER.main}`);
        shader.fragmentShader = shader.fragmentShader
            .replace('#include <common>', '#include <common>\n' + DISTANCE_GLSL)
            .replace(/gl_FragColor = vec4\( color, opacity \* \( 1\.0 - getShadowMask\(\) \) \);/,
                     'gl_FragColor = vec4(getShadowMask(), sbDistance(), 0.0, 1.0);')
            .replace('#include <tonemapping_fragment>', '').replace('#include <colorspace_fragment>', '')
            .replace('#include <fog_fragment>', '').replace('#include <premultiplied_alpha_fragment>', '');
        if (!shader.fragmentShader.includes('getShadowMask(), sbDistance()'))
            throw new Error("three's ShadowMaterial shader is not the one this adapter edits");
    };
    return m;
}

const vec = (a) => new THREE.Vector3(a[0], a[1], a[2]);

// The scene's light as three's nearest light, its shadow set up by the cell.
function makeLight(L, p, mapSize) {
    const light = L.kind === 'directional' ? new THREE.DirectionalLight(0xffffff, 1)
                                           : new THREE.SpotLight(0xffffff, 1, 0, Math.PI / 3, 0, 0);
    const eye = vec(L.eye), ahead = vec(L.z).negate();
    light.position.copy(eye);
    light.target.position.copy(eye.clone().add(ahead));
    light.castShadow = true;
    const shadow = light.shadow, cam = shadow.camera;
    cam.up.copy(vec(L.y));
    cam.near = L.near, cam.far = L.far;
    const [l, r, b, t] = L.window;
    if (L.kind === 'directional') {
        cam.left = l, cam.right = r, cam.bottom = b, cam.top = t;
        cam.updateProjectionMatrix();
    } else {
        const h = Math.max(Math.abs(l), Math.abs(r), Math.abs(b), Math.abs(t));
        light.angle = Math.atan(h / L.near);
        cam.fov = THREE.MathUtils.RAD2DEG * 2 * light.angle;
        cam.aspect = 1;
        cam.setViewOffset(1, 1, (l + h) / (2 * h), (h - t) / (2 * h), (r - l) / (2 * h), (t - b) / (2 * h));
    }
    shadow.mapSize.set(mapSize, mapSize);
    shadow.bias = p.bias;
    shadow.normalBias = p.normal_bias;
    if (p.radius !== undefined)
        shadow.radius = p.radius;
    if (p.blur_samples !== undefined)
        shadow.blurSamples = p.blur_samples;
    return light;
}

export async function render(req) {
    const type = TYPES[req.technique];
    if (type === undefined)
        throw new Error(`three has no technique ${req.technique}`);
    const p = req.params, { width: w, height: h } = req;
    const { root, camera, meshes } = await load(req.sceneUrl);
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
    renderer.setSize(w, h, false);
    renderer.shadowMap.type = type;

    const light = makeLight(req.light, p, req.map_size);
    const scene = new THREE.Scene();
    scene.add(root, light, light.target);
    sbUniforms.sbInverseProjection.value.copy(camera.projectionMatrixInverse);
    sbUniforms.sbSize.value.set(w, h);
    /* three's default for a one-sided material draws its other side into the map */
    const fileSide = { [THREE.FrontSide]: THREE.BackSide, [THREE.BackSide]: THREE.FrontSide,
                       [THREE.DoubleSide]: THREE.DoubleSide };
    const use = (kind, receive) => {
        for (const m of meshes) {
            m.material = m.userData.sbMaterials[kind];
            m.receiveShadow = receive;
            m.material.shadowSide = p.shadow_side === 'engine' ? fileSide[m.userData.sbFileSide] : THREE.DoubleSide;
        }
    };
    /* a float depth buffer: three's default 16-bit one, at the loader's far plane of 2e6 for a file with
     * no zfar, picks the wrong one of two close planes */
    const target = new THREE.WebGLRenderTarget(w, h, { type: THREE.FloatType, format: THREE.RGBAFormat,
        minFilter: THREE.NearestFilter, magFilter: THREE.NearestFilter, depthBuffer: true,
        depthTexture: new THREE.DepthTexture(w, h, THREE.FloatType) });
    const rows = new Float32Array(w * h * 4), out = new Float32Array(w * h * req.outputs.length);
    const draw = () => {
        renderer.setRenderTarget(target);
        renderer.setClearColor(new THREE.Color(1, -1, 0), 0);
        renderer.clear();
        renderer.render(scene, camera);
    };
    let ms = [];
    try {
        for (let k = 0; k < req.outputs.length; k++) {
            const pass = outputPass(req.outputs[k]);
            use(pass.material, pass.receive);
            const wait = readOnePixel(gl);  /* the target stays bound */
            draw();  /* untimed: programs compiled, the shadow map allocated, as Babylon's adapter does */
            wait();
            if (k === 0)
                ms = timeFrames(draw, wait, req.warmup, req.frames);
            renderer.readRenderTargetPixels(target, 0, 0, w, h, rows);
            takeChannel(rows, w, h, 4, pass.channel, out, k * w * h);
        }
    } finally {
        renderer.setRenderTarget(null);
        target.depthTexture.dispose();
        target.dispose();
        light.shadow.dispose();
        scene.remove(root);
    }
    /* the map is shadowbench's fitted one, texel for texel */
    return { version, renderer: rendererString(gl), ms, data: base64(out), texel_ratio: [1, 1] };
}

window.sbRender = render;
