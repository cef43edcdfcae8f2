// The page render.mjs drives: loads scene.glb with three's GLTFLoader, places the camera and the
// light (with its shadow camera) from view.json, and renders two float passes into render
// targets: three's own shadow factor for the light (getShadowMask, the code three's materials
// shade with, so its bias, normalBias, PCF and VSM run unchanged) and the camera-to-surface
// distance. window.renderView(view, settings) returns both, rows from the top, as base64 f32.

import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { captureWarnings, rowsFromTop, base64 } from '/common/page_util.mjs';

const warnings = captureWarnings();

// three's ShadowMaterial shader with its output replaced by the shadow factor itself, unlit and
// without tone mapping or colour-space conversion.
function visibilityMaterial(side) {
  const shadow = THREE.ShaderLib.shadow;
  const body = 'gl_FragColor = vec4( getShadowMask(), 0.0, 0.0, 1.0 );\n}';
  const fragment = shadow.fragmentShader.slice(0, shadow.fragmentShader.indexOf('gl_FragColor')) + body;
  return new THREE.ShaderMaterial({
    uniforms: THREE.UniformsUtils.clone(shadow.uniforms),
    vertexShader: shadow.vertexShader,
    fragmentShader: fragment,
    lights: true,
    side,
  });
}

function depthMaterial(side) {
  return new THREE.ShaderMaterial({
    vertexShader: `
      varying vec3 vWorldPosition;
      void main() {
        vec4 world = modelMatrix * vec4( position, 1.0 );
        vWorldPosition = world.xyz;
        gl_Position = projectionMatrix * viewMatrix * world;
      }`,
    fragmentShader: `
      varying vec3 vWorldPosition;
      void main() { gl_FragColor = vec4( distance( vWorldPosition, cameraPosition ), 0.0, 0.0, 1.0 ); }`,
    side,
  });
}

function vec3(a) {
  return new THREE.Vector3(a[0], a[1], a[2]);
}

// A point light: three draws its own cube (six 90° faces of mapSize², hardware face selection,
// no guard band) from the light's position with the exported near and far.
function makePointLight(light) {
  const map = light.shadow_map;
  const l = new THREE.PointLight(0xffffff, 1, map.far, 0);
  l.shadow.camera = new THREE.PerspectiveCamera(90, 1, map.near, map.far);
  l.position.copy(vec3(light.position));
  return l;
}

function makeLight(light, settings) {
  const l = light.type === 'point' ? makePointLight(light) : makeDirectedLight(light);
  l.castShadow = true;
  l.shadow.mapSize.set(settings.mapSize, settings.mapSize);
  l.shadow.bias = settings.bias;
  l.shadow.normalBias = settings.normalBias;
  l.shadow.radius = settings.radius;
  l.shadow.blurSamples = settings.blurSamples;
  return l;
}

function makeDirectedLight(light) {
  const map = light.shadow_map;
  const eye = map.eye;
  let l;
  if (light.type === 'directional') {
    l = new THREE.DirectionalLight(0xffffff, 1);
    l.shadow.camera = new THREE.OrthographicCamera(map.left, map.right, map.top, map.bottom, map.near, map.far);
  } else if (light.type === 'spot') {
    // three sets the shadow camera's fov from the angle (fov = 2·angle·focus), its aspect from
    // the map and its far from the light's distance.
    l = new THREE.SpotLight(0xffffff, 1, map.far, THREE.MathUtils.degToRad(map.fov_y_deg / 2), 0, 0);
    l.shadow.camera = new THREE.PerspectiveCamera(map.fov_y_deg, map.aspect, map.near, map.far);
    l.shadow.focus = 1;
  } else {
    throw new Error(`light type ${light.type}`);
  }
  l.position.copy(vec3(eye.position));
  l.target.position.copy(vec3(eye.target));
  // three's shadow camera does lookAt(target) with its own up: the map's basis needs the exported up.
  l.shadow.camera.up.copy(vec3(eye.up));
  return l;
}

function readRows(renderer, target, width, height, fill) {
  const rgba = new Float32Array(4 * width * height);
  renderer.readRenderTargetPixels(target, 0, 0, width, height, rgba);
  return rowsFromTop(rgba, width, height, fill);
}

async function renderView(view, settings) {
  const { width, height } = view.camera;
  const canvas = document.createElement('canvas');
  const renderer = new THREE.WebGLRenderer({ canvas, antialias: false, alpha: true });
  const gl = renderer.getContext();
  if (!(gl instanceof WebGL2RenderingContext) || !gl.getExtension('EXT_color_buffer_float')) {
    throw new Error('this WebGL has no float render targets (WebGL2 with EXT_color_buffer_float)');
  }
  renderer.setPixelRatio(1);
  renderer.setSize(width, height, false);
  renderer.setClearColor(0x000000, 0);
  renderer.shadowMap.enabled = true;
  renderer.shadowMap.type = THREE[settings.shadowType];
  renderer.shadowMap.autoUpdate = true;

  const gltf = await new GLTFLoader().loadAsync(`/view/${view.scene_glb}`);
  const scene = new THREE.Scene();
  const meshes = [];
  gltf.scene.traverse((o) => {
    if (o.isMesh) meshes.push(o);
  });
  // Only the meshes: the glb's own lights and cameras are replaced by view.json's.
  for (const mesh of meshes) {
    mesh.updateMatrixWorld(true);
    const world = mesh.matrixWorld.clone();
    mesh.removeFromParent();
    mesh.matrixAutoUpdate = false;
    mesh.matrix.copy(world);
    mesh.castShadow = true;
    mesh.receiveShadow = true;
    // The glb's sides: closed objects one-sided, open ones double-sided (docs/conventions.md).
    mesh.userData.side = mesh.material.side;
    scene.add(mesh);
  }
  const light = makeLight(view.light, settings);
  scene.add(light);
  if (light.target) scene.add(light.target);

  const c = view.camera;
  const camera = new THREE.PerspectiveCamera(c.fov_y_deg, width / height, c.near, c.far);
  camera.position.copy(vec3(c.position));
  camera.up.copy(vec3(c.up));
  camera.lookAt(vec3(c.look_at));
  camera.updateMatrixWorld(true);

  const target = new THREE.WebGLRenderTarget(width, height, {
    type: THREE.FloatType,
    format: THREE.RGBAFormat,
    minFilter: THREE.NearestFilter,
    magFilter: THREE.NearestFilter,
    depthBuffer: true,
  });
  renderer.setRenderTarget(target);

  const started = performance.now();
  for (const mesh of meshes) mesh.material = visibilityMaterial(mesh.userData.side);
  renderer.render(scene, camera);
  const visibility = readRows(renderer, target, width, height, NaN);
  const visibilityMs = performance.now() - started;

  for (const mesh of meshes) mesh.material = depthMaterial(mesh.userData.side);
  renderer.shadowMap.autoUpdate = false;
  renderer.render(scene, camera);
  const depth = readRows(renderer, target, width, height, Infinity);
  const renderMs = performance.now() - started;
  return {
    revision: THREE.REVISION,
    visibility: base64(visibility),
    depth: base64(depth),
    visibilityMs,
    depthMs: renderMs - visibilityMs,
    renderMs,
    warnings,
  };
}

window.renderView = renderView;
