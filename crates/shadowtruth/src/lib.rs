//! shadowtruth measures how wrong shadow maps are: an exact ray-traced reference decides, pixel
//! by pixel, what a camera sees lit, and every shadow-map technique — or any renderer's shadow
//! buffer — is scored against it.
//!
//! Data flows one way: [`scene`] → [`trace`] (BVH, G-buffer, references) and [`raster`] (light
//! views, depth layers) → [`technique`] (visibility of every evaluated pixel) → [`metrics`]
//! (false shadow and false lit) → [`record`] (the report's records); [`import`] reads another
//! renderer's buffers to be scored the same way. [`verify`] re-decides the
//! reference with exact predicates. The `shadowtruth` command (crate `shadowtruth-cli`: plans and
//! their schedule, reports, figures, the gate, the papers suite) and the GPU pipeline (crate
//! `shadowtruth-gpu`) are built over this crate's public API.
//!
//! # Scoring a shadow buffer
//!
//! The common embedding: trace the reference of a view once, then score a visibility buffer
//! (1 lit, 0 shadowed, one value per camera pixel) against it.
//!
//! ```
//! use shadowtruth::{SceneBvh, load_scene, score_visibility, trace_scored_view};
//!
//! let scene = load_scene(concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/plane_box.json"))?;
//! let (camera, light) = (&scene.cameras[0], &scene.lights[0]);
//! let bvh = SceneBvh::build(&scene);
//! // The G-buffer with the pixels the reference cannot decide beyond doubt left out (counted in
//! // `uncertain`, scored neither way).
//! let (gbuffer, reference) = trace_scored_view(&scene, &bvh, camera, light);
//!
//! // A renderer that draws everything lit: every shadowed pixel is false lit.
//! let all_lit = vec![1.0; gbuffer.pixel_count()];
//! let counts = score_visibility(&gbuffer, &reference, &all_lit)?;
//! assert_eq!(counts.false_shadow, 0);
//! assert!(counts.false_lit > 0);
//! # Ok::<(), shadowtruth::Error>(())
//! ```

extern crate self as shadowtruth;

mod api;
pub mod atomic_file;
mod error;
pub mod file_name;
pub mod import;
pub mod input_file;
pub mod json_input;
pub mod metrics;
pub mod output_lock;
pub mod raster;
pub mod record;
pub mod scene;
pub mod technique;
pub mod trace;
pub mod verify;

pub use api::{
    cube_map, light_view, load_scene, rasterize_layers, score_imported, score_visibility, shade_technique,
};
pub use error::{Error, Result};
pub use import::{ImportedImage, ReadOptions, read_depth, read_visibility};
pub use metrics::Counts;
pub use raster::{CubeMap, DepthFormat, LightView};
pub use scene::{Camera, Light, Scene};
pub use technique::{BuiltLayers, TechniqueSpec};
pub use trace::{GBuffer, HardReference, SceneBvh, trace_hard_reference, trace_scored_view};

/// The README's Rust examples, compiled and run with the doctests.
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
pub struct ReadmeDoctests;
