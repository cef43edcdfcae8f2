//! The size an imported image must declare, checked on its header before any pixel is decoded,
//! and whether the file is long enough to hold what its header declares.

use crate::raster::MAX_SHADOW_MAP_RESOLUTION;
use crate::scene::Camera;

/// The largest camera image of a scene (src/scene/format.rs): 16384 a side, 64 megapixels.
const MAX_CAMERA_SIDE: u32 = crate::scene::MAX_IMAGE_SIDE as u32;
const MAX_CAMERA_PIXELS: u64 = crate::scene::MAX_IMAGE_PIXELS;

/// The size an image file must declare (its header is read first; nothing larger is decoded).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExpectedSize {
    /// A buffer of one view: exactly its camera's width × height.
    View { width: u32, height: u32 },
    /// A shadow map whose sidecar declares its resolution: exactly resolution².
    Map { resolution: u32 },
    /// The size is not known: at most `side` a side and `pixels` in all, `largest` saying what
    /// the bound is (in messages).
    AtMost { side: u32, pixels: u64, largest: &'static str },
}

impl ExpectedSize {
    /// Any camera image: a visibility or depth buffer holds one value per camera pixel, and a
    /// camera is at most 16384 a side and 64 megapixels (src/scene/format.rs), so nothing larger
    /// can be any view's (256 MiB as f32).
    pub const ANY_CAMERA: ExpectedSize =
        ExpectedSize::AtMost { side: MAX_CAMERA_SIDE, pixels: MAX_CAMERA_PIXELS, largest: "camera image" };

    /// Any shadow map: square, at most the largest map resolution the tool rasterizes
    /// (`MAX_SHADOW_MAP_RESOLUTION`, 16384²; 1 GiB as f32).
    pub const ANY_SHADOW_MAP: ExpectedSize = ExpectedSize::AtMost {
        side: MAX_SHADOW_MAP_RESOLUTION,
        pixels: MAX_SHADOW_MAP_RESOLUTION as u64 * MAX_SHADOW_MAP_RESOLUTION as u64,
        largest: "shadow map",
    };

    /// Exactly the image of `camera`.
    pub fn of_camera(camera: &Camera) -> ExpectedSize {
        ExpectedSize::View { width: camera.width, height: camera.height }
    }

    /// Whether a header's `width` × `height` is this size; the error says "declares W×H,
    /// expected …W×H".
    pub fn check(self, width: u64, height: u64) -> Result<(), String> {
        let declares = format!("declares {width}×{height}");
        match self {
            ExpectedSize::View { width: w, height: h } if (width, height) != (w as u64, h as u64) => {
                Err(format!("{declares}, expected the camera's {w}×{h}"))
            }
            ExpectedSize::Map { resolution: r } if (width, height) != (r as u64, r as u64) => {
                Err(format!("{declares}, expected {r}×{r} (the sidecar's `resolution`)"))
            }
            ExpectedSize::AtMost { side, pixels, largest }
                if width > side as u64 || height > side as u64 || width * height > pixels =>
            {
                Err(format!(
                    "{declares}, expected at most {side}×{side} and {pixels} pixels (the largest {largest})"
                ))
            }
            _ if width == 0 || height == 0 => Err(format!("{declares}: an empty image")),
            _ => Ok(()),
        }
    }
}

/// Whether a file of `file_bytes` can hold `pixel_bytes` of pixel data compressed at most
/// `max_ratio`:1 (None: no cheap bound): a short file with a large header is refused before its
/// image is allocated.
pub(super) fn check_plausible_length(
    pixel_bytes: u64,
    max_ratio: Option<u64>,
    file_bytes: u64,
    compression: &str,
) -> Result<(), String> {
    let Some(ratio) = max_ratio else { return Ok(()) };
    if pixel_bytes > file_bytes.saturating_mul(ratio) {
        return Err(format!(
            "its header declares {pixel_bytes} bytes of pixels, more than a file of {file_bytes} bytes holds \
             ({compression} compresses at most {ratio}:1): a truncated or forged file"
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_are_checked_against_the_expected_one_or_the_bound() {
        let view = ExpectedSize::View { width: 32, height: 24 };
        assert!(view.check(32, 24).is_ok());
        assert_eq!(view.check(16, 16).unwrap_err(), "declares 16×16, expected the camera's 32×24");
        assert!(ExpectedSize::Map { resolution: 8 }.check(8, 9).unwrap_err().contains("expected 8×8"));
        let any = ExpectedSize::ANY_CAMERA;
        assert!(any.check(16384, 4096).is_ok());
        assert!(any.check(16385, 1).is_err(), "a side above 16384");
        assert!(any.check(16384, 4097).is_err(), "more than 64 megapixels");
        let e = any.check(100_000, 100_000).unwrap_err();
        assert!(e.starts_with("declares 100000×100000, expected at most 16384×16384"), "{e}");
        assert!(ExpectedSize::ANY_SHADOW_MAP.check(16384, 16384).is_ok());
        assert!(any.check(0, 5).unwrap_err().contains("empty"));
    }

    /// The bound is the scene format's: a camera of the largest size loads, one above it does not.
    #[test]
    fn the_camera_bound_is_the_largest_camera_a_scene_may_have() {
        let scene = |width: u32, height: u32| {
            let json = serde_json::json!({
                "format": "shadowtruth/scene/v1", "name": "s",
                "objects": [{ "name": "ground", "shape": { "type": "plane", "size": [8, 8] } }],
                "cameras": [{ "name": "c", "position": [0, 4, 6], "look_at": [0, 0, 0], "fov_y_deg": 45,
                              "width": width, "height": height }],
                "lights": [{ "name": "sun", "type": "directional", "direction": [0, -1, 0] }]
            });
            let text = json.to_string();
            crate::scene::load_scene_str(&text, std::path::Path::new("s.json"), std::path::Path::new("."))
        };
        let side = MAX_CAMERA_SIDE;
        let largest = scene(side, (MAX_CAMERA_PIXELS / side as u64) as u32).unwrap();
        assert!(
            ExpectedSize::ANY_CAMERA
                .check(largest.cameras[0].width as u64, largest.cameras[0].height as u64)
                .is_ok()
        );
        assert!(
            scene(side + 1, 1).is_err() && scene(side, (MAX_CAMERA_PIXELS / side as u64) as u32 + 1).is_err()
        );
    }

    #[test]
    fn a_length_is_plausible_up_to_the_ratio() {
        assert!(check_plausible_length(1032, Some(1032), 1, "zip").is_ok());
        assert!(check_plausible_length(1033, Some(1032), 1, "zip").is_err());
        assert!(check_plausible_length(u64::MAX, None, 1, "dwaa").is_ok());
        assert!(check_plausible_length(u64::MAX, Some(1032), u64::MAX, "zip").is_ok(), "no overflow");
    }
}
