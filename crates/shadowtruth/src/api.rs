//! The library's entry points, one per step of scoring a shadow: load a scene, look from the
//! light, rasterize what a technique reads, shade it, score a visibility buffer. Tracing uses
//! [`SceneBvh::build`] and [`trace_scored_view`] (or [`GBuffer::trace`] and
//! [`trace_hard_reference`]) directly.
//!
//! [`SceneBvh::build`]: crate::SceneBvh::build
//! [`GBuffer::trace`]: crate::GBuffer::trace
//! [`trace_hard_reference`]: crate::trace_hard_reference
//! [`trace_scored_view`]: crate::trace_scored_view

use crate::error::{Error, Result};
use crate::import::{ImportedImage, evaluated_visibility};
use crate::metrics::{Counts, score_hard};
use crate::raster::{CubeMap, DepthFormat, LightView, MAX_SHADOW_MAP_RESOLUTION};
use crate::scene::{Camera, Light, Scene};
use crate::technique::{BuiltLayers, ShadeContext, ShadeOrder, TechniqueSpec, shade_evaluated};
use crate::trace::{GBuffer, HardReference};
use std::borrow::Cow;
use std::path::Path;

/// Loads a scene file (`shadowtruth/scene/v1` JSON with its meshes); every problem is reported
/// with its file and JSON path.
///
/// ```
/// let scene = shadowtruth::load_scene(concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/plane_box.json"))?;
/// assert!(scene.triangle_count() > 0);
/// assert_eq!(scene.cameras[0].name, "main");
///
/// let missing = shadowtruth::load_scene("no/such/scene.json").unwrap_err();
/// assert!(missing.to_string().contains("no/such/scene.json"));
/// # Ok::<(), shadowtruth::Error>(())
/// ```
pub fn load_scene(path: impl AsRef<Path>) -> Result<Scene> {
    Ok(crate::scene::load_scene(path.as_ref())?)
}

/// The view of a `resolution`² shadow map of `light`: fitted to the scene's bounds for a
/// directional light, the cone's perspective for a spot light (docs/conventions.md). A point
/// light's map is a cube of six views (`cube_map`), so it has no one view: an error.
///
/// ```
/// # let scene = shadowtruth::load_scene(concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/plane_box.json"))?;
/// let view = shadowtruth::light_view(&scene, &scene.lights[0], 1024)?;
/// assert_eq!(view.resolution, 1024);
/// assert!(shadowtruth::light_view(&scene, &scene.lights[0], 0).is_err());
/// # Ok::<(), shadowtruth::Error>(())
/// ```
pub fn light_view(scene: &Scene, light: &Light, resolution: u32) -> Result<LightView> {
    if !(1..=MAX_SHADOW_MAP_RESOLUTION).contains(&resolution) {
        return Err(Error::Invalid(format!(
            "shadow-map resolution {resolution}: must be between 1 and {MAX_SHADOW_MAP_RESOLUTION}"
        )));
    }
    if light.is_point() {
        return Err(Error::Invalid(format!(
            "light '{}' is a point light: its shadow map is a cube of six views (`cube_map`)",
            light.name
        )));
    }
    Ok(LightView::new(light, scene.bounds(), resolution))
}

/// The six faces of a point light's cube shadow map, each `resolution`² texels plus its guard
/// band (docs/point-lights.md).
///
/// ```
/// # let scene = shadowtruth::load_scene(concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/point/room.json"))?;
/// let cube = shadowtruth::cube_map(&scene.lights[0], 512)?;
/// assert_eq!(cube.faces.len(), 6);
/// assert_eq!(cube.faces[0].resolution, 512 + 2 * cube.guard_texels);
/// # Ok::<(), shadowtruth::Error>(())
/// ```
pub fn cube_map(light: &Light, resolution: u32) -> Result<CubeMap> {
    if !light.is_point() {
        return Err(Error::Invalid(format!("light '{}' is not a point light: it has one view", light.name)));
    }
    if let crate::scene::LightKind::Point { map: crate::scene::PointMap::DualParaboloid, .. } = light.kind {
        return Err(Error::Invalid(format!(
            "light '{}' casts through dual paraboloids (`raster::DualParaboloid`), not a cube",
            light.name
        )));
    }
    if !(1..=MAX_SHADOW_MAP_RESOLUTION).contains(&resolution) {
        return Err(Error::Invalid(format!(
            "shadow-map resolution {resolution}: must be between 1 and {MAX_SHADOW_MAP_RESOLUTION}"
        )));
    }
    Ok(CubeMap::new(light, resolution))
}

/// Rasterizes the depth layers `technique` reads (nearest, two nearest, or a multiple-depth
/// map; with the technique's culling and raster bias) in `format`.
///
/// ```
/// use shadowtruth::{DepthFormat, TechniqueSpec};
/// # let scene = shadowtruth::load_scene(concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/plane_box.json"))?;
/// let view = shadowtruth::light_view(&scene, &scene.lights[0], 512)?;
/// let technique: TechniqueSpec = serde_json::from_str(r#"{"technique": "midpoint"}"#).unwrap();
/// let layers = shadowtruth::rasterize_layers(&scene, &view, DepthFormat::F32, &technique)?;
/// assert!(matches!(layers, shadowtruth::BuiltLayers::TwoNearest(_)));
/// # Ok::<(), shadowtruth::Error>(())
/// ```
pub fn rasterize_layers(
    scene: &Scene,
    view: &LightView,
    format: DepthFormat,
    technique: &TechniqueSpec,
) -> Result<BuiltLayers> {
    Ok(BuiltLayers::build(scene, view, format, &built(technique)?.layer_needs()))
}

/// Shades `technique` at every pixel the G-buffer evaluates, reading `layers` (from
/// [`rasterize_layers`] for the same technique and view). Returns one visibility per camera
/// pixel, row by row from the top (1 lit, 0 shadowed, fractions for filtered techniques);
/// pixels that are not evaluated (background, facing away, outside the light) are 1.
///
/// ```
/// use shadowtruth::{DepthFormat, SceneBvh, TechniqueSpec, trace_scored_view};
/// # let scene = shadowtruth::load_scene(concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/plane_box.json"))?;
/// let (camera, light) = (&scene.cameras[0], &scene.lights[0]);
/// let bvh = SceneBvh::build(&scene);
/// let (gbuffer, reference) = trace_scored_view(&scene, &bvh, camera, light);
///
/// let technique: TechniqueSpec =
///     serde_json::from_str(r#"{"technique": "slope_scaled", "factor": 1.5, "units": 2}"#).unwrap();
/// let view = shadowtruth::light_view(&scene, light, 2048)?;
/// let layers = shadowtruth::rasterize_layers(&scene, &view, DepthFormat::F32, &technique)?;
/// let visibility = shadowtruth::shade_technique(&technique, &scene, &gbuffer, &view, &layers)?;
/// let counts = shadowtruth::score_visibility(&gbuffer, &reference, &visibility)?;
/// assert!(counts.rates().error < 0.05);
/// # Ok::<(), shadowtruth::Error>(())
/// ```
pub fn shade_technique(
    technique: &TechniqueSpec,
    scene: &Scene,
    gbuffer: &GBuffer,
    view: &LightView,
    layers: &BuiltLayers,
) -> Result<Vec<f32>> {
    let built = built(technique)?;
    let order = ShadeOrder::new(gbuffer, view);
    let ctx = ShadeContext::new(scene, gbuffer.footprint, view, layers.as_layers());
    let evaluated = shade_evaluated(built.as_ref(), &order, &ctx);
    let mut image = vec![1.0; gbuffer.pixel_count()];
    for (&pixel, v) in gbuffer.evaluated.iter().zip(evaluated) {
        image[pixel as usize] = v;
    }
    Ok(image)
}

/// Scores a visibility buffer against the reference: `values` holds one value per camera
/// pixel, row by row from the top (`gbuffer.width` × `gbuffer.height`), 1 lit and 0
/// shadowed; a value of ½ or more counts as lit. Only evaluated pixels are scored; every value
/// must still be finite and within [0, 1]. The counts' artefact classes (aliasing, acne, leak)
/// need the shadow map's light view and are left at 0. `reference` must be the hard reference of
/// the G-buffer's view (its size, an error otherwise); the pixels it lists as uncertain are
/// scored neither way, and counted in `uncertain`, whether or not the G-buffer has left them out
/// already ([`trace_scored_view`](crate::trace_scored_view) does).
///
/// ```
/// # use shadowtruth::{GBuffer, SceneBvh, trace_hard_reference};
/// # let scene = shadowtruth::load_scene(concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/plane_box.json"))?;
/// # let bvh = SceneBvh::build(&scene);
/// # let gbuffer = GBuffer::trace(&bvh, &scene.cameras[0], &scene.lights[0]);
/// # let reference = trace_hard_reference(&scene, &bvh, &gbuffer, &scene.lights[0]);
/// // The reference scored against itself: no pixel is wrong.
/// let exact: Vec<f32> = reference.lit.iter().map(|&lit| lit as f32).collect();
/// let counts = shadowtruth::score_visibility(&gbuffer, &reference, &exact)?;
/// assert_eq!((counts.false_shadow, counts.false_lit), (0, 0));
///
/// // A buffer of the wrong size, or a value outside [0, 1], is an error.
/// assert!(shadowtruth::score_visibility(&gbuffer, &reference, &exact[1..]).is_err());
/// let mut bad = exact.clone();
/// bad[0] = f32::NAN;
/// assert!(shadowtruth::score_visibility(&gbuffer, &reference, &bad).is_err());
///
/// // A pixel the reference lists as uncertain is scored neither way, only counted, even by a
/// // G-buffer that still evaluates it: here a wrong value there is no false pixel.
/// let doubtful = gbuffer.evaluated[0];
/// let reference = shadowtruth::HardReference { uncertain: vec![doubtful], ..reference };
/// let mut wrong_there = exact.clone();
/// wrong_there[doubtful as usize] = 1.0 - wrong_there[doubtful as usize];
/// let left_out = shadowtruth::score_visibility(&gbuffer, &reference, &wrong_there)?;
/// assert_eq!((left_out.false_shadow, left_out.false_lit, left_out.uncertain), (0, 0, counts.uncertain + 1));
/// assert_eq!(left_out.evaluated, counts.evaluated - 1);
/// # Ok::<(), shadowtruth::Error>(())
/// ```
pub fn score_visibility(gbuffer: &GBuffer, reference: &HardReference, values: &[f32]) -> Result<Counts> {
    let (width, height) = (gbuffer.width, gbuffer.height);
    if values.len() != gbuffer.pixel_count() {
        return Err(Error::Visibility(format!(
            "{} values for a {width}×{height} view ({} pixels)",
            values.len(),
            gbuffer.pixel_count()
        )));
    }
    if let Some(i) = values.iter().position(|v| !(0.0..=1.0).contains(v)) {
        let (x, y) = (i as u32 % width, i as u32 / width);
        return Err(Error::Visibility(format!("pixel ({x}, {y}) is {}, outside [0, 1]", values[i])));
    }
    let gbuffer = scored_gbuffer(gbuffer, reference)?;
    let evaluated: Vec<f32> = gbuffer.evaluated.iter().map(|&i| values[i as usize]).collect();
    Ok(score_hard(&gbuffer, reference, &evaluated))
}

/// `gbuffer` with the pixels `reference` cannot decide left out: itself when it has left them
/// out already (or there are none), a copy otherwise. A reference of another size, or listing a
/// pixel outside the G-buffer, is an error.
fn scored_gbuffer<'g>(gbuffer: &'g GBuffer, reference: &HardReference) -> Result<Cow<'g, GBuffer>> {
    let n = gbuffer.pixel_count();
    if (reference.width, reference.height) != (gbuffer.width, gbuffer.height) || reference.lit.len() != n {
        return Err(Error::Invalid(format!(
            "a {}×{} reference for a {}×{} G-buffer",
            reference.width, reference.height, gbuffer.width, gbuffer.height
        )));
    }
    if let Some(&i) = reference.uncertain.iter().find(|&&i| i as usize >= n) {
        return Err(Error::Invalid(format!(
            "the reference lists pixel {i} as uncertain, outside the G-buffer"
        )));
    }
    if reference.uncertain_still_evaluated(gbuffer).is_none() {
        return Ok(Cow::Borrowed(gbuffer));
    }
    let mut left_out = gbuffer.clone();
    left_out.leave_out(&reference.uncertain);
    Ok(Cow::Owned(left_out))
}

/// The technique, validated; `external` is refused (its visibility is imported, not shaded).
fn built(technique: &TechniqueSpec) -> Result<Box<dyn crate::technique::Technique>> {
    technique.validate().map_err(|source| Error::Technique { technique: technique.label(), source })?;
    technique.build().ok_or_else(|| {
        Error::Invalid(format!(
            "technique {}: imported from files, not shaded (see score_imported)",
            technique.name()
        ))
    })
}

/// Scores another renderer's buffers against the reference (see [`crate::import`]):
/// `visibility` (from [`read_visibility`](crate::read_visibility)) and optionally its camera
/// `depth` (from [`read_depth`](crate::read_depth)), both the G-buffer's size. Pixels where the
/// renderer drew background, or whose depth differs from the reference's distance by more than
/// `depth_tolerance` (relative, plus [`DEPTH_FLOOR_WORLD`](crate::import::DEPTH_FLOOR_WORLD)),
/// are counted in `surface_mismatch` and scored neither way; the rates are over the other
/// evaluated pixels. `camera` is the G-buffer's. As with [`score_visibility`], the artefact
/// classes are left at 0 and the pixels the reference lists as uncertain are left out.
///
/// ```
/// use shadowtruth::{ImportedImage, SceneBvh, trace_scored_view};
/// use shadowtruth::import::DEFAULT_DEPTH_TOLERANCE;
/// # let scene = shadowtruth::load_scene(concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/plane_box.json"))?;
/// let (camera, light) = (&scene.cameras[0], &scene.lights[0]);
/// let bvh = SceneBvh::build(&scene);
/// let (gbuffer, reference) = trace_scored_view(&scene, &bvh, camera, light);
///
/// // A renderer that agrees with the reference except for one pixel, where it drew background.
/// let mut values: Vec<f32> = reference.lit.iter().map(|&lit| lit as f32).collect();
/// values[gbuffer.evaluated[0] as usize] = f32::NAN;
/// let image = ImportedImage { path: "render.exr".into(), width: camera.width, height: camera.height, values };
/// let counts = shadowtruth::score_imported(&gbuffer, camera, &reference, &image, None, DEFAULT_DEPTH_TOLERANCE)?;
/// assert_eq!((counts.false_shadow, counts.false_lit, counts.surface_mismatch), (0, 0, 1));
/// assert_eq!(counts.scored(), counts.evaluated - 1);
/// # Ok::<(), shadowtruth::Error>(())
/// ```
pub fn score_imported(
    gbuffer: &GBuffer,
    camera: &Camera,
    reference: &HardReference,
    visibility: &ImportedImage,
    depth: Option<&ImportedImage>,
    depth_tolerance: f64,
) -> Result<Counts> {
    if (camera.width, camera.height) != (gbuffer.width, gbuffer.height) {
        return Err(Error::Invalid(format!("camera {} is not the G-buffer's", camera.name)));
    }
    let gbuffer = scored_gbuffer(gbuffer, reference)?;
    let evaluated = evaluated_visibility(&gbuffer, camera, visibility, depth, depth_tolerance)?;
    Ok(score_hard(&gbuffer, reference, &evaluated))
}
