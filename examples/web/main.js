// The three.js example (examples/web/README.md): a glTF model drawn by
// three.js with a RawShaderMaterial whose fragment shader is the surfgrad
// GLSL ES 3.00 library (the single file the build writes,
// shaders/flat/surfgrad.glsl) and the layers below, composed as surface
// gradients (Mikkelsen 2019) and resolved once. No tangent attribute is
// read: every UV set gets its frame per pixel (listing 6).
//
// URL parameters (the browser test sets them; a person uses the panel):
//   size=WxH        canvas size (default: the window)
//   camera=px,py,pz,tx,ty,tz,fovDeg,near,far
//                   the renderer's explicit scene camera (up +y); default
//                   frames the model like `surfgrad render MODEL`
//   model=PATH      a glTF below the server root (default NormalTangentTest)
//   layers=a,b,...  base, detail, triplanar, decal, noise (default all)
//   blend=surfgrad|whiteout|udn|rnm   how base and detail combine
//   view=shaded|normal
// When the first frame is drawn, window.surfgrad = { ready: true, ... }.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { fragmentBody, vertexShader, layerNames, blendNames } from './surfgrad_material.js';

const q = new URLSearchParams(location.search);
const state = {
  layers: new Set((q.get('layers') ?? layerNames.join(',')).split(',').filter(Boolean)),
  blend: q.get('blend') ?? 'surfgrad',
  view: q.get('view') ?? 'shaded',
};
for (const l of state.layers) if (!layerNames.includes(l)) throw new Error(`layers: unknown layer "${l}"`);
if (!blendNames.includes(state.blend)) throw new Error(`blend: unknown "${state.blend}"`);
if (!['shaded', 'normal'].includes(state.view)) throw new Error(`view: unknown "${state.view}"`);

const fixedSize = q.get('size')?.split('x').map(Number);
const width = fixedSize ? fixedSize[0] : window.innerWidth;
const height = fixedSize ? fixedSize[1] : window.innerHeight;

const renderer = new THREE.WebGLRenderer({ antialias: false, preserveDrawingBuffer: true });
renderer.setPixelRatio(1);
renderer.setSize(width, height);
renderer.setClearColor(0x000000, 0);
document.body.appendChild(renderer.domElement);

const textureLoader = new THREE.TextureLoader();
async function dataTexture(path) {
  const t = await textureLoader.loadAsync(path);
  t.wrapS = t.wrapT = THREE.RepeatWrapping;
  t.colorSpace = THREE.NoColorSpace;
  t.flipY = false; // row 0 is the image's top row, as glTF's textures
  return t;
}

const [library, gltf, detailMap, triplanarMap, decalMap] = await Promise.all([
  fetch('shaders/surfgrad.glsl').then((r) => {
    if (!r.ok) throw new Error('shaders/surfgrad.glsl: ' + r.status + ' (build the project first)');
    return r.text();
  }),
  new GLTFLoader().loadAsync(q.get('model') ?? 'data/gltf/NormalTangentTest/glTF/NormalTangentTest.gltf'),
  dataTexture('data/textures/wicker_normal.png'),
  dataTexture('data/textures/technicalFabricSmall_normal_256.png'),
  dataTexture('data/textures/ClearCoatCarPaint_Normal.png'),
]);

const uniforms = {
  uNormalMap: { value: null },
  uNormalScale: { value: 1.0 },
  uDetailMap: { value: detailMap },
  uDetailTiling: { value: 4.0 },
  uDetailStrength: { value: 0.6 },
  uHasUv1: { value: false },
  uTriplanarMap: { value: triplanarMap },
  uTriplanarScale: { value: 2.5 },
  uTriplanarStrength: { value: 0.5 },
  uDecalMap: { value: decalMap },
  uDecalCenter: { value: new THREE.Vector3() },
  uDecalHalfSize: { value: 0.35 },
  uNoiseFrequency: { value: 9.0 },
  uNoiseAmplitude: { value: 0.02 },
  uLayerMask: { value: 0 },
  uBlend: { value: 0 },
  uView: { value: 0 },
  uDoubleSided: { value: false },
  uLightDir: { value: new THREE.Vector3(0.4, 0.6, 0.7).normalize() },
};

const box = new THREE.Box3().setFromObject(gltf.scene);
const center = box.getCenter(new THREE.Vector3());
uniforms.uDecalCenter.value.copy(center);

const materials = [];
gltf.scene.traverse((o) => {
  if (!o.isMesh) return;
  const src = o.material;
  const m = new THREE.RawShaderMaterial({
    glslVersion: THREE.GLSL3,
    uniforms: THREE.UniformsUtils.clone(uniforms),
    vertexShader,
    fragmentShader: 'precision highp float;\nprecision highp int;\nprecision highp sampler2D;\n' +
      library + fragmentBody,
    side: src.side === THREE.DoubleSide ? THREE.DoubleSide : THREE.FrontSide,
  });
  // Filtered trilinearly whatever the glTF sampler says (this model asks
  // for NEAREST_MIPMAP_LINEAR), as surfgrad's renderer filters every map.
  if (src.normalMap) {
    src.normalMap.minFilter = THREE.LinearMipmapLinearFilter;
    src.normalMap.magFilter = THREE.LinearFilter;
    src.normalMap.needsUpdate = true;
  }
  m.uniforms.uNormalMap.value = src.normalMap;
  m.uniforms.uNormalScale.value = src.normalScale ? src.normalScale.x : 1.0;
  m.uniforms.uDoubleSided.value = src.side === THREE.DoubleSide;
  m.uniforms.uHasUv1.value = o.geometry.attributes.uv1 !== undefined;
  for (const k of ['uDetailMap', 'uTriplanarMap', 'uDecalMap']) m.uniforms[k].value = uniforms[k].value;
  o.material = m;
  materials.push(m);
});

const scene = new THREE.Scene();
scene.add(gltf.scene);
const camera = new THREE.PerspectiveCamera(35, width / height, 0.01, 100);
if (q.get('camera')) {
  const c = q.get('camera').split(',').map(Number);
  if (c.length !== 9 || c.some((v) => !Number.isFinite(v))) throw new Error('camera: expected 9 numbers');
  camera.fov = c[6];
  camera.near = c[7];
  camera.far = c[8];
  camera.position.set(c[0], c[1], c[2]);
  camera.up.set(0, 1, 0);
  camera.lookAt(c[3], c[4], c[5]);
} else {
  // The renderer's automatic framing: azimuth 30, elevation 20 degrees.
  const radius = Math.max(0.5 * box.getSize(new THREE.Vector3()).length(), 1e-3);
  const az = THREE.MathUtils.degToRad(30), el = THREE.MathUtils.degToRad(20);
  const half = THREE.MathUtils.degToRad(camera.fov / 2);
  const halfX = Math.atan(Math.tan(half) * width / height);
  const dist = radius / Math.sin(Math.min(half, halfX));
  const dir = new THREE.Vector3(Math.sin(az) * Math.cos(el), Math.sin(el), Math.cos(az) * Math.cos(el));
  camera.position.copy(center).addScaledVector(dir, dist);
  camera.near = Math.max(dist - 2 * radius, Math.max(dist, radius) * 1e-3);
  camera.far = dist + 3 * radius;
  camera.lookAt(center);
}
camera.updateProjectionMatrix();

function apply() {
  let mask = 0;
  layerNames.forEach((name, i) => { if (state.layers.has(name)) mask |= 1 << i; });
  for (const m of materials) {
    m.uniforms.uLayerMask.value = mask;
    m.uniforms.uBlend.value = blendNames.indexOf(state.blend);
    m.uniforms.uView.value = state.view === 'normal' ? 1 : 0;
  }
  renderer.render(scene, camera);
}

// The panel.
const layerBox = document.getElementById('layers');
for (const name of layerNames) {
  const label = document.createElement('label');
  const box = document.createElement('input');
  box.type = 'checkbox';
  box.checked = state.layers.has(name);
  box.addEventListener('change', () => {
    if (box.checked) state.layers.add(name); else state.layers.delete(name);
    apply();
  });
  label.append(box, ' ' + name);
  layerBox.append(label);
}
for (const id of ['blend', 'view']) {
  const sel = document.getElementById(id);
  sel.value = state[id];
  sel.addEventListener('change', () => { state[id] = sel.value; apply(); });
}
if (q.get('panel') === '0') document.getElementById('panel').style.display = 'none';

// A person orbits the model (not with a fixed camera: the browser test's).
if (!q.get('camera')) {
  const controls = new OrbitControls(camera, renderer.domElement);
  controls.target.copy(center);
  controls.update();
  controls.addEventListener('change', apply);
}
if (!fixedSize) {
  window.addEventListener('resize', () => {
    camera.aspect = window.innerWidth / window.innerHeight;
    camera.updateProjectionMatrix();
    renderer.setSize(window.innerWidth, window.innerHeight);
    apply();
  });
}

apply();
// Programs compile on first use: one more frame, then report.
renderer.render(scene, camera);
window.surfgrad = { ready: true, width, height };
