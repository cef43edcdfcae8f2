//! A point light's cube map for one view and resolution (docs/point-lights.md): the six faces,
//! which of them shades each evaluated pixel, and the record of the run's counts per face and
//! near its seams.

use shadowtruth::metrics::{LightUv, falseness};
use shadowtruth::raster::{CUBE_FACE_NAMES, CubeMap, SEAM_TEXELS};
use shadowtruth::record::{CascadeCounts, CubeFaceRecord, CubeRecord};
use shadowtruth::scene::Light;
use shadowtruth::technique::CascadeOrders;
use shadowtruth::trace::{GBuffer, HardReference};

/// The cube of one (camera, point light, resolution), built once and shared by every technique.
pub(crate) struct CubeFaces {
    pub cube: CubeMap,
    pub orders: CascadeOrders,
    /// Per evaluated pixel, its face and whether it lies near a seam.
    face_of: Vec<(u8, bool)>,
}

impl CubeFaces {
    pub fn new(light: &Light, resolution: u32, gbuffer: &GBuffer) -> Self {
        let cube = CubeMap::new(light, resolution);
        let orders = CascadeOrders::of_faces(gbuffer, &cube);
        let face_of = gbuffer
            .evaluated
            .iter()
            .map(|&i| {
                let p = gbuffer.position[i as usize];
                let face = cube.face_of(p);
                let near_seam = cube.texels_from_edge(face, p).is_some_and(|t| t < SEAM_TEXELS);
                (face as u8, near_seam)
            })
            .collect();
        CubeFaces { cube, orders, face_of }
    }

    /// The face that shades evaluated pixel `k` (in `gbuffer.evaluated` order).
    pub fn face(&self, k: usize) -> usize {
        self.face_of[k].0 as usize
    }

    /// The light-map position of every evaluated pixel in its face, the faces side by side.
    pub fn light_uv(&self, gbuffer: &GBuffer) -> LightUv {
        let faces = &self.cube.faces;
        LightUv::through_maps(gbuffer, faces[0].resolution, |p| {
            let face = self.cube.face_of(p);
            Some((&faces[face], face))
        })
    }

    /// The cube and the counts of `visibility` (per evaluated pixel) on each face.
    pub fn record(&self, gbuffer: &GBuffer, reference: &HardReference, visibility: &[f32]) -> CubeRecord {
        let mut counts = [CascadeCounts::default(); 6];
        let mut near_seam = [CascadeCounts::default(); 6];
        for ((&i, &v), &(face, seam)) in gbuffer.evaluated.iter().zip(visibility).zip(&self.face_of) {
            let face = face as usize;
            let tally = |c: &mut CascadeCounts| {
                c.evaluated += 1;
                // A surface mismatch (an imported buffer's NaN) is scored neither way.
                if !v.is_nan() {
                    let (false_shadow, false_lit) = falseness(reference.lit[i as usize] != 0, v);
                    c.false_shadow += false_shadow as u64;
                    c.false_lit += false_lit as u64;
                }
            };
            tally(&mut counts[face]);
            if seam {
                tally(&mut near_seam[face]);
            }
        }
        let faces = (0..6)
            .map(|f| CubeFaceRecord { face: CUBE_FACE_NAMES[f].into(), near_seam: near_seam[f], counts: counts[f] })
            .collect();
        CubeRecord { guard_texels: self.cube.guard_texels, face_texels: self.cube.faces[0].resolution, faces }
    }
}
