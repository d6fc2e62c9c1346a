//! The exact renderer on blended surfaces (`nielson`, `fang-mann`): watertight from inside,
//! hits on their rays and patches, no NaN anywhere — in particular for rays that meet the
//! surface at or next to a mesh vertex, where the blending weights have no limit.

use glam::DVec3;
use smoothlab::mesh::{Mesh, generate};
use smoothlab::render::IntersectCounters;
use smoothlab::render::{Ray64, Tracer};
use smoothlab::surface::Surface;

fn mesh() -> Mesh {
    smoothlab::testing::mesh(generate::deformed_icosahedron())
}

fn blends(mesh: &Mesh) -> Vec<(String, Surface)> {
    [("nielson", "1"), ("fang-mann", "1"), ("fang-mann", "2")]
        .iter()
        .map(|(scheme, t)| {
            let params = [("t".to_string(), t.to_string())];
            let surface = smoothlab::schemes::build(scheme, mesh, &params).expect("builds");
            (format!("{scheme} t={t}"), surface)
        })
        .collect()
}

/// A deterministic direction on the unit sphere (golden-angle spiral).
fn direction(i: u64, n: u64) -> DVec3 {
    let z = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
    let phi = i as f64 * 2.399_963_229_728_653;
    let r = (1.0 - z * z).sqrt();
    DVec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Points on the mesh at and next to every vertex: the vertex itself and points a fraction
/// `r` of the way towards each incident face's centroid, for r down to 1e-12.
fn near_vertex_targets(mesh: &Mesh) -> Vec<DVec3> {
    let p = mesh.positions();
    let mut out = Vec::new();
    for face in mesh.faces() {
        let centroid = face.iter().map(|&v| p[v as usize]).sum::<DVec3>() / 3.0;
        for &v in face {
            let vertex = p[v as usize];
            out.push(vertex);
            for r in [1e-3, 1e-6, 1e-9, 1e-12] {
                out.push(vertex + (centroid - vertex) * r);
            }
        }
    }
    out
}

fn tracer(surface: &Surface) -> Tracer<'_> {
    Tracer::with_default_settings(surface).expect("tracer")
}

/// Every ray from inside hits: random directions from a few interior origins, and rays aimed
/// exactly at and next to every vertex and at every edge midpoint.
#[test]
fn blends_are_watertight_from_inside() {
    let mesh = mesh();
    let centre = mesh.bounds().center();
    for (label, surface) in blends(&mesh) {
        let tracer = tracer(&surface);
        let mut counters = IntersectCounters::default();
        let mut misses = 0;
        let n = 6000;
        for i in 0..n {
            let origin = centre + DVec3::new(0.05, -0.03, 0.02) * (i % 4) as f64;
            let ray = Ray64::new(origin, direction(i, n));
            if tracer
                .closest_hit(&ray, 0.0, f64::INFINITY, &mut counters)
                .is_none()
            {
                misses += 1;
            }
        }
        let mut targets = near_vertex_targets(&mesh);
        let p = mesh.positions();
        targets.extend(
            mesh.edges()
                .iter()
                .map(|e| 0.5 * (p[e.a as usize] + p[e.b as usize])),
        );
        for target in &targets {
            let ray = Ray64::new(centre, *target - centre);
            if tracer
                .closest_hit(&ray, 0.0, f64::INFINITY, &mut counters)
                .is_none()
            {
                misses += 1;
            }
        }
        println!(
            "{label}: {misses} of {} rays escaped; {counters:?}",
            n as usize + targets.len()
        );
        assert_eq!(misses, 0, "{label}: {misses} rays escaped; {counters:?}");
    }
}

/// Rays from outside: every hit lies on its ray within the renderer's root tolerance, agrees
/// with the brute-force closest hit, and the full jet there (normal, curvature) is finite —
/// also for the rays aimed at and next to the vertices.
#[test]
fn blend_hits_are_accurate_and_finite() {
    let mesh = mesh();
    let centre = mesh.bounds().center();
    let diag = mesh.bounds().diagonal();
    for (label, surface) in blends(&mesh) {
        let tracer = tracer(&surface);
        let mut counters = IntersectCounters::default();
        let (mut worst, mut hits, mut near_vertex_hits) = (0.0_f64, 0, 0);
        let mut rays: Vec<Ray64> = (0..3000u64)
            .map(|i| {
                let origin = centre + direction(i, 3000) * 2.0 * diag;
                let towards = centre + direction((i * 7 + 3) % 3000, 3000) * 0.3 * diag;
                Ray64::new(origin, towards - origin)
            })
            .collect();
        let targets = near_vertex_targets(&mesh);
        let first_target_ray = rays.len();
        for (k, target) in targets.iter().enumerate() {
            // From outside, along the outward direction from the centre (plus a tilt).
            let out = (*target - centre).normalize() + 0.2 * direction(k as u64 % 97, 97);
            rays.push(Ray64::new(*target + out * diag, -out));
        }
        for (i, ray) in rays.iter().enumerate() {
            let Some(hit) = tracer.closest_hit(ray, 0.0, f64::INFINITY, &mut counters) else {
                assert!(
                    i < first_target_ray,
                    "{label}: ray at a vertex target missed"
                );
                continue;
            };
            hits += 1;
            let patch = &surface.patches[hit.patch as usize];
            let jet = patch.jet(hit.u, hit.v);
            worst = worst.max((jet.p - ray.at(hit.t)).length() / diag);
            let n = jet.normal();
            assert!(
                n.is_finite() && (n.length() - 1.0).abs() < 1e-12,
                "{label} ray {i}: {jet:?}"
            );
            let curvature = jet.curvature().expect("regular at every hit");
            assert!(
                curvature.gaussian.is_finite() && curvature.mean.is_finite(),
                "{label} ray {i}: {curvature:?}"
            );
            if i >= first_target_ray {
                near_vertex_hits += 1;
                let target = targets[i - first_target_ray];
                assert!(
                    (jet.p - target).length() <= 0.05 * diag,
                    "{label} ray {i}: hit {} far from its target {target}",
                    jet.p
                );
            }
            if i % 10 == 0 {
                // The same closest hit: at a vertex shared by several patches each patch's root
                // is accepted within the root tolerance of the ray, so the traversal order may
                // pick another patch whose depth differs by up to twice that tolerance.
                let slow = tracer
                    .closest_hit_brute_force(ray, 0.0, f64::INFINITY, &mut counters)
                    .expect("the BVH hit is a hit");
                assert!(
                    (slow.t - hit.t).abs() <= 2.0 * tracer.root_tolerance(),
                    "{label} ray {i}: BVH {hit:?}, brute force {slow:?}"
                );
            }
        }
        let bound = tracer.root_tolerance() / diag;
        println!(
            "{label}: {hits} hits ({near_vertex_hits} at vertex targets), worst hit-to-ray \
             {worst:.1e} x diag (bound {bound:.1e}); {counters:?}"
        );
        assert!(
            worst <= bound && bound < 1e-9,
            "{label}: {worst:e} > {bound:e}"
        );
        assert_eq!(near_vertex_hits, targets.len(), "{label}");
        // Leaves where Newton from the planar start was undecided had their roots found by the
        // in-leaf search: each such root is counted once as a failure and once as a search root.
        assert_eq!(
            counters.newton_failures, counters.fallback_roots,
            "{label}: {counters:?}"
        );
    }
}
