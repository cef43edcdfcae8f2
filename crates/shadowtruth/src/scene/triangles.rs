//! The scene's triangle ids: flat triangles first, then each instance's triangles in turn.
//! Every stage that reads triangles by id or walks all of them goes through these methods, so
//! flat and instanced geometry are read by the same rules (src/scene/instance.rs).

use super::{Instance, Scene, is_degenerate, world_vertex};
use glam::Vec3;
use std::ops::Range;

/// Where a scene triangle id lives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TriangleSource {
    /// An index into `Scene::flat_triangles`.
    Flat(usize),
    /// Triangle `local` of the mesh placed by instance `instance`.
    Instanced { instance: usize, local: usize },
}

impl Scene {
    /// The number of triangle ids: flat triangles and every instance's.
    pub fn triangle_count(&self) -> usize {
        match self.instances.last() {
            Some(last) => last.first_triangle as usize + self.instance_triangle_count(last),
            None => self.flat_triangles.len(),
        }
    }

    fn instance_triangle_count(&self, instance: &Instance) -> usize {
        self.meshes[instance.mesh as usize].triangles.len()
    }

    /// Where triangle `id` is stored. Panics when `id` is not a triangle of the scene.
    pub fn triangle_source(&self, id: u32) -> TriangleSource {
        let flat = self.flat_triangles.len();
        if (id as usize) < flat {
            return TriangleSource::Flat(id as usize);
        }
        let instance = self.instances.partition_point(|i| i.first_triangle <= id) - 1;
        let local = (id - self.instances[instance].first_triangle) as usize;
        assert!(local < self.instance_triangle_count(&self.instances[instance]), "no triangle {id}");
        TriangleSource::Instanced { instance, local }
    }

    /// The world-space vertices of triangle `id`.
    pub fn triangle(&self, id: u32) -> [Vec3; 3] {
        match self.triangle_source(id) {
            TriangleSource::Flat(i) => self.flat_triangles[i],
            TriangleSource::Instanced { instance, local } => {
                let instance = &self.instances[instance];
                instance.triangle(&self.meshes[instance.mesh as usize], local)
            }
        }
    }

    /// The object of triangle `id`.
    pub fn object_of(&self, id: u32) -> u32 {
        match self.triangle_source(id) {
            TriangleSource::Flat(i) => self.flat_triangle_object[i],
            TriangleSource::Instanced { instance, .. } => self.instances[instance].object,
        }
    }

    /// Whether triangle `id` belongs to a closed object.
    pub fn is_closed(&self, id: u32) -> bool {
        self.objects.get(self.object_of(id) as usize).is_some_and(|o| o.closed)
    }

    /// The triangles with ids in `ids`, in id order, as (id, world vertices); instanced
    /// triangles that are degenerate in world space are skipped, as flattening drops them.
    pub fn triangles_in(&self, ids: Range<u32>) -> impl Iterator<Item = (u32, [Vec3; 3])> + '_ {
        let flat_end = (self.flat_triangles.len() as u32).clamp(ids.start, ids.end.max(ids.start));
        let flat = (ids.start..flat_end).map(|id| (id, self.flat_triangles[id as usize]));
        let first_instance =
            self.instances.partition_point(|i| i.first_triangle <= flat_end).saturating_sub(1);
        let instanced = self.instances[first_instance.min(self.instances.len())..]
            .iter()
            .take_while(move |i| i.first_triangle < ids.end)
            .flat_map(move |instance| {
                let mesh = &self.meshes[instance.mesh as usize];
                let start = flat_end.max(instance.first_triangle);
                let end = ids.end.min(instance.first_triangle + mesh.triangles.len() as u32);
                // Each vertex transformed once when the range reads at least as many corners as
                // the mesh has vertices (a chunk of a placed tree, a whole object), rather than
                // once per corner: the same `world_vertex` of the same vertex, so the same bits.
                let corners = 3 * end.saturating_sub(start) as usize;
                let world: Vec<Vec3> = if corners >= mesh.positions.len() {
                    mesh.positions.iter().map(|&p| world_vertex(&instance.world_from_local, p)).collect()
                } else {
                    Vec::new()
                };
                (start..end).filter_map(move |id| {
                    let local = (id - instance.first_triangle) as usize;
                    let tri = if world.is_empty() {
                        instance.triangle(mesh, local)
                    } else {
                        instance.triangle_of(&world, mesh, local)
                    };
                    (!is_degenerate(&tri)).then_some((id, tri))
                })
            });
        flat.chain(instanced)
    }

    /// Every triangle, in id order (see [`Scene::triangles_in`]).
    pub fn triangles(&self) -> impl Iterator<Item = (u32, [Vec3; 3])> + '_ {
        self.triangles_in(0..self.triangle_count() as u32)
    }

    /// The triangles of object `index`, in id order.
    pub fn object_triangles(&self, index: usize) -> impl Iterator<Item = [Vec3; 3]> + '_ {
        let o = &self.objects[index];
        self.triangles_in(o.first_triangle..o.first_triangle + o.triangle_count).map(|(_, tri)| tri)
    }
}
