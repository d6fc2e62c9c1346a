//! Watertightness of the exact renderer on every scheme: no ray slips between two patches.
//!
//! - From inside: on the scanned meshes and every generated closed scene, cameras at the three
//!   deepest interior points of the mesh look along the six axes (150° field of view) and shoot
//!   random directions; every ray from inside a closed surface must hit it. Over a million rays
//!   per scheme.
//! - Grazing: from points a millionth of the diagonal above patch seams, rays along the seam
//!   descend at 1°, 3° and 10° to the tangent plane; each must hit the surface right there.

use glam::DVec3;
use rayon::prelude::*;
use smoothlab::mesh::Mesh;
use smoothlab::mesh::generate::{SCANNED_SCENES, SCENES};
use smoothlab::render::IntersectCounters;
use smoothlab::render::{Camera, Projection};
use smoothlab::render::{Ray64, Tracer};
use smoothlab::surface::{Surface, edge_uv};
use smoothlab::testing::render::{sphere_direction, uniform};

/// Every test mesh with its name: the scanned ones first.
fn meshes() -> Vec<(String, Mesh)> {
    let mut out: Vec<(String, Mesh)> = SCANNED_SCENES
        .iter()
        .map(|s| (s.name.to_string(), s.mesh().expect("scanned mesh loads")))
        .collect();
    out.extend(
        SCENES
            .iter()
            .map(|s| (s.name.to_string(), s.mesh().expect("scene mesh builds"))),
    );
    out
}

/// Closest point of the triangle `abc` to `p` (Voronoi regions of the vertices, edges and face).
fn closest_on_triangle(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> DVec3 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

/// The winding number of the closed mesh around `p` (sum of the faces' signed solid angles,
/// Van Oosterom–Strackee) and the distance from `p` to the mesh.
fn winding_and_distance(mesh: &Mesh, p: DVec3) -> (f64, f64) {
    let pos = mesh.positions();
    let mut solid = 0.0;
    let mut distance = f64::INFINITY;
    for f in mesh.faces() {
        let [a, b, c] = f.map(|v| pos[v as usize]);
        let (x, y, z) = (a - p, b - p, c - p);
        let (lx, ly, lz) = (x.length(), y.length(), z.length());
        let numerator = x.dot(y.cross(z));
        let denominator = lx * ly * lz + x.dot(y) * lz + y.dot(z) * lx + z.dot(x) * ly;
        solid += 2.0 * numerator.atan2(denominator);
        distance = distance.min((closest_on_triangle(p, a, b, c) - p).length());
    }
    (solid / (4.0 * std::f64::consts::PI), distance)
}

/// The three interior points of a 16³ grid over the mesh's box that lie deepest inside it
/// (largest distance to the mesh), with that depth relative to the diagonal.
fn deepest_interior_points(mesh: &Mesh) -> Vec<(DVec3, f64)> {
    let bounds = mesh.bounds();
    let n = 16;
    let mut inside: Vec<(DVec3, f64)> = (0..n * n * n)
        .into_par_iter()
        .filter_map(|k| {
            let cell = DVec3::new((k % n) as f64, ((k / n) % n) as f64, (k / (n * n)) as f64);
            let p = bounds.min + (bounds.max - bounds.min) * (cell + 0.5) / n as f64;
            let (winding, distance) = winding_and_distance(mesh, p);
            (winding > 0.5).then_some((p, distance / bounds.diagonal()))
        })
        .collect();
    inside.sort_by(|a, b| b.1.total_cmp(&a.1));
    inside.truncate(3);
    inside
}

/// Rays from `eye`: six 150° axis views of `side`² pixels and `random` uniform directions.
fn rays_from(eye: DVec3, side: u32, random: u64, seed: u64) -> Vec<Ray64> {
    let mut rays = Vec::new();
    for axis in [
        DVec3::X,
        -DVec3::X,
        DVec3::Y,
        -DVec3::Y,
        DVec3::Z,
        -DVec3::Z,
    ] {
        let up = if axis.y.abs() > 0.5 {
            DVec3::Z
        } else {
            DVec3::Y
        };
        let camera = Camera::look_at(
            eye,
            eye + axis,
            up,
            Projection::Perspective { fov_deg: 150.0 },
        )
        .expect("camera");
        for k in 0..side * side {
            let (x, y) = (k % side, k / side);
            let to_plane = |i: u32| 2.0 * (f64::from(i) + 0.5) / f64::from(side) - 1.0;
            rays.push(camera.ray(to_plane(x), to_plane(y), 1.0));
        }
    }
    rays.extend((0..random).map(|i| Ray64::new(eye, sphere_direction(seed, i))));
    rays
}

/// Rays in `rays` that find no hit, with the summed intersection counters.
fn misses(tracer: &Tracer, rays: &[Ray64]) -> (Vec<Ray64>, IntersectCounters) {
    rays.par_chunks(4096)
        .map(|chunk| {
            let mut counters = IntersectCounters::default();
            let missed: Vec<Ray64> = chunk
                .iter()
                .filter(|ray| {
                    tracer
                        .closest_hit(ray, 0.0, f64::INFINITY, &mut counters)
                        .is_none()
                })
                .copied()
                .collect();
            (missed, counters)
        })
        .reduce(
            || (Vec::new(), IntersectCounters::default()),
            |(mut a, mut ca), (b, cb)| {
                a.extend(b);
                ca.add(&cb);
                (a, ca)
            },
        )
}

fn build(scheme: &str, mesh: &Mesh) -> Surface {
    smoothlab::schemes::build(scheme, mesh, &[])
        .unwrap_or_else(|e| panic!("{scheme} builds on a closed mesh: {e}"))
}

/// Shoots the inside rays of every mesh at one scheme's surfaces; returns (rays, misses).
fn inside_rays(scheme: &str) -> (usize, Vec<String>) {
    let mut total = 0;
    let mut failures = Vec::new();
    for (name, mesh) in meshes() {
        let scanned = SCANNED_SCENES.iter().any(|s| s.name == name);
        let (side, random) = if scanned { (96, 40_000) } else { (40, 12_000) };
        let surface = build(scheme, &mesh);
        let tracer = Tracer::with_default_settings(&surface).expect("tracer");
        for (c, (eye, depth)) in deepest_interior_points(&mesh).into_iter().enumerate() {
            let rays = rays_from(eye, side, random, 1000 + c as u64);
            total += rays.len();
            let (missed, counters) = misses(&tracer, &rays);
            println!(
                "{scheme:>9} {name:>20} camera {c} (depth {depth:.3}): {} rays, {} misses, \
                 {} undecided, {} fallback roots",
                rays.len(),
                missed.len(),
                counters.undecided,
                counters.fallback_roots
            );
            if !missed.is_empty() {
                failures.push(format!(
                    "{name}: {} of {} rays from {eye} escaped, e.g. along {}",
                    missed.len(),
                    rays.len(),
                    missed[0].dir
                ));
            }
        }
    }
    (total, failures)
}

/// Outward unit normal of the mesh face nearest to `p` (the test meshes are consistently
/// oriented outward): the side of the surface a point just above `p` must be on.
fn outward_near(mesh: &Mesh, p: DVec3) -> DVec3 {
    let pos = mesh.positions();
    let nearest = mesh
        .faces()
        .iter()
        .map(|f| {
            let [a, b, c] = f.map(|v| pos[v as usize]);
            (
                (closest_on_triangle(p, a, b, c) - p).length(),
                (b - a).cross(c - a),
            )
        })
        .min_by(|x, y| x.0.total_cmp(&y.0))
        .expect("faces");
    nearest.1.normalize()
}

/// Where `ray` first meets `surface` before `t_end`, by an independent method: every patch whose
/// control-net box the segment crosses is tessellated into `2 · 512²` flat triangles (chord
/// error ~`κ h² / 8` with `h` ≈ patch size / 512, far below the rays' 1e-6 × diagonal
/// height) and intersected in f64 (Möller–Trumbore).
fn reference_hit(surface: &Surface, ray: &Ray64, t_end: f64) -> Option<f64> {
    const N: usize = 512;
    let end = ray.origin + ray.dir * t_end;
    let segment_box = (ray.origin.min(end), ray.origin.max(end));
    let mut best: Option<f64> = None;
    for patch in &surface.patches {
        let b = patch.full_bounds();
        if b.max.cmplt(segment_box.0).any() || b.min.cmpgt(segment_box.1).any() {
            continue;
        }
        let grid: Vec<Vec<DVec3>> = (0..=N)
            .map(|j| {
                (0..=N - j)
                    .map(|i| patch.eval(i as f64 / N as f64, j as f64 / N as f64))
                    .collect()
            })
            .collect();
        let mut hit = |a: DVec3, b: DVec3, c: DVec3| {
            let (e1, e2) = (b - a, c - a);
            let p = ray.dir.cross(e2);
            let det = e1.dot(p);
            if det == 0.0 {
                return;
            }
            let s = ray.origin - a;
            let u = s.dot(p) / det;
            let q = s.cross(e1);
            let v = ray.dir.dot(q) / det;
            let t = e2.dot(q) / det;
            if u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > 0.0 && t < best.unwrap_or(t_end) {
                best = Some(t);
            }
        };
        for j in 0..N {
            for i in 0..N - j {
                hit(grid[j][i], grid[j][i + 1], grid[j + 1][i]);
                if i + 1 < N - j {
                    hit(grid[j][i + 1], grid[j + 1][i + 1], grid[j + 1][i]);
                }
            }
        }
    }
    best
}

/// Grazing rays along seams: from `1e-6 × diagonal` above a point of a patch boundary (on the
/// outside), along the seam turned by up to 15° towards the patch, descending at 1°, 3° and
/// 10° to it. Most enter the surface right there (within twice the planar distance
/// `ε / sin α`); where the tracer reports no hit or a farther one, [`reference_hit`] decides:
/// a ray is wrong when the reference meets the surface before the tracer's hit (by more than
/// the reference's own accuracy). Where the surface curves away from the ray faster than the
/// ray descends (a saddle or a concave seam), the farther hit is the right one.
fn grazing_misses(scheme: &str, mesh: &Mesh, points: u64) -> Vec<String> {
    let surface = &build(scheme, mesh);
    let tracer = &Tracer::with_default_settings(surface).expect("tracer");
    let eps = 1e-6 * surface.bounds().diagonal();
    (0..points)
        .into_par_iter()
        .flat_map_iter(|i| {
            let patch_index = (uniform(501, i, 0, 0) * surface.patches.len() as f64) as usize;
            let patch_index = patch_index.min(surface.patches.len() - 1);
            let patch = &surface.patches[patch_index];
            let edge = (uniform(501, i, 0, 1) * 3.0) as usize % 3;
            let uv = edge_uv(edge, 0.02 + 0.96 * uniform(501, i, 0, 2));
            let jet = patch.jet(uv.x, uv.y);
            let mut n = jet.normal();
            if n.dot(outward_near(mesh, jet.p)) < 0.0 {
                n = -n;
            }
            let along_uv = edge_uv(edge, 1.0) - edge_uv(edge, 0.0);
            let along = jet.du * along_uv.x + jet.dv * along_uv.y;
            let along = (along - n * along.dot(n)).normalize();
            // Turned towards the patch's own side of the seam: across a crease (C0 schemes) the
            // neighbour may fall away faster than the ray descends.
            let inward_uv = glam::DVec2::splat(1.0 / 3.0) - uv;
            let side = n.cross(along);
            let side = if side.dot(jet.du * inward_uv.x + jet.dv * inward_uv.y) < 0.0 {
                -side
            } else {
                side
            };
            let turn = uniform(501, i, 0, 3) * 15f64.to_radians();
            let sign = if uniform(501, i, 0, 4) < 0.5 { -1.0 } else { 1.0 };
            let tangent = along * (turn.cos() * sign) + side * turn.sin();
            let eye = jet.p + n * eps;
            let p = jet.p;
            let mut counters = IntersectCounters::default();
            [1.0_f64, 3.0, 10.0].into_iter().filter_map(move |deg| {
                let alpha = deg.to_radians();
                let ray = Ray64::new(eye, tangent * alpha.cos() - n * alpha.sin());
                let limit = 2.0 * eps / alpha.sin();
                let found = tracer.closest_hit(&ray, 0.0, f64::INFINITY, &mut counters);
                if found.is_some_and(|hit| hit.t <= limit) {
                    return None;
                }
                // The reference looks up to the tracer's hit, or 1000 planar distances.
                let t_end = found.map_or(500.0 * limit, |hit| hit.t);
                let reference = reference_hit(surface, &ray, t_end)?;
                // A tenth of the planar distance: the reference's height error (chord error of
                // 512² triangles per patch) over the ray's slope stays well below it.
                let slack = 0.1 * limit;
                (reference < t_end - slack).then(|| {
                    format!(
                        "patch {patch_index} edge {edge} at {p}, {deg}°: {found:?}, but the surface is met at t = {reference} (limit {limit:e}); ray {:?} {:?}",
                        ray.origin.to_array(),
                        ray.dir.to_array()
                    )
                })
            })
        })
        .collect()
}

/// Every scheme, every closed test mesh, over 10^6 rays per scheme from inside: 0 misses.
#[test]
fn every_scheme_is_watertight_from_inside_scanned_and_generated_meshes() {
    let mut report = Vec::new();
    for scheme in smoothlab::schemes::names() {
        let (rays, failures) = inside_rays(scheme);
        assert!(rays >= 1_000_000, "{scheme}: only {rays} rays");
        report.extend(failures.into_iter().map(|f| format!("{scheme}: {f}")));
    }
    assert!(report.is_empty(), "{}", report.join("\n"));
}

/// Grazing rays along seams of the scanned bunny: no ray reports a farther hit (or none) where
/// the independent reference meets the surface first.
#[test]
fn grazing_rays_along_seams_hit_where_they_enter() {
    let bunny = SCANNED_SCENES[0].mesh().expect("bunny");
    let mut report = Vec::new();
    for scheme in smoothlab::schemes::names() {
        let grazing = grazing_misses(scheme, &bunny, 4000);
        let none = grazing.iter().filter(|f| f.contains("None")).count();
        println!(
            "{scheme:>9} grazing: 12000 rays, {} wrong (no hit: {none})",
            grazing.len()
        );
        report.extend(grazing.into_iter().map(|f| format!("{scheme}: {f}")));
    }
    assert!(
        report.is_empty(),
        "{} rays:\n{}",
        report.len(),
        report.join("\n")
    );
}
