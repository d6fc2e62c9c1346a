//! Spikes: vertices where the mesh itself turns sharply, and the sharp edges a construction
//! takes there when its smooth surface would fold.
//!
//! At the tip of a spike or the ridge of a near-fold of a scanned or decimated mesh (an ear
//! tip of a bunny), two faces around a vertex turn by more than a right angle across an edge.
//! A smooth surface through such a vertex has one tangent plane there, which the faces on the
//! far side of the turn see nearly edge-on; the tangents that plane carries then sweep a
//! patch over its face (a *fold*, see `Patch::fold_samples`), whatever rule chose the plane.
//! A surface that is only G0 across the turning edges has one tangent plane per side and no
//! such conflict. So after a construction, at every vertex with an edge turning more than
//! [`SPIKE_TURN_DEG`] around which the surface folds, [`spike_edges`] picks those edges (and,
//! where that leaves a single one, the next-sharpest edge too, so that the fan splits into two
//! smooth sectors instead of a dart's one); the registry rebuilds the surface with them sharp
//! (`Mesh::with_spike_edges`) and keeps the result if it has fewer fold samples (a mesh messy
//! around its spikes can fold more in sectors: the Stanford dragon's coarsest scan with hb),
//! reports them in a warning and the metrics count them as sharp joints. Everywhere else the
//! surface is the paper's, bit for bit; a mesh without such a vertex is not even checked for
//! folds. A scheme that refuses a vertex whose faces fold
//! over themselves (no normal sees them all from the front) gets the same remedy there: each
//! side of the fold is a smooth sector of its own, taken only if the surface then folds
//! nowhere.

use rayon::prelude::*;

use crate::mesh::Mesh;
use crate::surface::Surface;

/// Angle (degrees) between the normals of an edge's two faces above which the edge can be made
/// sharp at a spike where the surface folds: past a right angle the faces on either side face
/// away from each other.
pub(super) const SPIKE_TURN_DEG: f64 = 90.0;

/// An interior edge `(v, w)` at a vertex and the turn (rad) between its two faces.
#[derive(Clone, Copy, Debug)]
struct RingEdge {
    to: u32,
    turn: f64,
}

/// The interior edges at `v` that are not sharp yet, with their turns.
fn smooth_ring_edges(mesh: &Mesh, v: u32) -> Vec<RingEdge> {
    let ring = mesh.one_ring(v);
    let faces = mesh.ring_faces(v);
    let closed = !mesh.is_boundary_vertex(v);
    // Edge (v, ring[j]) lies between ring_faces[j - 1] and ring_faces[j]; on a boundary fan
    // edges 0 and n - 1 are boundary edges.
    (0..ring.len())
        .filter(|&j| closed || (j > 0 && j < faces.len()))
        .filter_map(|j| {
            let before = faces[(j + faces.len() - 1) % faces.len()];
            let after = faces[j];
            let corner = mesh.faces()[after as usize].iter().position(|&x| x == v)?;
            (!mesh.is_sharp(after, corner)).then(|| RingEdge {
                to: ring[j],
                turn: crate::mesh::turn_angle(mesh.face_normal(before), mesh.face_normal(after)),
            })
        })
        .collect()
}

/// The vertices with an interior edge that is not sharp and whose faces turn by more than
/// [`SPIKE_TURN_DEG`], a right angle: their normals' dot product is negative. In order.
fn spike_vertices(mesh: &Mesh) -> Vec<u32> {
    let positions = mesh.positions();
    let area_normal = |f: u32| {
        let [a, b, c] = mesh.faces()[f as usize].map(|v| positions[v as usize]);
        (b - a).cross(c - a)
    };
    let mut spike = vec![false; mesh.vertex_count()];
    for f in 0..mesh.face_count() as u32 {
        for e in 0..3 {
            let Some((g, _)) = mesh.neighbor(f, e) else {
                continue;
            };
            if g > f && !mesh.is_sharp(f, e) && area_normal(f).dot(area_normal(g)) < 0.0 {
                let face = mesh.faces()[f as usize];
                spike[face[e] as usize] = true;
                spike[face[(e + 1) % 3] as usize] = true;
            }
        }
    }
    (0..mesh.vertex_count() as u32)
        .filter(|&v| spike[v as usize])
        .collect()
}

/// The edges (vertex pairs, smaller first, sorted, each once) to make sharp so that `surface`,
/// built on `mesh`, need not fold at a spike: at every spike vertex with a face around it over
/// which a patch folds, its edges turning more than [`SPIKE_TURN_DEG`], and, if that makes it
/// an interior vertex with a single sharp edge, its next-sharpest edge. Empty when no spike
/// vertex has a folding face.
pub(super) fn spike_edges(mesh: &Mesh, surface: &Surface) -> Vec<(u32, u32)> {
    let spikes = spike_vertices(mesh);
    if spikes.is_empty() {
        return Vec::new();
    }
    let mut watched = vec![false; mesh.face_count()];
    for &v in &spikes {
        for &f in mesh.ring_faces(v) {
            watched[f as usize] = true;
        }
    }
    let folding: Vec<u32> = surface
        .patches
        .par_iter()
        .filter(|p| watched[p.face as usize] && p.fold_samples(mesh.face_normal(p.face)) > 0)
        .map(|p| p.face)
        .collect();
    let mut folded = vec![false; mesh.face_count()];
    for f in folding {
        folded[f as usize] = true;
    }
    let mut edges: Vec<(u32, u32)> = spikes
        .iter()
        .filter(|&&v| mesh.ring_faces(v).iter().any(|&f| folded[f as usize]))
        .flat_map(|&v| edges_at(mesh, v))
        .collect();
    edges.sort_unstable();
    edges.dedup();
    edges
}

/// The warning for the edges `added` (vertex pairs, smaller first; sorted here) that scheme
/// `scheme` made sharp at spikes of `sharpened` (the mesh with them sharp): how many, the
/// sharpest with its turn (in the file's numbering), how many vertices, and the remedy.
pub(super) fn warning(scheme: &str, sharpened: &Mesh, added: &mut [(u32, u32)]) -> String {
    added.sort_unstable();
    let (sharpest, turn) = sharpened
        .edges()
        .into_iter()
        .filter(|e| added.binary_search(&(e.a, e.b)).is_ok())
        .filter_map(|e| {
            let (f, g) = (e.faces.0, e.faces.1?);
            let turn = crate::mesh::turn_angle(sharpened.face_normal(f), sharpened.face_normal(g));
            Some(((e.a, e.b), turn.to_degrees()))
        })
        .fold(((0, 0), f64::NEG_INFINITY), |best, e| {
            if e.1 > best.1 { e } else { best }
        });
    let mut vertices: Vec<u32> = added.iter().flat_map(|&(a, b)| [a, b]).collect();
    vertices.sort_unstable();
    vertices.dedup();
    format!(
        "{scheme}: made {} edges sharp at spikes of the mesh, where a smooth surface would fold \
         over a face (sharpest: edge ({}, {}), its faces turning {turn:.1}°; {} vertices \
         involved): the surface is G0 across them and the metrics count them as sharp joints; \
         fix the mesh there, or choose sharp edges with --crease-angle",
        added.len(),
        sharpened.input_vertex(sharpest.0),
        sharpened.input_vertex(sharpest.1),
        vertices.len(),
    )
}

/// The fold samples of `surface`, built on `mesh` (`Patch::fold_samples` over every patch).
pub(super) fn fold_samples(mesh: &Mesh, surface: &Surface) -> usize {
    surface
        .patches
        .par_iter()
        .map(|p| p.fold_samples(mesh.face_normal(p.face)))
        .sum()
}

/// The edges to make sharp ([`edges_at`]) at every vertex whose faces fold over themselves
/// and whose fan is one sector (`fold_corners::folded_rings`):
/// where a scheme refuses such a vertex, each side of the fold becomes a sector of its own.
pub(super) fn folded_ring_edges(mesh: &Mesh) -> Vec<(u32, u32)> {
    let mut edges: Vec<(u32, u32)> = super::fold_corners::folded_rings(mesh)
        .into_iter()
        .flat_map(|v| edges_at(mesh, v))
        .collect();
    edges.sort_unstable();
    edges.dedup();
    edges
}

/// The edges to make sharp at vertex `v` (vertex pairs, smaller first): its interior edges
/// that are not sharp and turn more than [`SPIKE_TURN_DEG`], and, if that makes `v` an
/// interior vertex with a single sharp edge, its next-sharpest edge. Empty if `v` is no spike.
fn edges_at(mesh: &Mesh, v: u32) -> Vec<(u32, u32)> {
    let limit = SPIKE_TURN_DEG.to_radians();
    let mut ring = smooth_ring_edges(mesh, v);
    ring.sort_by(|a, b| b.turn.total_cmp(&a.turn));
    let mut take = ring.iter().take_while(|e| e.turn > limit).count();
    if take == 1 && !mesh.is_boundary_vertex(v) && mesh.sharp_valence(v) == 0 {
        take = 2.min(ring.len());
    }
    ring[..take]
        .iter()
        .map(|e| (v.min(e.to), v.max(e.to)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::Metrics;
    use crate::schemes::{Params, build, build_in_frame, find};
    use crate::testing;

    /// Scanned bunnies whose ear tips and ridges turn by up to 135° across an edge (vertex
    /// 248 of `scenes/bunny.obj`, vertices 94 and 248 of `scenes/bunny-irregular.obj`): each
    /// scheme's own surface folds there; with the spikes' edges sharp it does not, and it is
    /// G1 over every other joint.
    #[test]
    fn folds_at_spikes_go_when_their_edges_are_made_sharp() {
        let cases = [
            ("bunny", "hb"),
            ("bunny", "loop94"),
            ("bunny-irregular", "hb"),
            ("bunny-irregular", "piper"),
            ("bunny-irregular", "fang-mann"),
            ("bunny-irregular", "nielson"),
        ];
        for (scene, scheme) in cases {
            let mesh = testing::scene(scene);
            let spec = find(scheme).unwrap();
            let params = Params::resolve(spec, &[]).unwrap();
            let papers = (spec.build)(&mesh, &params).unwrap();
            let edges = spike_edges(&mesh, &papers);
            assert!(fold_samples(&mesh, &papers) > 0, "{scene} {scheme}");
            assert!(!edges.is_empty(), "{scene} {scheme}");

            // Every edge chosen has an end where the mesh turns past a right angle and whose
            // fan it splits into sectors (that end is no dart).
            let limit = SPIKE_TURN_DEG.to_radians();
            let spikes = spike_vertices(&mesh);
            let sharpened = mesh.with_spike_edges(&edges);
            assert_eq!(sharpened.sharp_edges().at_spikes(), edges.len());
            for &(a, b) in &edges {
                let split_spike = |v: u32| {
                    spikes.contains(&v)
                        && smooth_ring_edges(&mesh, v).iter().any(|e| e.turn > limit)
                        && sharpened.sharp_valence(v) >= 2
                };
                assert!(
                    split_spike(a) || split_spike(b),
                    "{scene} {scheme}: ({a}, {b})"
                );
            }

            let surface = build(scheme, &mesh, &[]).unwrap();
            let m = Metrics::measure(&surface, &mesh, 0.0);
            let label = format!("{scene} {scheme}");
            assert_eq!(m.folds, 0, "{label}");
            assert!(
                m.spike_edges >= edges.len() && m.spike_edges <= 8,
                "{label}: {m:?}"
            );
            assert!(m.sharp_joints >= m.spike_edges, "{label}");
            assert!(m.g1_max_rad.unwrap() <= 1e-9, "{label}: {:?}", m.g1_max_rad);
            assert!(m.sharp_g0_max_rel.unwrap() <= 1e-14, "{label}");
            let warned = surface
                .warnings
                .iter()
                .filter(|w| w.contains("edges sharp at spikes of the mesh"))
                .count();
            assert_eq!(warned, 1, "{label}: {:?}", surface.warnings);
        }
    }

    /// Where no spike folds, the registry's surface is the scheme's own, bit for bit: on the
    /// bunny, whose spike piper's surface does not fold over, and on meshes without spikes.
    #[test]
    fn without_a_folding_spike_the_papers_surface_is_kept_bit_for_bit() {
        let cases = [
            ("bunny", "piper"),
            ("bunny", "nielson"),
            ("genus2", "hb"),
            ("mixed-valence", "loop94"),
            ("icosahedron", "fang-mann"),
        ];
        for (scene, scheme) in cases {
            let mesh = testing::scene(scene);
            let spec = find(scheme).unwrap();
            let (surface, frame) = build_in_frame(scheme, &mesh, &[]).unwrap();
            let local = mesh.framed(frame.centre, frame.scale);
            let papers = (spec.build)(&local, &Params::resolve(spec, &[]).unwrap()).unwrap();
            assert!(surface.spike_face_pairs.is_empty(), "{scene} {scheme}");
            assert_eq!(surface.patches, papers.patches, "{scene} {scheme}");
            assert_eq!(surface.warnings, papers.warnings, "{scene} {scheme}");
        }
        assert!(spike_vertices(&testing::scene("icosahedron")).is_empty());
        assert!(!spike_vertices(&testing::scene("bunny")).is_empty());
    }
}
