//! Control-net preparation [UP §2]: a (half-)box-spline patch exists only where its subnet
//! is regular, and a hole corresponds to exactly one irregular vertex only when irregular
//! vertices are far enough apart. The input mesh is therefore refined until every two
//! irregular vertices (valence ≠ 6) are at least `k + 2` edges apart, so that each one is
//! surrounded by `k + 1` rings of regular vertices, as UP §2 requires.
//!
//! The refinement rule is Loop's (Loop 1987) for every `k`: edge points
//! `3/8 (a + b) + 1/8 (c + d)`, vertex points `(1 − nβ) v + β Σ neighbours` with
//! `β = (5/8 − (3/8 + cos(2π/n)/4)²)/n`. For `k = 2` this is the box spline's own refinement in
//! regular regions (the refined net defines the same quartic box-spline surface there). For
//! other `k` the refined net is a different control net of the same shape class (the
//! higher-order box-spline masks reach over two or more rings and have no established rule
//! next to an irregular vertex); the surface is the (half-)box spline of the refined net.
//! Loop refinement creates no new irregular vertices and doubles graph distances, so the
//! number of levels is `⌈log₂((k + 2) / d₀)⌉` for the smallest distance `d₀` of two irregular
//! vertices of the input, at most [`MAX_LEVELS`].
//!
//! Every refined face remembers the input face it lies in and its corners' barycentric
//! coordinates there (exact dyadic fractions), which become the patches' `face` and `domain`.

use std::collections::{HashMap, VecDeque};

use glam::DVec3;

use crate::error::{Error, Result};
use crate::mesh::{LoadOptions, Mesh};

/// Most refinement levels tried before the mesh is refused (4⁵ = 1024 faces per input face).
pub(crate) const MAX_LEVELS: usize = 5;

/// A refined control net with the input face each of its faces comes from.
#[derive(Clone, Debug)]
pub(crate) struct RefinedNet {
    /// The refined mesh (vertices keep the numbering of the refinement).
    pub mesh: Mesh,
    /// For each refined face, the input face containing it.
    pub origin: Vec<u32>,
    /// For each refined face, its corners' barycentric coordinates in the input face.
    pub domain: Vec<[DVec3; 3]>,
    /// Number of Loop steps applied.
    pub levels: usize,
}

/// Positions, faces, and per face the input face and the domain corners.
type RefinedParts = (Vec<DVec3>, Vec<[u32; 3]>, Vec<u32>, Vec<[DVec3; 3]>);

/// One Loop subdivision step of a closed mesh, with the ancestry of the new faces.
fn loop_step(mesh: &Mesh, origin: &[u32], domain: &[[DVec3; 3]]) -> RefinedParts {
    let positions = mesh.positions();
    let mut out: Vec<DVec3> = (0..mesh.vertex_count() as u32)
        .map(|v| {
            let ring = mesh.one_ring(v);
            let n = ring.len() as f64;
            let c = 3.0 / 8.0 + 0.25 * (std::f64::consts::TAU / n).cos();
            let beta = (5.0 / 8.0 - c * c) / n;
            let sum: DVec3 = ring.iter().map(|&w| positions[w as usize]).sum();
            (1.0 - n * beta) * positions[v as usize] + beta * sum
        })
        .collect();
    let mut edge_vertex: HashMap<(u32, u32), u32> = HashMap::new();
    let mut faces = Vec::with_capacity(4 * mesh.face_count());
    let mut new_origin = Vec::with_capacity(4 * mesh.face_count());
    let mut new_domain = Vec::with_capacity(4 * mesh.face_count());
    for (f, face) in mesh.faces().iter().enumerate() {
        let mut mid = [0u32; 3];
        for e in 0..3 {
            let (a, b) = (face[e], face[(e + 1) % 3]);
            let key = (a.min(b), a.max(b));
            mid[e] = *edge_vertex.entry(key).or_insert_with(|| {
                let c = face[(e + 2) % 3];
                // The opposite corner across the edge (the mesh is closed).
                let (g, ge) = mesh
                    .neighbor(f as u32, e)
                    .expect("gk refines closed meshes only");
                let d = mesh.faces()[g as usize][(ge + 2) % 3];
                let p = |v: u32| positions[v as usize];
                out.push(0.375 * (p(a) + p(b)) + 0.125 * (p(c) + p(d)));
                out.len() as u32 - 1
            });
        }
        let [a, b, c] = *face;
        let [ab, bc, ca] = mid;
        let [da, db, dc] = domain[f];
        let (dab, dbc, dca) = (0.5 * (da + db), 0.5 * (db + dc), 0.5 * (dc + da));
        for (tri, dom) in [
            ([a, ab, ca], [da, dab, dca]),
            ([ab, b, bc], [dab, db, dbc]),
            ([ca, bc, c], [dca, dbc, dc]),
            ([ab, bc, ca], [dab, dbc, dca]),
        ] {
            faces.push(tri);
            new_origin.push(origin[f]);
            new_domain.push(dom);
        }
    }
    (out, faces, new_origin, new_domain)
}

/// The smallest graph distance between two distinct irregular vertices, with one of the two
/// (`None` if there are fewer than two).
pub(crate) fn irregular_separation(mesh: &Mesh) -> Option<(usize, u32)> {
    let n = mesh.vertex_count();
    let mut dist = vec![usize::MAX; n];
    let mut source = vec![u32::MAX; n];
    let mut queue = VecDeque::new();
    for v in 0..n as u32 {
        if mesh.valence(v) != 6 {
            dist[v as usize] = 0;
            source[v as usize] = v;
            queue.push_back(v);
        }
    }
    let mut best: Option<(usize, u32)> = None;
    while let Some(v) = queue.pop_front() {
        for &w in mesh.one_ring(v) {
            let (vi, wi) = (v as usize, w as usize);
            if dist[wi] == usize::MAX {
                dist[wi] = dist[vi] + 1;
                source[wi] = source[vi];
                queue.push_back(w);
            } else if source[wi] != source[vi] {
                let d = dist[vi] + dist[wi] + 1;
                if best.is_none_or(|(b, _)| d < b) {
                    best = Some((d, source[vi]));
                }
            }
        }
    }
    best
}

/// Refines `mesh` by Loop's rule until irregular vertices are at least `k + 2` edges apart.
///
/// Errors: an irregular vertex still closer than that to another after [`MAX_LEVELS`] steps
/// cannot happen for a valid closed mesh (distances double each step), but a refined net that
/// fails validation is reported with the input vertex count it came from.
pub(crate) fn prepare(mesh: &Mesh, k: usize) -> Result<RefinedNet> {
    let whole = crate::surface::WHOLE_FACE;
    let mut net = RefinedNet {
        mesh: mesh.clone(),
        origin: (0..mesh.face_count() as u32).collect(),
        domain: vec![whole; mesh.face_count()],
        levels: 0,
    };
    loop {
        let separation = irregular_separation(&net.mesh);
        match separation {
            Some((d, _)) if d < k + 2 => {}
            _ => return Ok(net),
        }
        if net.levels == MAX_LEVELS {
            let (d, v) = separation.expect("checked above");
            return Err(Error::Invalid(format!(
                "gk: irregular vertex {v} of the {}-times refined net is {d} edges from \
                 another, fewer than the k + 2 = {} needed",
                net.levels,
                k + 2
            )));
        }
        let (positions, faces, origin, domain) = loop_step(&net.mesh, &net.origin, &net.domain);
        let expected = positions.len();
        // The refined net of a closed manifold mesh needs no repair; one that would (faces
        // collapsed to needles of zero area in f64, as a stray vertex far from the rest makes)
        // would leave holes and faces out of step with their ancestry.
        let strict = LoadOptions {
            strict: true,
            ..LoadOptions::default()
        };
        let (refined, _) = Mesh::from_triangles_with(positions, faces, &strict).map_err(|_| {
            Error::Invalid(format!(
                "gk: Loop refinement level {} produced a net that is not a clean closed mesh \
                 (its vertices or faces coincide in f64): the mesh has faces too thin for Loop's \
                 rule, as a vertex far from the others makes; repair the mesh, or use another \
                 scheme",
                net.levels + 1
            ))
        })?;
        if refined.vertex_count() != expected {
            return Err(Error::Invalid(format!(
                "gk: Loop refinement level {} produced coinciding vertices",
                net.levels + 1
            )));
        }
        net = RefinedNet {
            mesh: refined,
            origin,
            domain,
            levels: net.levels + 1,
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::closed_test_meshes;

    /// Every closed test mesh is refined until its irregular vertices are k + 2 apart, with 4
    /// faces per face per level, domains that tile each input face (areas sum to 1), and the
    /// refined net's irregular vertices exactly the input's.
    #[test]
    fn refinement_separates_irregular_vertices() {
        for (name, mesh) in closed_test_meshes() {
            for k in 1..=4 {
                let net = prepare(&mesh, k).expect("closed meshes refine");
                let sep = irregular_separation(&net.mesh).map_or(usize::MAX, |s| s.0);
                assert!(sep >= k + 2, "{name} k = {k}: separation {sep}");
                assert_eq!(net.mesh.face_count(), mesh.face_count() << (2 * net.levels));
                let irregular = |m: &Mesh| {
                    (0..m.vertex_count() as u32)
                        .filter(|&v| m.valence(v) != 6)
                        .count()
                };
                assert_eq!(irregular(&net.mesh), irregular(&mesh), "{name}");
                let mut area = vec![0.0; mesh.face_count()];
                for (f, dom) in net.domain.iter().enumerate() {
                    let a = (dom[1] - dom[0]).cross(dom[2] - dom[0]).dot(DVec3::ONE) / 2.0;
                    assert!(a > 0.0, "{name}: refined face {f} keeps its orientation");
                    area[net.origin[f] as usize] += a;
                }
                for (f, a) in area.iter().enumerate() {
                    // (1,0,0),(0,1,0),(0,0,1): cross = (1,1,1), dotted with (1,1,1) / 2 = 1.5.
                    assert!(
                        (a - 1.5).abs() < 1e-12,
                        "{name}: input face {f} covered {a}"
                    );
                }
            }
        }
    }
}
