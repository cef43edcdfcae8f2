//! A point light's map for one view and resolution (docs/point-lights.md): its faces (a cube's
//! six, or two paraboloids), which of them shades each evaluated pixel, and the record of the
//! run's counts per face and near its seams.

use glam::Vec3;
use rayon::prelude::*;
use shadowtruth::metrics::{LightUv, falseness};
use shadowtruth::raster::{
    CUBE_FACE_NAMES, CubeMap, DualParaboloid, LightView, PARABOLOID_NAMES, SEAM_TEXELS,
};
use shadowtruth::record::{CascadeCounts, PointFaceRecord, PointMapRecord};
use shadowtruth::scene::{Light, LightKind, PointMap};
use shadowtruth::technique::CascadeOrders;
use shadowtruth::trace::{GBuffer, HardReference};

/// The faces of one (camera, point light, resolution), built once and shared by every technique.
pub(crate) struct PointFaces {
    layout: Layout,
    pub orders: CascadeOrders,
    /// Per evaluated pixel, its face and whether it lies near a seam.
    face_of: Vec<(u8, bool)>,
}

enum Layout {
    Cube(CubeMap),
    Paraboloids(DualParaboloid),
}

impl Layout {
    fn views(&self) -> &[LightView] {
        match self {
            Layout::Cube(cube) => &cube.faces,
            Layout::Paraboloids(dp) => &dp.hemispheres,
        }
    }

    fn face_of(&self, p: Vec3) -> usize {
        match self {
            Layout::Cube(cube) => cube.face_of(p),
            Layout::Paraboloids(dp) => dp.hemisphere_of(p),
        }
    }

    /// Texels between `p` in face `face` and the face's edge (a paraboloid's rim).
    fn texels_from_edge(&self, face: usize, p: Vec3) -> Option<f32> {
        match self {
            Layout::Cube(cube) => cube.texels_from_edge(face, p),
            Layout::Paraboloids(dp) => dp.texels_from_rim(face, p),
        }
    }
}

impl PointFaces {
    pub fn new(light: &Light, resolution: u32, gbuffer: &GBuffer) -> Self {
        let layout = match light.kind {
            LightKind::Point { map: PointMap::DualParaboloid, .. } => {
                Layout::Paraboloids(DualParaboloid::new(light, resolution))
            }
            _ => Layout::Cube(CubeMap::new(light, resolution)),
        };
        let face_of: Vec<(u8, bool)> = gbuffer
            .evaluated
            .par_iter()
            .map(|&i| {
                let p = gbuffer.position[i as usize];
                let face = layout.face_of(p);
                let near_seam = layout.texels_from_edge(face, p).is_some_and(|t| t < SEAM_TEXELS);
                (face as u8, near_seam)
            })
            .collect();
        let faces: Vec<u8> = face_of.iter().map(|&(face, _)| face).collect();
        let orders = CascadeOrders::of_faces(gbuffer, layout.views(), &faces);
        PointFaces { layout, orders, face_of }
    }

    /// The faces' light views, in the map's order.
    pub fn views(&self) -> &[LightView] {
        self.layout.views()
    }

    /// The face that shades evaluated pixel `k` (in `gbuffer.evaluated` order).
    pub fn face(&self, k: usize) -> usize {
        self.face_of[k].0 as usize
    }

    /// The light-map position of every evaluated pixel in its face, the faces side by side.
    pub fn light_uv(&self, gbuffer: &GBuffer) -> LightUv {
        let views = self.views();
        LightUv::through_maps(gbuffer, views[0].resolution, |p| {
            let face = self.layout.face_of(p);
            Some((&views[face], face))
        })
        .with_seams(gbuffer, |k| self.face_of[k].1)
    }

    /// The map and the counts of `visibility` (per evaluated pixel) on each face.
    pub fn record(&self, gbuffer: &GBuffer, reference: &HardReference, visibility: &[f32]) -> PointMapRecord {
        let count = self.views().len();
        let mut counts = vec![CascadeCounts::default(); count];
        let mut near_seam = vec![CascadeCounts::default(); count];
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
        let (layout, guard_texels, names): (&str, u32, &[&str]) = match &self.layout {
            Layout::Cube(cube) => ("cube", cube.guard_texels, &CUBE_FACE_NAMES),
            Layout::Paraboloids(_) => ("dual_paraboloid", 0, &PARABOLOID_NAMES),
        };
        let faces = (0..count)
            .map(|f| PointFaceRecord { face: names[f].into(), near_seam: near_seam[f], counts: counts[f] })
            .collect();
        PointMapRecord { layout: layout.into(), guard_texels, face_texels: self.views()[0].resolution, faces }
    }
}
