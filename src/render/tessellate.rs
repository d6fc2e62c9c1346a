//! The tessellated comparison path (`--tessellate N`): every patch becomes a regular grid of
//! N segments per edge (N² triangles) with positions and normals evaluated at the grid points
//! and stored in f32, as a mesh viewer would hold them; shading uses the barycentric
//! interpolation of the vertex normals (Phong normals). This is the baseline that tools
//! evaluating on a tessellation show: its stripes depend on N. It goes through the same obvhs
//! BVH and the same render loop as the exact path.
//!
//! Curvature is not defined on a piecewise-flat mesh: the shading point has zero second
//! derivatives, so curvature mode shows zero there (not the patch's curvature).

use std::time::{Duration, Instant};

use glam::{DVec2, DVec3, Vec2, Vec3};
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::builder::build_cwbvh;
use rayon::prelude::*;

use crate::error::{Error, Problem, Result};
use crate::geom::{Aabb, Jet};
use crate::render::bvh::{box_padding, build_params, outward_f32};
use crate::render::interaction::ShadingPoint;
use crate::render::intersect::{Hit, IntersectCounters, Ray64, closest_in_bvh};
use crate::render::trace::SurfaceTracer;
use crate::surface::{Patch, Surface};

/// One grid vertex: position, unit normal and patch parameters, in f32.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TessVertex {
    /// Position.
    pub position: Vec3,
    /// Unit normal of the patch there.
    pub normal: Vec3,
    /// Patch parameters `(u, v)`.
    pub uv: Vec2,
}

/// A tessellated surface with its BVH.
pub struct TessellatedTracer<'s> {
    surface: &'s Surface,
    /// Vertices of all patches.
    pub vertices: Vec<TessVertex>,
    /// Triangles as vertex indices plus patch index, in BVH primitive order.
    pub triangles: Vec<([u32; 3], u32)>,
    bvh: CwBvh,
    build_time: Duration,
    padding: f64,
    bounds: Aabb,
    face_edges: Vec<u8>,
    level: u32,
}

/// Vertex index of grid point (i, j) (u = i/N, v = j/N, i + j ≤ N) of a patch's grid.
fn grid_index(n: u32, i: u32, j: u32) -> u32 {
    // Rows of constant j hold N + 1 − j points.
    j * (n + 1) - j * (j.saturating_sub(1)) / 2 + i
}

/// Peak bytes per triangle of building a tessellated tracer: the f32 vertices (about half a
/// vertex per triangle), the triangle list in build and BVH order, the primitive boxes and the
/// BVH builder's temporaries. Measured as the peak resident memory of `render --tessellate N`
/// on the 80 `hb` patches of `scenes/icosahedron.obj`: 297 B per triangle at N = 128 and at
/// N = 256; rounded up.
pub(crate) const TESSELLATION_BYTES_PER_TRIANGLE: f64 = 320.0;

/// The estimated peak memory of tessellating `patches` patches with `n` segments per edge.
pub(crate) fn estimated_bytes(patches: usize, n: u32) -> f64 {
    patches as f64 * f64::from(n) * f64::from(n) * TESSELLATION_BYTES_PER_TRIANGLE
}

impl<'s> TessellatedTracer<'s> {
    /// Tessellates every patch of `surface` with `n` segments per edge and builds the BVH.
    /// The memory ([`estimated_bytes`]) is checked against the memory limit and the vertex
    /// count against the u32 indices first, before anything is allocated.
    pub fn new(surface: &'s Surface, n: u32) -> Result<TessellatedTracer<'s>> {
        let max = crate::budget::MAX_TESS;
        if n == 0 || n as usize > max {
            let message = format!("tessellation level {n} must be in 1..={max}");
            return Err(Error::config("--tessellate", Problem::Stated { message }));
        }
        if surface.patches.is_empty() {
            return Err(Error::Invalid(format!(
                "surface of scheme '{}' has no patches to render",
                surface.scheme
            )));
        }
        let what = format!(
            "the tessellation of {} patches at --tessellate {n}",
            surface.patches.len()
        );
        let remedy = "lower --tessellate (render.tessellate)";
        crate::budget::check_memory(&what, estimated_bytes(surface.patches.len(), n), remedy)?;
        let per_patch = (u64::from(n) + 1) * (u64::from(n) + 2) / 2;
        let vertex_count = per_patch * surface.patches.len() as u64;
        if vertex_count > u64::from(u32::MAX) {
            return Err(Error::TooLarge {
                what,
                estimate: format!("{vertex_count} vertices"),
                limit: format!("{} vertices (32-bit indices)", u32::MAX),
                remedy: remedy.into(),
            });
        }
        let start = Instant::now();
        let per_patch_vertices = ((n + 1) * (n + 2) / 2) as usize;
        let grids: Vec<Vec<TessVertex>> = surface
            .patches
            .par_iter()
            .map(|patch| {
                let mut grid = Vec::with_capacity(per_patch_vertices);
                for j in 0..=n {
                    for i in 0..=n - j {
                        let (u, v) = (f64::from(i) / f64::from(n), f64::from(j) / f64::from(n));
                        let jet = patch.jet(u, v);
                        grid.push(TessVertex {
                            position: jet.p.as_vec3(),
                            normal: jet.normal().as_vec3(),
                            uv: Vec2::new(u as f32, v as f32),
                        });
                    }
                }
                grid
            })
            .collect();
        let vertices: Vec<TessVertex> = grids.into_iter().flatten().collect();
        let mut triangles = Vec::with_capacity(surface.patches.len() * (n * n) as usize);
        for p in 0..surface.patches.len() as u32 {
            let base = p * per_patch_vertices as u32;
            for j in 0..n {
                for i in 0..n - j {
                    let a = base + grid_index(n, i, j);
                    let b = base + grid_index(n, i + 1, j);
                    let c = base + grid_index(n, i, j + 1);
                    triangles.push(([a, b, c], p));
                    if i + j + 1 < n {
                        let d = base + grid_index(n, i + 1, j + 1);
                        triangles.push(([b, d, c], p));
                    }
                }
            }
        }
        let bounds = vertices
            .iter()
            .fold(Aabb::EMPTY, |b, v| b.union_point(v.position.as_dvec3()));
        let padding = box_padding(&bounds);
        let boxes: Vec<obvhs::aabb::Aabb> = triangles
            .iter()
            .map(|(t, _)| {
                let b = Aabb::from_points(&t.map(|i| vertices[i as usize].position.as_dvec3()));
                outward_f32(&b, padding)
            })
            .collect();
        let bvh = build_cwbvh(&boxes, build_params(), &mut Duration::default());
        let triangles = bvh
            .primitive_indices
            .iter()
            .map(|&i| triangles[i as usize])
            .collect();
        Ok(TessellatedTracer {
            surface,
            vertices,
            triangles,
            bvh,
            build_time: start.elapsed(),
            padding,
            bounds,
            face_edges: surface.patches.iter().map(Patch::face_edge_mask).collect(),
            level: n,
        })
    }

    /// Möller–Trumbore in f64 on the f32 vertices; barycentrics may overshoot by 1e-7 so that
    /// rays through shared edges are not lost to rounding.
    fn intersect_triangle(&self, tri: [u32; 3], ray: &Ray64) -> Option<(f64, f64, f64)> {
        let [a, b, c] = tri.map(|i| self.vertices[i as usize].position.as_dvec3());
        let (e1, e2) = (b - a, c - a);
        let pvec = ray.dir.cross(e2);
        let det = e1.dot(pvec);
        if det.abs() < crate::tolerance::DIVISION_GUARD {
            return None;
        }
        let inv = 1.0 / det;
        let tvec = ray.origin - a;
        let b1 = tvec.dot(pvec) * inv;
        let qvec = tvec.cross(e1);
        let b2 = ray.dir.dot(qvec) * inv;
        const SLACK: f64 = 1e-7;
        if b1 < -SLACK || b2 < -SLACK || b1 + b2 > 1.0 + SLACK {
            return None;
        }
        Some((e2.dot(qvec) * inv, b1, b2))
    }
}

impl SurfaceTracer for TessellatedTracer<'_> {
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
        _counters: &mut IntersectCounters,
    ) -> Option<Hit> {
        closest_in_bvh(&self.bvh, self.padding, ray, t_min, t_max, |id, best_t| {
            let (tri, patch) = self.triangles[id];
            let (t, b1, b2) = self.intersect_triangle(tri, ray)?;
            if t <= t_min || t >= best_t {
                return None;
            }
            let [a, b, c] = tri.map(|i| self.vertices[i as usize].uv.as_dvec2());
            let uv = a * (1.0 - b1 - b2) + b * b1 + c * b2;
            Some(Hit {
                t,
                patch,
                u: uv.x,
                v: uv.y,
            })
        })
    }

    fn shading_point(&self, hit: &Hit, ray: &Ray64) -> ShadingPoint {
        let patch = &self.surface.patches[hit.patch as usize];
        let (normal, [va, vb, vc], upper) = self.interpolate(hit.patch, hit.u, hit.v);
        let n = self.grid_level();
        let position = ray.at(hit.t);
        let scale = f64::from(n);
        let (du, dv) = if upper {
            (vb.position - vc.position, vb.position - va.position)
        } else {
            (vb.position - va.position, vc.position - va.position)
        };
        let jet = Jet {
            p: position,
            du: du.as_dvec3() * scale,
            dv: dv.as_dvec3() * scale,
            ..Jet::default()
        };
        ShadingPoint::with_normal(*hit, patch.face, patch.piece, jet, normal, ray)
    }

    fn face_edge_mask(&self, patch: u32) -> u8 {
        self.face_edges[patch as usize]
    }

    fn build_ms(&self) -> f64 {
        self.build_time.as_secs_f64() * 1e3
    }

    fn leaf_count(&self) -> usize {
        self.triangles.len()
    }

    fn memory_parts(&self) -> Vec<(&'static str, usize)> {
        vec![
            ("vertices", std::mem::size_of_val(self.vertices.as_slice())),
            (
                "triangles",
                std::mem::size_of_val(self.triangles.as_slice()),
            ),
            (
                "bvh_nodes",
                std::mem::size_of_val(self.bvh.nodes.as_slice())
                    + std::mem::size_of_val(self.bvh.primitive_indices.as_slice()),
            ),
        ]
    }
}

impl TessellatedTracer<'_> {
    /// The interpolated (Phong) normal of the tessellation at patch parameters `(u, v)`, with
    /// the three vertices of the grid triangle containing them and whether it is an upper
    /// (i+1,j)–(i+1,j+1)–(i,j+1) triangle.
    pub fn interpolate(&self, patch: u32, u: f64, v: f64) -> (DVec3, [TessVertex; 3], bool) {
        let n = self.grid_level();
        let base = patch * ((n + 1) * (n + 2) / 2);
        let uv = DVec2::new(u, v) * f64::from(n);
        let i = (uv.x.floor().max(0.0) as u32).min(n - 1);
        let j = (uv.y.floor().max(0.0) as u32).min(n - 1 - i);
        let (fu, fv) = (uv.x - f64::from(i), uv.y - f64::from(j));
        let upper = fu + fv > 1.0 && i + j + 1 < n;
        let (tri, w) = if upper {
            let tri = [
                base + grid_index(n, i + 1, j),
                base + grid_index(n, i + 1, j + 1),
                base + grid_index(n, i, j + 1),
            ];
            // Barycentrics of (fu, fv) in the cell's upper triangle (1,0), (1,1), (0,1).
            (tri, DVec3::new(1.0 - fv, fu + fv - 1.0, 1.0 - fu))
        } else {
            let tri = [
                base + grid_index(n, i, j),
                base + grid_index(n, i + 1, j),
                base + grid_index(n, i, j + 1),
            ];
            (tri, DVec3::new(1.0 - fu - fv, fu, fv))
        };
        let vertices = tri.map(|k| self.vertices[k as usize]);
        let [va, vb, vc] = vertices;
        let normal =
            (va.normal.as_dvec3() * w.x + vb.normal.as_dvec3() * w.y + vc.normal.as_dvec3() * w.z)
                .normalize_or_zero();
        (normal, vertices, upper)
    }

    /// Largest angle (radians) between the interpolated normal and the exact patch normal over
    /// `samples` quasi-random parameter points per patch.
    pub fn max_normal_error(&self, samples: u32) -> f64 {
        let mut worst = 0.0_f64;
        for (p, patch) in self.surface.patches.iter().enumerate() {
            for k in 0..samples {
                // R2 low-discrepancy points folded into the triangle.
                let a = (0.5 + f64::from(k) * 0.754_877_666_246_692_7).fract();
                let b = (0.5 + f64::from(k) * 0.569_840_290_998_053_3).fract();
                let (u, v) = if a + b > 1.0 {
                    (1.0 - a, 1.0 - b)
                } else {
                    (a, b)
                };
                let exact = patch.jet(u, v).normal();
                let (approx, _, _) = self.interpolate(p as u32, u, v);
                worst = worst.max(approx.angle_between(exact));
            }
        }
        worst
    }

    /// Segments per patch edge.
    pub fn grid_level(&self) -> u32 {
        self.level
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::test_support::assert_config_error;
    use crate::testing::surfaces::octahedron_sphere;

    #[test]
    fn a_level_out_of_range_is_a_config_error() {
        let surface = octahedron_sphere(2, 1.0, 0);
        let Err(err) = TessellatedTracer::new(&surface, 0) else {
            panic!("level 0 accepted");
        };
        let max = crate::budget::MAX_TESS;
        let text = format!("tessellation level 0 must be in 1..={max}");
        assert_config_error(
            &err,
            "--tessellate",
            |p| matches!(p, Problem::Stated { .. }),
            text,
        );
    }

    #[test]
    fn grid_indices_are_dense() {
        let n = 5;
        let mut seen = vec![false; ((n + 1) * (n + 2) / 2) as usize];
        for j in 0..=n {
            for i in 0..=n - j {
                let k = grid_index(n, i, j) as usize;
                assert!(!seen[k], "({i},{j}) repeats index {k}");
                seen[k] = true;
            }
        }
        assert!(seen.iter().all(|&s| s));
    }

    /// Hits of the tessellation lie on its triangles, and the interpolated normal approaches
    /// the exact one as N grows.
    #[test]
    fn tessellation_converges_to_the_surface() {
        let surface = octahedron_sphere(3, 1.0, 0);
        let mut errors = Vec::new();
        for n in [4u32, 16] {
            let tracer = TessellatedTracer::new(&surface, n).expect("tessellation");
            assert_eq!(tracer.grid_level(), n);
            assert_eq!(
                tracer.leaf_count(),
                surface.patches.len() * (n * n) as usize
            );
            let mut worst = 0.0_f64;
            let mut counters = IntersectCounters::default();
            for k in 0..200 {
                let dir = DVec3::new(
                    (k as f64 * 0.37).sin(),
                    (k as f64 * 0.91).cos(),
                    0.5 + (k % 7) as f64 * 0.1,
                );
                let ray = Ray64::new(DVec3::ZERO, dir);
                let hit = tracer
                    .closest_hit(&ray, 0.0, f64::INFINITY, &mut counters)
                    .expect("closed surface: rays from inside hit");
                let sp = tracer.shading_point(&hit, &ray);
                let exact = surface.patches[hit.patch as usize]
                    .jet(hit.u, hit.v)
                    .normal();
                worst = worst.max(sp.normal.angle_between(exact));
            }
            errors.push(worst);
        }
        assert!(
            errors[1] < 0.25 * errors[0],
            "normal error must shrink: {errors:?}"
        );
    }
}
