//! The reference cache under `references/`: one mask PNG per (scene, camera, light) and a
//! manifest with the digest of everything each mask depends on (geometry, camera, light,
//! reference settings, tracer version). A mask whose digest no longer matches is traced again.

use super::TRACER_VERSION;
use crate::atomic_file::{encode_gray_png, write_atomic};
use crate::scene::{Camera, Light, LightKind, Scene};
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

pub const MANIFEST_FORMAT: &str = "shadowtruth/references/v1";

#[derive(Clone, Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Manifest {
    format: String,
    /// Key `scene/camera/light`.
    entries: BTreeMap<String, ManifestEntry>,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct ManifestEntry {
    /// Mask path relative to the cache folder.
    mask: String,
    digest: String,
    width: u32,
    height: u32,
}

/// A mask read back from the cache, in the `MaskCode` encoding.
pub struct CachedReference {
    pub width: u32,
    pub height: u32,
    pub codes: Vec<u8>,
}

/// The digest of what the hard reference of (scene, camera, light) depends on.
pub fn reference_digest(scene: &Scene, camera: &Camera, light: &Light) -> String {
    let mut h = Sha256::new();
    h.update(TRACER_VERSION.as_bytes());
    h.update(b"\0hard\0");
    h.update(scene.geometry_digest().as_bytes());
    let floats = |h: &mut Sha256, xs: &[f32]| xs.iter().for_each(|x| h.update(x.to_bits().to_le_bytes()));
    floats(&mut h, &camera.position.to_array());
    floats(&mut h, &camera.look_at.to_array());
    floats(&mut h, &camera.up.to_array());
    floats(&mut h, &[camera.fov_y_deg]);
    h.update(camera.width.to_le_bytes());
    h.update(camera.height.to_le_bytes());
    match &light.kind {
        LightKind::Directional { direction } => {
            h.update(b"directional");
            floats(&mut h, &direction.to_array());
        }
        LightKind::Spot { position, direction, cone_deg, near, far } => {
            h.update(b"spot");
            floats(&mut h, &position.to_array());
            floats(&mut h, &direction.to_array());
            floats(&mut h, &[*cone_deg, *near, *far]);
        }
    }
    crate::scene::hex(&h.finalize())
}

/// A cache folder (normally `references/`).
pub struct ReferenceCache {
    dir: PathBuf,
}

fn key(scene: &str, camera: &str, light: &str) -> String {
    format!("{scene}/{camera}/{light}")
}

impl ReferenceCache {
    pub fn new(dir: impl Into<PathBuf>) -> Self {
        ReferenceCache { dir: dir.into() }
    }

    pub fn dir(&self) -> &Path {
        &self.dir
    }

    fn manifest_path(&self) -> PathBuf {
        self.dir.join("manifest.json")
    }

    fn read_manifest(&self) -> Manifest {
        std::fs::read(self.manifest_path())
            .ok()
            .and_then(|b| serde_json::from_slice::<Manifest>(&b).ok())
            .filter(|m| m.format == MANIFEST_FORMAT)
            .unwrap_or_else(|| Manifest { format: MANIFEST_FORMAT.into(), entries: BTreeMap::new() })
    }

    /// The digest recorded for a mask, if any.
    pub fn recorded_digest(&self, scene: &str, camera: &str, light: &str) -> Option<String> {
        self.read_manifest().entries.get(&key(scene, camera, light)).map(|e| e.digest.clone())
    }

    /// The path of a cached mask, relative to the cache folder.
    pub fn mask_path(scene: &str, camera: &str, light: &str) -> String {
        format!("{scene}/{camera}__{light}.png")
    }

    /// The cached mask when its recorded digest equals `digest` and the file decodes.
    pub fn load(&self, scene: &str, camera: &str, light: &str, digest: &str) -> Option<CachedReference> {
        let manifest = self.read_manifest();
        let entry = manifest.entries.get(&key(scene, camera, light))?;
        if entry.digest != digest {
            return None;
        }
        let img = image::open(self.dir.join(&entry.mask)).ok()?.into_luma8();
        if img.width() != entry.width || img.height() != entry.height {
            return None;
        }
        Some(CachedReference { width: img.width(), height: img.height(), codes: img.into_raw() })
    }

    /// Writes a mask and records it in the manifest (both atomically).
    pub fn store(
        &self,
        scene: &str,
        camera: &str,
        light: &str,
        digest: &str,
        width: u32,
        height: u32,
        codes: &[u8],
    ) -> std::io::Result<()> {
        let rel = Self::mask_path(scene, camera, light);
        write_atomic(&self.dir.join(&rel), &encode_gray_png(width, height, codes)?)?;
        let mut manifest = self.read_manifest();
        manifest.entries.insert(
            key(scene, camera, light),
            ManifestEntry { mask: rel, digest: digest.into(), width, height },
        );
        let mut text = serde_json::to_string_pretty(&manifest).map_err(std::io::Error::other)?;
        text.push('\n');
        write_atomic(&self.manifest_path(), text.as_bytes())
    }
}

impl ReferenceCache {
    /// The hard reference of (scene, camera, light): read from the cache when its digest matches
    /// and its classes agree with `gbuffer`, traced (and stored) otherwise. Returns whether it
    /// came from the cache.
    pub fn hard_reference(
        &self,
        scene: &Scene,
        bvh: &super::SceneBvh,
        gbuffer: &super::GBuffer,
        camera: &Camera,
        light: &Light,
    ) -> std::io::Result<(super::HardReference, bool)> {
        let digest = reference_digest(scene, camera, light);
        if let Some(cached) = self.load(&scene.name, &camera.name, &light.name, &digest) {
            let reference = super::HardReference::from_mask_codes(cached.width, cached.height, &cached.codes);
            if reference.mask_codes(gbuffer) == cached.codes {
                return Ok((reference, true));
            }
        }
        let reference = super::trace_hard_reference(bvh, gbuffer, light);
        let codes = reference.mask_codes(gbuffer);
        self.store(&scene.name, &camera.name, &light.name, &digest, gbuffer.width, gbuffer.height, &codes)?;
        Ok((reference, false))
    }
}
