//! `external`: another renderer's visibility buffer, imported from an image file instead of
//! shaded here, and scored like every technique (`crate::import` reads and checks it). The
//! technique has no shadow map, so it builds no `Technique` and its run reads no depth layers.
//!
//! File names may hold `{scene}`, `{camera}` and `{light}`, filled in per view
//! ([`ExternalParams::for_view`]); in a plan they are relative to the plan file.

use super::canonical::CanonicalFields;
use super::params::{err, non_negative};
use super::{Technique, TechniqueParams, TechniqueSpecError};
use crate::import::{
    DEFAULT_DEPTH_TOLERANCE, ExpectedSize, ImageSource, ImportError, ImportedImage, ReadOptions,
    read_depth_from, read_visibility_from,
};
use crate::scene::Camera;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The placeholders a file name may hold.
const PLACEHOLDERS: [&str; 3] = ["{scene}", "{camera}", "{light}"];

/// `external`: the renderer's `name`, its `visibility` file (EXR or PNG, 1 lit, row 0 at the
/// top unless `flip_y`), optionally its camera `depth` file (distance along the primary ray in
/// world units) and the relative `depth_tolerance`, and the EXR `channel` to read.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExternalParams {
    pub name: String,
    pub visibility: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub depth: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub depth_tolerance: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub channel: Option<String>,
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub flip_y: bool,
}

impl ExternalParams {
    /// The files of one view: each placeholder replaced by the view's name. The names come from
    /// a scene file, so a name that a file's path would read as more than one plain file-name
    /// part (`/`, `\`, NUL, `.`, `..`, nothing) is an error naming it, when a placeholder takes it:
    /// a scene's names never choose which folder a file is read from.
    pub fn for_view(&self, scene: &str, camera: &str, light: &str) -> Result<ExternalParams, String> {
        let uses = |placeholder: &str| {
            self.visibility.contains(placeholder)
                || self.depth.as_deref().is_some_and(|d| d.contains(placeholder))
        };
        for (placeholder, what, name) in
            [("{scene}", "scene", scene), ("{camera}", "camera", camera), ("{light}", "light", light)]
        {
            if uses(placeholder) && !is_plain_file_name_part(name) {
                return Err(format!(
                    "the {what} name {name:?} cannot fill {placeholder} in an external technique's file: \
                     only names without `/`, `\\` or NUL, other than `.` and `..`, make file names"
                ));
            }
        }
        let fill =
            |s: &str| s.replace("{scene}", scene).replace("{camera}", camera).replace("{light}", light);
        Ok(ExternalParams {
            visibility: fill(&self.visibility),
            depth: self.depth.as_deref().map(fill),
            ..self.clone()
        })
    }

    /// The files with relative names taken relative to `base` (a plan file's folder).
    pub fn relative_to(&self, base: &Path) -> ExternalParams {
        let join = |s: &str| base.join(s).to_string_lossy().into_owned();
        ExternalParams {
            visibility: join(&self.visibility),
            depth: self.depth.as_deref().map(join),
            ..self.clone()
        }
    }

    /// How the visibility file is read.
    pub fn read_options(&self) -> ReadOptions {
        ReadOptions { channel: self.channel.clone(), flip_y: self.flip_y }
    }

    /// The visibility file and the depth file (if any) of a view of `camera`, each header checked
    /// to declare the camera's size before a pixel is decoded.
    pub fn read_buffers(
        &self,
        camera: &Camera,
    ) -> Result<(ImportedImage, Option<ImportedImage>), ImportError> {
        let expected = ExpectedSize::of_camera(camera);
        let visibility = read_visibility_from(file(&self.visibility), &self.read_options(), expected)?;
        let depth_options = ReadOptions { channel: None, flip_y: self.flip_y };
        let depth =
            self.depth.as_deref().map(|d| read_depth_from(file(d), &depth_options, expected)).transpose()?;
        Ok((visibility, depth))
    }

    /// The relative depth tolerance (`crate::import`), its default filled in.
    pub fn depth_tolerance(&self) -> f64 {
        self.depth_tolerance.unwrap_or(DEFAULT_DEPTH_TOLERANCE)
    }
}

/// A file named by a technique entry.
fn file(name: &str) -> ImageSource<'_> {
    ImageSource::File(Path::new(name))
}

/// A file name: not empty, and braces only around a known placeholder.
fn file_name(field: &'static str, name: &str) -> Result<(), TechniqueSpecError> {
    if name.is_empty() {
        return Err(err(field, "an empty file name"));
    }
    let mut rest = name.to_string();
    for p in PLACEHOLDERS {
        rest = rest.replace(p, "");
    }
    if rest.contains(['{', '}']) {
        return Err(err(field, format!("\"{name}\": the only placeholders are {}", PLACEHOLDERS.join(", "))));
    }
    Ok(())
}

impl TechniqueParams for ExternalParams {
    fn validate(&self) -> Result<(), TechniqueSpecError> {
        if self.name.trim().is_empty() {
            return Err(err("name", "an empty name: name the renderer"));
        }
        file_name("visibility", &self.visibility)?;
        if let Some(depth) = &self.depth {
            file_name("depth", depth)?;
        }
        if let Some(t) = self.depth_tolerance {
            non_negative("depth_tolerance", t)?;
            if self.depth.is_none() {
                return Err(err("depth_tolerance", "given without a `depth` file"));
            }
        }
        if self.channel.as_deref().is_some_and(str::is_empty) {
            return Err(err("channel", "an empty channel name"));
        }
        Ok(())
    }

    /// None: the visibility is read from the file (the schedule loads it instead of shading).
    fn build(&self) -> Option<Box<dyn Technique>> {
        None
    }

    fn canonical_fields(&self, f: &mut CanonicalFields) {
        f.named("name", &self.name);
        f.named("visibility", &self.visibility);
        if let Some(depth) = &self.depth {
            f.named("depth", depth);
            f.number("depth_tolerance", self.depth_tolerance());
        }
        if let Some(channel) = &self.channel {
            f.named("channel", channel);
        }
        f.flag("flip_y", self.flip_y);
    }
}

/// Whether `name` stays one plain part when put into a path.
fn is_plain_file_name_part(name: &str) -> bool {
    !name.is_empty() && name != "." && name != ".." && !name.contains(['/', '\\', '\0'])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params(visibility: &str) -> ExternalParams {
        ExternalParams {
            name: "r".into(),
            visibility: visibility.into(),
            depth: None,
            depth_tolerance: None,
            channel: None,
            flip_y: false,
        }
    }

    #[test]
    fn placeholders_are_filled_per_view_and_unknown_ones_refused() {
        let p = params("renders/{scene}.{camera}.{light}.exr");
        assert!(p.validate().is_ok());
        assert_eq!(p.for_view("s", "c", "l").unwrap().visibility, "renders/s.c.l.exr");
        for hostile in ["../../x", "/abs", "a\\b", "", ".", "..", "a\0b"] {
            assert!(p.for_view("s", hostile, "l").is_err(), "{hostile:?}");
        }
        // A placeholder the files do not use takes any name.
        let fixed = ExternalParams { visibility: "renders/fixed.exr".into(), ..p.clone() };
        assert!(fixed.for_view("s", "../../x", "l").is_ok());
        let e = params("renders/{view}.exr").validate().unwrap_err();
        assert_eq!(e.field, Some("visibility"));
        let mut p = params("v.exr");
        p.depth_tolerance = Some(0.01);
        assert_eq!(p.validate().unwrap_err().field, Some("depth_tolerance"));
    }
}
