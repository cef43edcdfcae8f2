//! The `path` field of cameras and lights in scene files:
//! `{"interpolation": "linear" | "catmull_rom", "keys": [{"time": t, ...}, ...]}`, each key
//! holding the values its owner moves (a camera's `position` and `look_at`, a light's
//! `direction`, and a spot light's `position`).

use super::path::{CameraPath, Interpolation, Keyframes, LightPath};
use crate::json_input::{Reader, as_array_of, as_number, as_string};
use glam::DVec3;

/// A path's keys, read: per key its time and the named vectors in the order asked for.
struct ReadKeys {
    interpolation: Interpolation,
    times: Vec<f64>,
    /// `tracks[j][i]`: the j-th named vector of key i.
    tracks: Vec<Vec<DVec3>>,
}

impl ReadKeys {
    fn track(&self, j: usize) -> Keyframes {
        Keyframes {
            interpolation: self.interpolation,
            times: self.times.clone(),
            values: self.tracks[j].clone(),
        }
    }
}

/// Reads a path whose keys each hold the vectors `fields` (`direction` fields must be non-zero).
fn read_keys(r: &mut Reader, fields: &[&'static str]) -> Option<ReadKeys> {
    let interpolation = r.optional_or("interpolation", as_interpolation, Interpolation::CatmullRom);
    let items = r.array("keys")?;
    if items.is_empty() {
        r.problem("keys", "must contain at least one key");
        return None;
    }
    let read = r.each("keys", items, |k| {
        let time = k.required("time", as_number);
        let vectors: Vec<Option<DVec3>> = fields
            .iter()
            .map(|&f| k.required(f, if f == "direction" { as_nonzero } else { as_dvec3 }))
            .collect();
        Some((time?, vectors.into_iter().collect::<Option<Vec<DVec3>>>()?))
    });
    if read.len() != items.len() || read.iter().any(Option::is_none) {
        return None;
    }
    let read: Vec<(f64, Vec<DVec3>)> = read.into_iter().flatten().collect();
    if let Some(i) = read.windows(2).position(|w| w[1].0 <= w[0].0) {
        r.problem(&format!("keys[{}].time", i + 1), "must be greater than the previous key's time");
        return None;
    }
    Some(ReadKeys {
        interpolation: interpolation?,
        times: read.iter().map(|k| k.0).collect(),
        tracks: (0..fields.len()).map(|j| read.iter().map(|k| k.1[j]).collect()).collect(),
    })
}

/// A camera's path: keys of `position` and `look_at`.
pub(super) fn read_camera_path(r: &mut Reader) -> Option<CameraPath> {
    let keys = read_keys(r, &["position", "look_at"])?;
    Some(CameraPath { position: keys.track(0), look_at: keys.track(1) })
}

/// A light's path: keys of `direction`, and of `position` too for a spot light.
pub(super) fn read_light_path(r: &mut Reader, spot: bool) -> Option<LightPath> {
    let fields: &[&'static str] = if spot { &["direction", "position"] } else { &["direction"] };
    let keys = read_keys(r, fields)?;
    Some(LightPath { direction: keys.track(0), position: spot.then(|| keys.track(1)) })
}

fn as_interpolation(v: &serde_json::Value) -> Result<Interpolation, String> {
    let name = as_string(v)?;
    Interpolation::parse(&name)
        .ok_or(format!("unknown interpolation \"{name}\"; expected linear or catmull_rom"))
}

fn as_dvec3(v: &serde_json::Value) -> Result<DVec3, String> {
    // Rounded through f32 as every other scene vector is.
    Ok(DVec3::from(as_array_of::<3>(v)?).as_vec3().as_dvec3())
}

fn as_nonzero(v: &serde_json::Value) -> Result<DVec3, String> {
    let d = as_dvec3(v)?;
    match d.try_normalize() {
        Some(_) => Ok(d),
        None => Err("must have a non-zero length".into()),
    }
}
