//! The one interface the render loop needs from a traceable surface, implemented by the exact
//! patch tracer ([`Tracer`]) and by the tessellated comparison path. Static dispatch only: the
//! render loop is generic over it.

use crate::geom::Aabb;
use crate::render::bundle::BundleScratch;
use crate::render::interaction::ShadingPoint;
use crate::render::intersect::{Hit, IntersectCounters, Ray64, Tracer};
use crate::surface::Surface;

/// A surface that rays can be shot at.
pub trait SurfaceTracer: Sync {
    /// The surface (for patch metadata).
    fn surface(&self) -> &Surface;
    /// Bounds of what is traced.
    fn bounds(&self) -> Aabb;
    /// The closest hit with `t ∈ (t_min, t_max)`: patch, `(u, v)` and distance only.
    fn closest_hit(
        &self,
        ray: &Ray64,
        t_min: f64,
        t_max: f64,
        counters: &mut IntersectCounters,
    ) -> Option<Hit>;
    /// The closest hits of `rays` with `t ∈ (t_min, t_max)`, one per entry of `hits`, as
    /// [`SurfaceTracer::closest_hit`] gives them. A tracer may trace rays that share their
    /// origin together (`scratch` holds its buffers); the default traces them one by one.
    fn closest_hits(
        &self,
        rays: &[Ray64],
        t_min: f64,
        t_max: f64,
        hits: &mut [Option<Hit>],
        counters: &mut IntersectCounters,
        scratch: &mut BundleScratch,
    ) {
        let _ = scratch;
        for (ray, hit) in rays.iter().zip(hits) {
            *hit = self.closest_hit(ray, t_min, t_max, counters);
        }
    }
    /// Whether anything lies on the ray with `t ∈ (t_min, t_max)` (a shadow ray): stops at the
    /// first hit found, not the closest. The default asks for the closest hit.
    fn occluded(
        &self,
        ray: &Ray64,
        t_min: f64,
        t_max: f64,
        counters: &mut IntersectCounters,
    ) -> bool {
        self.closest_hit(ray, t_min, t_max, counters).is_some()
    }
    /// The full local geometry at a hit, evaluated once per shaded sample.
    fn shading_point(&self, hit: &Hit, ray: &Ray64) -> ShadingPoint;
    /// Which edges of patch `patch` lie on mesh-face edges (bit e for edge e).
    fn face_edge_mask(&self, patch: u32) -> u8;
    /// Build time of the acceleration structure, milliseconds.
    fn build_ms(&self) -> f64;
    /// Number of BVH primitives.
    fn leaf_count(&self) -> usize;
    /// Bytes of geometry plus acceleration structure, by part (named as in the stats'
    /// `memory_parts`).
    fn memory_parts(&self) -> Vec<(&'static str, usize)>;
    /// Bytes of geometry plus acceleration structure: the sum of
    /// [`SurfaceTracer::memory_parts`].
    fn memory_bytes(&self) -> usize {
        self.memory_parts().iter().map(|(_, bytes)| bytes).sum()
    }
}

impl SurfaceTracer for Tracer<'_> {
    fn surface(&self) -> &Surface {
        self.surface
    }

    fn bounds(&self) -> Aabb {
        self.bounds
    }

    fn closest_hit(
        &self,
        ray: &Ray64,
        t_min: f64,
        t_max: f64,
        counters: &mut IntersectCounters,
    ) -> Option<Hit> {
        Tracer::closest_hit(self, ray, t_min, t_max, counters)
    }

    fn closest_hits(
        &self,
        rays: &[Ray64],
        t_min: f64,
        t_max: f64,
        hits: &mut [Option<Hit>],
        counters: &mut IntersectCounters,
        scratch: &mut BundleScratch,
    ) {
        Tracer::closest_hits(self, rays, t_min, t_max, hits, counters, scratch);
    }

    fn occluded(
        &self,
        ray: &Ray64,
        t_min: f64,
        t_max: f64,
        counters: &mut IntersectCounters,
    ) -> bool {
        Tracer::occluded(self, ray, t_min, t_max, counters)
    }

    fn shading_point(&self, hit: &Hit, ray: &Ray64) -> ShadingPoint {
        let patch = &self.surface.patches[hit.patch as usize];
        ShadingPoint::new(*hit, patch.face, patch.piece, patch.jet(hit.u, hit.v), ray)
    }

    fn face_edge_mask(&self, patch: u32) -> u8 {
        self.face_edges[patch as usize]
    }

    fn build_ms(&self) -> f64 {
        self.bvh.build_time.as_secs_f64() * 1e3
    }

    fn leaf_count(&self) -> usize {
        self.bvh.leaves.len()
    }

    fn memory_parts(&self) -> Vec<(&'static str, usize)> {
        let control_points: usize = self
            .surface
            .patches
            .iter()
            .map(|p| {
                p.as_bezier().map_or(0, |b| {
                    std::mem::size_of_val(b.offsets()) + std::mem::size_of_val(&b.origin())
                })
            })
            .sum();
        let mut parts = self.bvh.memory_parts().to_vec();
        parts.push(("control_points", control_points));
        parts.push(("face_edges", self.face_edges.len()));
        parts
    }
}
