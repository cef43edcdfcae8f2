// The page render.mjs drives: loads scene.glb with Babylon's glTF loader into a right-handed
// scene (glTF and view.json are right-handed), places the camera and the light (directional or
// spot) from view.json, and renders two float passes into render targets: Babylon's own shadow
// factor for the light (StandardMaterial's `shadow`, so its bias, normalBias, depth metric and
// filters run unchanged) and the camera-to-surface distance. window.renderView(view, settings)
// returns both, rows from the top, as base64 f32.

import { Engine } from '@babylonjs/core/Engines/engine.js';
import { Scene } from '@babylonjs/core/scene.js';
import { FreeCamera } from '@babylonjs/core/Cameras/freeCamera.js';
import { DirectionalLight } from '@babylonjs/core/Lights/directionalLight.js';
import { SpotLight } from '@babylonjs/core/Lights/spotLight.js';
import { ShadowGenerator } from '@babylonjs/core/Lights/Shadows/shadowGenerator.js';
import { CascadedShadowGenerator } from '@babylonjs/core/Lights/Shadows/cascadedShadowGenerator.js';
import '@babylonjs/core/Lights/Shadows/shadowGeneratorSceneComponent.js';
import { Vector3, Matrix } from '@babylonjs/core/Maths/math.vector.js';
import { Color3, Color4 } from '@babylonjs/core/Maths/math.color.js';
import { StandardMaterial } from '@babylonjs/core/Materials/standardMaterial.js';
import { ShaderMaterial } from '@babylonjs/core/Materials/shaderMaterial.js';
import { MaterialPluginBase } from '@babylonjs/core/Materials/materialPluginBase.js';
import { RenderTargetTexture } from '@babylonjs/core/Materials/Textures/renderTargetTexture.js';
import { Constants } from '@babylonjs/core/Engines/constants.js';
import { LoadAssetContainerAsync } from '@babylonjs/core/Loading/sceneLoader.js';
import '@babylonjs/loaders/glTF/2.0/index.js';
import '@babylonjs/loaders/glTF/glTFFileLoader.js';
import { captureWarnings, rowsFromTop, base64 } from '/common/page_util.mjs';

const warnings = captureWarnings();

// StandardMaterial computes `shadow`, the light's shadow factor (darkness 0: 0 in shadow), in its
// light loop; its output is replaced by that factor, unlit, before image processing can reach it.
// Clamped to [0, 1]: the cascaded generator's blend between two cascades rounds to 1 + 2⁻²³ on
// lit pixels (a factor is in [0, 1], and `score` refuses anything else).
class ShadowFactorOutput extends MaterialPluginBase {
  constructor(material) {
    super(material, 'ShadowFactorOutput', 1000, {}, true, true);
  }
  getClassName() {
    return 'ShadowFactorOutput';
  }
  getCustomCode(shaderType) {
    return shaderType === 'fragment' ? { CUSTOM_FRAGMENT_BEFORE_FRAGCOLOR: 'color = vec4(clamp(shadow, 0.0, 1.0), 0.0, 0.0, 1.0);' } : null;
  }
}

function visibilityMaterial(scene, backFaceCulling) {
  const m = new StandardMaterial('visibility', scene);
  m.diffuseColor = new Color3(1, 1, 1);
  m.specularColor = new Color3(0, 0, 0);
  m.backFaceCulling = backFaceCulling;
  new ShadowFactorOutput(m);
  return m;
}

function distanceMaterial(scene, backFaceCulling, eye) {
  const m = new ShaderMaterial(
    'distance',
    scene,
    {
      vertexSource: `precision highp float;
        attribute vec3 position;
        uniform mat4 world;
        uniform mat4 viewProjection;
        varying vec3 vWorld;
        void main() {
          vec4 w = world * vec4(position, 1.0);
          vWorld = w.xyz;
          gl_Position = viewProjection * w;
        }`,
      fragmentSource: `precision highp float;
        uniform vec3 eye;
        varying vec3 vWorld;
        void main() { gl_FragColor = vec4(distance(vWorld, eye), 0.0, 0.0, 1.0); }`,
    },
    { attributes: ['position'], uniforms: ['world', 'viewProjection', 'eye'] },
  );
  m.setVector3('eye', eye);
  m.backFaceCulling = backFaceCulling;
  return m;
}

const vec3 = (a) => new Vector3(a[0], a[1], a[2]);

const FILTERS = {
  none: (g) => (g.filter = ShadowGenerator.FILTER_NONE),
  poisson: (g) => (g.usePoissonSampling = true),
  pcf: (g) => (g.usePercentageCloserFiltering = true),
  pcss: (g) => (g.useContactHardeningShadow = true),
  'contact-hardening': (g) => (g.useContactHardeningShadow = true),
  esm: (g) => (g.useExponentialShadowMap = true),
  'blur-esm': (g) => (g.useBlurExponentialShadowMap = true),
  'close-esm': (g) => (g.useCloseExponentialShadowMap = true),
  'blur-close-esm': (g) => (g.useBlurCloseExponentialShadowMap = true),
};
const FILTER_NAMES = {
  [ShadowGenerator.FILTER_NONE]: 'none',
  [ShadowGenerator.FILTER_POISSONSAMPLING]: 'poisson',
  [ShadowGenerator.FILTER_PCF]: 'pcf',
  [ShadowGenerator.FILTER_PCSS]: 'pcss',
  [ShadowGenerator.FILTER_EXPONENTIALSHADOWMAP]: 'esm',
  [ShadowGenerator.FILTER_BLUREXPONENTIALSHADOWMAP]: 'blur-esm',
  [ShadowGenerator.FILTER_CLOSEEXPONENTIALSHADOWMAP]: 'close-esm',
  [ShadowGenerator.FILTER_BLURCLOSEEXPONENTIALSHADOWMAP]: 'blur-close-esm',
};
const QUALITIES = { low: ShadowGenerator.QUALITY_LOW, medium: ShadowGenerator.QUALITY_MEDIUM, high: ShadowGenerator.QUALITY_HIGH };

/** A directional light for the cascaded generator, which fits each cascade's box to a slice of
 * the camera's frustum itself (CascadedShadowGenerator._computeMatrices) and ignores the export's
 * box. */
function cascadedLight(scene, view) {
  const eye = view.light.shadow_map.eye;
  const direction = vec3(eye.target).subtract(vec3(eye.position)).normalize();
  const light = new DirectionalLight('light', direction, scene);
  light.intensity = 1;
  return light;
}

/** A light whose map is the exported one: the box (directional) or the frustum (spot). */
function exportedLight(scene, view) {
  const sm = view.light.shadow_map;
  const eye = sm.eye;
  const position = vec3(eye.position);
  const direction = vec3(eye.target).subtract(position).normalize();
  let light;
  if (view.light.type === 'directional') {
    light = new DirectionalLight('light', direction, scene);
    light.position = position;
    light.autoUpdateExtends = false;
    light.shadowOrthoScale = 0;
  } else if (view.light.type === 'spot') {
    // The cone does not reach the shadow factor; the projection below replaces the one Babylon
    // would build from it.
    light = new SpotLight('light', position, direction, (sm.fov_y_deg * Math.PI) / 180, 0, scene);
  } else {
    throw new Error(`light type ${view.light.type}: only directional and spot lights are rendered`);
  }
  light.intensity = 1;
  // A spot's depth metric is (clip z + shadowMinZ) / (shadowMinZ + shadowMaxZ): with the exported
  // OpenGL projection, the view depth's (d − near) / (far − near). A directional light's is the
  // window depth, (z_ndc + 1) / 2, whatever these are.
  light.shadowMinZ = sm.near;
  light.shadowMaxZ = sm.far;
  // Babylon builds the light's view itself (LookAtLH with world up); the projection undoes it, so
  // that the map's world-to-clip matrix is the exported OpenGL one, box orientation included.
  // Babylon's matrices multiply row vectors: the column-major array is the same matrix. Its
  // left-handed view mirrors x against the export's right-handed one, and Babylon picks the
  // faces it culls in the map for that orientation: the map's x is mirrored back (the same
  // texel grid, read from the other side) so that the casters' front faces stay front faces.
  const clipFromWorld = Matrix.FromArray(sm.opengl.clip_from_world_column_major);
  const mirrorX = Matrix.Scaling(-1, 1, 1);
  light.customProjectionMatrixBuilder = (viewMatrix, _renderList, result) => {
    viewMatrix.clone().invert().multiply(clipFromWorld).multiplyToRef(mirrorX, result);
  };
  return light;
}


async function renderPass(scene, camera, width, height) {
  const target = new RenderTargetTexture('pass', { width, height }, scene, false, true, Constants.TEXTURETYPE_FLOAT, false, Constants.TEXTURE_NEAREST_SAMPLINGMODE);
  target.clearColor = new Color4(0, 0, 0, 0);
  camera.outputRenderTarget = target;
  await scene.whenReadyAsync();
  scene.render();
  const rgba = await target.readPixels();
  camera.outputRenderTarget = null;
  target.dispose();
  return rgba;
}

async function renderView(view, settings) {
  const { width, height } = view.camera;
  const canvas = document.createElement('canvas');
  canvas.width = width;
  canvas.height = height;
  const engine = new Engine(canvas, false, { preserveDrawingBuffer: true, stencil: false, antialias: false, adaptToDeviceRatio: false });
  if (engine.webGLVersion < 2 || !engine.getCaps().textureFloatRender) {
    throw new Error('this WebGL has no float render targets (WebGL2 with EXT_color_buffer_float)');
  }
  engine.setSize(width, height);
  const scene = new Scene(engine);
  scene.useRightHandedSystem = true;
  scene.clearColor = new Color4(0, 0, 0, 0);
  scene.ambientColor = new Color3(0, 0, 0);

  const container = await LoadAssetContainerAsync(`/view/${view.scene_glb}`, scene);
  // Only the meshes: the glb's own lights and cameras are replaced by view.json's.
  const meshes = container.meshes.filter((m) => m.getTotalVertices() > 0);
  container.addAllToScene();
  for (const l of container.lights) l.dispose();
  for (const c of container.cameras) c.dispose();

  const c = view.camera;
  const camera = new FreeCamera('camera', vec3(c.position), scene);
  camera.upVector = vec3(c.up);
  camera.setTarget(vec3(c.look_at));
  camera.fov = c.fov_y_rad;
  camera.fovMode = FreeCamera.FOVMODE_VERTICAL_FIXED;
  camera.minZ = c.near;
  camera.maxZ = c.far;
  scene.activeCamera = camera;

  let generator;
  if (settings.cascades !== undefined) {
    generator = new CascadedShadowGenerator(settings.mapSize, cascadedLight(scene, view), settings.float32, camera);
    generator.numCascades = settings.cascades;
    if (settings.lambda !== undefined) generator.lambda = settings.lambda;
    if (settings.stabilize !== undefined) generator.stabilizeCascades = settings.stabilize;
  } else {
    generator = new ShadowGenerator(settings.mapSize, exportedLight(scene, view), settings.float32);
  }
  if (settings.filter !== undefined) FILTERS[settings.filter](generator);
  generator.filteringQuality = QUALITIES[settings.pcfQuality];
  if (settings.bias !== undefined) generator.bias = settings.bias;
  if (settings.normalBias !== undefined) generator.normalBias = settings.normalBias;
  if (settings.depthScale !== undefined) generator.depthScale = settings.depthScale;

  // The glb's sides: closed objects one-sided, open ones double-sided (docs/conventions.md).
  const culling = new Map(meshes.map((m) => [m, m.material ? m.material.backFaceCulling : true]));
  for (const mesh of meshes) {
    mesh.receiveShadows = true;
    generator.addShadowCaster(mesh, false);
  }

  const started = performance.now();
  for (const mesh of meshes) mesh.material = visibilityMaterial(scene, culling.get(mesh));
  const visibility = rowsFromTop(await renderPass(scene, camera, width, height), width, height, NaN);
  const visibilityMs = performance.now() - started;
  for (const mesh of meshes) mesh.material = distanceMaterial(scene, culling.get(mesh), camera.position);
  const depth = rowsFromTop(await renderPass(scene, camera, width, height), width, height, Infinity);
  const renderMs = performance.now() - started;
  const map = generator.getShadowMap();
  const types = { [Constants.TEXTURETYPE_FLOAT]: 'float32', [Constants.TEXTURETYPE_HALF_FLOAT]: 'float16', [Constants.TEXTURETYPE_UNSIGNED_BYTE]: 'rgba8' };
  return {
    version: Engine.Version,
    generator: settings.cascades !== undefined ? `CascadedShadowGenerator (${generator.numCascades} cascades, lambda ${generator.lambda})` : 'ShadowGenerator',
    filter: FILTER_NAMES[generator.filter] ?? String(generator.filter),
    mapType: types[map.textureType] ?? String(map.textureType),
    bias: generator.bias,
    normalBias: generator.normalBias,
    depthScale: generator.depthScale,
    visibility: base64(visibility),
    depth: base64(depth),
    visibilityMs,
    depthMs: renderMs - visibilityMs,
    renderMs,
    warnings,
  };
}

window.renderView = renderView;
