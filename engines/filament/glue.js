// Filament's glue (docs/engines.md, "ShadowOptions"): filament.js loaded
// with embind's registerType exposed, and the one binding type its
// ShadowOptions waits for supplied. Filament's code, its glue's behaviour
// and every other binding are untouched.
//
// Filament's JS bindings (npm filament 1.53.4) bind the light's
// ShadowOptions but cannot pass it: its value_object has a field,
// `transform`, whose C++ type (filament::math::quatf, a float quaternion)
// the bindings never register, so LightManager.Builder.shadowOptions
// throws embind's UnboundTypeError. loadFilament registers that type.
/* global Filament */

// Where the page finds Filament's glue (filament.js) and its wasm.
export const GLUE_DIR = '/engines/filament/node_modules/filament/';

// The glue's embind type registration, a function of the Emscripten
// closure that registers a binding type and completes whatever waits for
// it. The one edit made to the glue is to put it on the
// module, before its definition (hoisted: the whole closure sees it).
const REGISTER_TYPE = 'function registerType(rawType,registeredInstance,options={}){';
const EXPOSE_REGISTER_TYPE = 'Module.sbRegisterType=registerType;';

// Loads Filament's glue with registerType exposed (checked: it must be
// found exactly once, or this is not the glue edited here), as the
// classic script it is, and initialises Filament.
async function loadGlue() {
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
export const SHADOW_OPTIONS = Object.freeze({
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

// Loads Filament (its glue and wasm) with ShadowOptions passable.
export async function loadFilament() {
    await loadGlue();
    supplyTransformType();
}
