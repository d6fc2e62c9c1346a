//! Folds that no rule of a construction settles: the faces a surface still folds over get
//! sharp edges, round by round, until it folds nowhere.
//!
//! The schemes' own rules (front-facing normals and tangent planes, short tangents, the spike
//! rule of [`super::spikes`]) settle the folds of a clean or a decimated scan. A mesh that is
//! folded over itself in many places — a coarse marching-cubes reconstruction with fins two
//! faces thick and rings that wrap round themselves, such as the Stanford dragon's coarsest
//! published resolution — leaves folds they cannot settle, and a scheme that needs a
//! front-facing normal refuses such a ring. Here, after them ([`fold_rounds`]), every face
//! over which the surface still folds gets a crease along the edge across which it turns
//! most ([`sharpest_edge`]), and all its edges if it folds again, so that the face is a sector
//! of its own at each corner; a face that folds again with all its edges sharp has every
//! edge at its corners made sharp (its corners *fully sharp*: each face around them is a
//! sector of its own, whose tangent plane is the face's plane), and so do the vertices of a
//! ring the scheme refuses and the ends of an edge where it fails; a vertex a round would
//! leave with exactly two sharp edges gets a third ([`with_third_edges`]). A face whose three
//! corners are fully sharp has straight boundary curves along its edges (a crease between
//! two faces' own normals is their edge, `mesh::crease_tangent`); where its patches still
//! fold inside that plane (HB00's split of a sliver: its cross-boundary functions `Φ`, `Ψ`
//! cannot reproduce a flat triangle's constant derivative) it becomes the flat triangle,
//! which meets its neighbours along the same edges ([`flatten_sharp_faces`]). Every round
//! makes at least one more edge sharp, so the rounds end; the surface with the fewest fold
//! samples is kept. On a mesh where nothing folds they end after the first check, with the
//! scheme's surface unchanged.

use glam::DVec3;
use rayon::prelude::*;

use crate::bezier::TriangleBezier;
use crate::error::{Error, Result};
use crate::mesh::front_facing::front_facing_normals;
use crate::mesh::{Mesh, NormalSource, turn_angle};
use crate::surface::{Patch, PatchGeometry, Surface};
use crate::tolerance::{DOMAIN_ZERO, POSITION_REL};

/// Samples along each face edge of a patch at which its boundary curve is compared with the
/// straight edge before the face is replaced by the flat triangle.
const EDGE_SAMPLES: usize = 6;

/// Per vertex, true where every interior edge is sharp (each face around it is a sector of
/// its own).
pub(super) fn fully_sharp_vertices(mesh: &Mesh) -> Vec<bool> {
    let mut fully = vec![true; mesh.vertex_count()];
    for f in 0..mesh.face_count() as u32 {
        let face = mesh.faces()[f as usize];
        for e in 0..3 {
            if mesh.neighbor(f, e).is_some() && !mesh.is_sharp(f, e) {
                fully[face[e] as usize] = false;
                fully[face[(e + 1) % 3] as usize] = false;
            }
        }
    }
    fully
}

/// Rounds of [`fold_rounds`] at most; each makes at least one more edge sharp. A scheme that
/// fails at edges names those of one stage of its construction per build, so a folded scan
/// can take many: Nielson on the 109k-face face scan of results/public-models.md ends with 0
/// folds after 78 rounds (and was refused at a cap of 64).
const FOLD_ROUNDS: usize = 256;

/// What [`fold_rounds`] ends in: the surface with the fewest fold samples met (or the scheme's
/// error, where no round built one), the mesh it was built on, and what was done to get it.
pub(super) struct Rounds {
    /// The mesh with the edges made sharp.
    pub mesh: Mesh,
    /// The surface built on it, or the scheme's error.
    pub built: Result<Surface>,
    /// Its fold samples (`usize::MAX` for an error or an unusable surface).
    pub samples: usize,
    /// The number of edges made sharp.
    pub edges: usize,
    /// The faces over which the surfaces before it folded, sorted, each once.
    pub folded: Vec<u32>,
}

/// Builds again (`build`) with more sharp edges on `mesh`, whose surface is `built`, while it
/// folds or the scheme refuses a folded ring or fails at edges: the edges of the faces that
/// fold ([`edges_for_folds`]), the edges at a refused ring's vertices and at the failing
/// edges' ends ([`edges_around`]). Keeps the surface with the fewest fold samples: a
/// construction that does not interpolate (HB00 with α < 1) can fold more with sharp edges,
/// and then keeps its own surface. A surface that reaches absurdly far (`check_surface`)
/// stops the rounds: it comes from absurd parameters, which the caller's check names.
pub(super) fn fold_rounds(
    mut mesh: Mesh,
    built: Result<Surface>,
    mut build: impl FnMut(&Mesh) -> Result<Surface>,
) -> Rounds {
    let (mut next, samples, mut folded) = next_round(&mesh, &built);
    let mut best = Rounds {
        mesh: mesh.clone(),
        built,
        samples,
        edges: 0,
        folded: Vec::new(),
    };
    let mut edges = 0;
    for _ in 0..FOLD_ROUNDS {
        if next.is_empty() {
            break;
        }
        mesh = mesh.with_spike_edges(&next);
        edges += next.len();
        let built = build(&mesh);
        let (after, samples, faces) = next_round(&mesh, &built);
        if samples < best.samples {
            folded.sort_unstable();
            folded.dedup();
            best = Rounds {
                mesh: mesh.clone(),
                built,
                samples,
                edges,
                folded: folded.clone(),
            };
        }
        folded.extend(faces);
        next = after;
    }
    best
}

/// Rounds of [`prune_rounds`] at most; each gives back at least one edge it had taken away.
const PRUNE_ROUNDS: usize = 8;

/// The interior edges that are sharp in `mesh` (vertex pairs, smaller first, sorted, each
/// once), with the faces on their two sides.
fn sharp_edges_with_faces(mesh: &Mesh) -> Vec<((u32, u32), [u32; 2])> {
    let mut edges = Vec::new();
    for f in 0..mesh.face_count() as u32 {
        let face = mesh.faces()[f as usize];
        for e in 0..3 {
            if let Some((g, _)) = mesh.neighbor(f, e)
                && mesh.is_sharp(f, e)
            {
                let (a, b) = (face[e], face[(e + 1) % 3]);
                edges.push(((a.min(b), a.max(b)), [f.min(g), f.max(g)]));
            }
        }
    }
    edges.sort_unstable();
    edges.dedup_by_key(|(pair, _)| *pair);
    edges
}

/// Gives back the edges the rounds made sharp that the final surface does not need:
/// the rounds pass through surfaces that fold more than the one they end in (a round makes
/// every edge at the corners of a face that folds again sharp, and a third edge where a vertex
/// would keep two), so some of their edges lie between faces the surface never folded over.
/// Those are taken away together from `rounds.mesh` (the other edges stay, on `base`, the mesh
/// before the rounds); where the surface built then folds, or the scheme refuses, the edges
/// taken away at the faces that fold, at their corners and at the refused vertices and edges
/// ([`next_round`]) are given back, and it is built again. Ends in a surface with 0 fold
/// samples, or returns `rounds` unchanged (no round gives anything back, or the rounds did
/// not end with 0 fold samples).
pub(super) fn prune_rounds(
    base: &Mesh,
    rounds: Rounds,
    mut build: impl FnMut(&Mesh) -> Result<Surface>,
) -> Rounds {
    if rounds.samples != 0 || rounds.edges == 0 {
        return rounds;
    }
    let before: Vec<(u32, u32)> = sharp_edges_with_faces(base)
        .into_iter()
        .map(|(pair, _)| pair)
        .collect();
    let mut keep: Vec<(u32, u32)> = Vec::new();
    let mut away: Vec<(u32, u32)> = Vec::new();
    for (pair, faces) in sharp_edges_with_faces(&rounds.mesh) {
        if before.binary_search(&pair).is_ok() {
            continue;
        }
        if faces.iter().any(|f| rounds.folded.binary_search(f).is_ok()) {
            keep.push(pair);
        } else {
            away.push(pair);
        }
    }
    for _ in 0..PRUNE_ROUNDS {
        if away.is_empty() {
            break;
        }
        let mesh = base.with_spike_edges(&keep);
        let built = build(&mesh);
        let (next, samples, faces) = next_round(&mesh, &built);
        if samples == 0 {
            return Rounds {
                mesh,
                built,
                samples,
                edges: keep.len(),
                folded: rounds.folded,
            };
        }
        let corners: Vec<u32> = faces
            .iter()
            .flat_map(|&f| mesh.faces()[f as usize])
            .collect();
        let mut wanted = edges_around(&mesh, &corners);
        wanted.extend(next);
        wanted.sort_unstable();
        let (back, still): (Vec<_>, Vec<_>) = away
            .into_iter()
            .partition(|pair| wanted.binary_search(pair).is_ok());
        if back.is_empty() {
            break;
        }
        keep.extend(back);
        keep.sort_unstable();
        away = still;
    }
    rounds
}

/// `edges` and, at every interior vertex they would leave with exactly two sharp edges, a
/// third: the ring edge halfway round the wider of its two sectors. Two sharp edges at a
/// vertex take one crease line through it, whose tangents are half a turn apart however
/// narrow the face between them; with three, each sector takes the plane of its end edges
/// (`Mesh::corner_normals`), and the crease of two such sectors is their common edge.
fn with_third_edges(mesh: &Mesh, mut edges: Vec<(u32, u32)>) -> Vec<(u32, u32)> {
    if edges.is_empty() {
        return edges;
    }
    let after = mesh.with_spike_edges(&edges);
    let mut ends: Vec<u32> = edges.iter().flat_map(|&(a, b)| [a, b]).collect();
    ends.sort_unstable();
    ends.dedup();
    for v in ends {
        if after.is_boundary_vertex(v) || after.sharp_valence(v) != 2 {
            continue;
        }
        let cuts: Vec<usize> = after.sharp_cuts(v).collect();
        let n = after.one_ring(v).len();
        let (a, b) = (cuts[0], cuts[1]);
        let (start, gap) = if b - a >= n - (b - a) {
            (a, b - a)
        } else {
            (b, n - (b - a))
        };
        if gap >= 2 {
            let w = after.one_ring(v)[(start + gap / 2) % n];
            edges.push((v.min(w), v.max(w)));
        }
    }
    edges.sort_unstable();
    edges.dedup();
    edges
}

/// For the surface (or error) `built` on `mesh`: the edges the next round makes sharp, its
/// fold samples (`usize::MAX` for an error or an unusable surface) and the faces it folds
/// over.
fn next_round(mesh: &Mesh, built: &Result<Surface>) -> (Vec<(u32, u32)>, usize, Vec<u32>) {
    let (edges, samples, faces) = match built {
        Ok(surface) if super::check_surface(surface, mesh, &[]).is_err() => {
            (Vec::new(), usize::MAX, Vec::new())
        }
        Ok(surface) => {
            let (faces, samples) = folding_faces(mesh, surface);
            (edges_for_folds(mesh, &faces), samples, faces)
        }
        Err(Error::FoldedVertex { vertex, .. }) => {
            let mut rings = folded_rings(mesh);
            rings.push(*vertex as u32);
            (edges_around(mesh, &rings), usize::MAX, Vec::new())
        }
        Err(Error::DegenerateEdge { a, b, also, .. }) => {
            let ends: Vec<u32> = std::iter::once((*a, *b))
                .chain(also.iter().copied())
                .flat_map(|(a, b)| [a as u32, b as u32])
                .collect();
            (edges_around(mesh, &ends), usize::MAX, Vec::new())
        }
        Err(_) => (Vec::new(), usize::MAX, Vec::new()),
    };
    (with_third_edges(mesh, edges), samples, faces)
}

/// The faces over which a patch of `surface` folds (`Patch::fold_samples`), sorted, each
/// once, and the fold samples of all its patches.
pub(super) fn folding_faces(mesh: &Mesh, surface: &Surface) -> (Vec<u32>, usize) {
    let per_patch: Vec<(u32, usize)> = surface
        .patches
        .par_iter()
        .map(|p| (p.face, p.fold_samples(mesh.face_normal(p.face))))
        .filter(|&(_, samples)| samples > 0)
        .collect();
    let samples = per_patch.iter().map(|&(_, s)| s).sum();
    let mut faces: Vec<u32> = per_patch.into_iter().map(|(f, _)| f).collect();
    faces.sort_unstable();
    faces.dedup();
    (faces, samples)
}

/// The edges to make sharp where the surface folds over the faces `folding`: for a face with
/// no sharp interior edge yet, the one across which it turns most ([`sharpest_edge`]); for a
/// face that folds again with some sharp, its other interior edges; for a face whose edges are
/// all sharp already, every edge at its corners ([`edges_around`]). So a face first gets one
/// crease, then becomes a sector of its own at each corner, then its corners fully sharp.
/// Sorted, each once.
pub(super) fn edges_for_folds(mesh: &Mesh, folding: &[u32]) -> Vec<(u32, u32)> {
    let mut edges = Vec::new();
    let mut corners = Vec::new();
    for &f in folding {
        let face = mesh.faces()[f as usize];
        let own: Vec<(u32, u32)> = (0..3)
            .filter(|&e| mesh.neighbor(f, e).is_some() && !mesh.is_sharp(f, e))
            .map(|e| {
                (
                    face[e].min(face[(e + 1) % 3]),
                    face[e].max(face[(e + 1) % 3]),
                )
            })
            .collect();
        let interior = (0..3).filter(|&e| mesh.neighbor(f, e).is_some()).count();
        if own.is_empty() {
            corners.extend(face);
        } else if own.len() == interior {
            edges.extend(sharpest_edge(mesh, f));
        } else {
            edges.extend(own);
        }
    }
    edges.extend(edges_around(mesh, &corners));
    edges.sort_unstable();
    edges.dedup();
    edges
}

/// The interior edge of face `f` across which it turns most against its neighbour (the
/// largest angle between the two faces' normals), as a vertex pair, smaller first; `None` for
/// a face without neighbours. Where a surface folds over a face, the crease it needs is
/// usually there: one sharp edge settles most folds of a scan's slivers, and a face that
/// still folds gets its other edges in the next round (on the Stanford dragon's res4 this
/// takes hb from 949 sharp edges to 553 for the same 0 folds).
fn sharpest_edge(mesh: &Mesh, f: u32) -> Option<(u32, u32)> {
    let face = mesh.faces()[f as usize];
    let normal = mesh.face_normal(f).normalize();
    (0..3)
        .filter_map(|e| {
            let (g, _) = mesh.neighbor(f, e)?;
            let turn = turn_angle(normal, mesh.face_normal(g).normalize());
            let (a, b) = (face[e], face[(e + 1) % 3]);
            Some((turn, (a.min(b), a.max(b))))
        })
        .max_by(|x, y| x.0.total_cmp(&y.0))
        .map(|(_, edge)| edge)
}

/// The interior edges that are not sharp yet at the `vertices` (vertex pairs, smaller first,
/// sorted, each once): the edges that make them fully sharp.
pub(super) fn edges_around(mesh: &Mesh, vertices: &[u32]) -> Vec<(u32, u32)> {
    let mut wanted = vec![false; mesh.vertex_count()];
    for &v in vertices {
        wanted[v as usize] = true;
    }
    let mut edges = Vec::new();
    for f in 0..mesh.face_count() as u32 {
        let face = mesh.faces()[f as usize];
        for e in 0..3 {
            let (a, b) = (face[e], face[(e + 1) % 3]);
            if (wanted[a as usize] || wanted[b as usize])
                && mesh.neighbor(f, e).is_some()
                && !mesh.is_sharp(f, e)
            {
                edges.push((a.min(b), a.max(b)));
            }
        }
    }
    edges.sort_unstable();
    edges.dedup();
    edges
}

/// Replaces the patches of every face of `surface` whose three corners are fully sharp
/// ([`fully_sharp_vertices`]), which folds inside its plane, and whose boundary curves are
/// its straight edges, parametrised in proportion to length, by the flat triangle over the
/// same pieces (degree unchanged, a blend's by the Bézier patch of its sub-surfaces'
/// degree): the neighbours meet it along the same curves, and it folds nowhere. Returns the
/// number of faces replaced, which a warning in the surface counts.
pub(super) fn flatten_sharp_faces(mesh: &Mesh, surface: &mut Surface) -> usize {
    let fully = fully_sharp_vertices(mesh);
    let candidates: Vec<bool> = mesh
        .faces()
        .iter()
        .map(|face| face.iter().all(|&v| fully[v as usize]))
        .collect();
    if !candidates.iter().any(|&c| c) {
        return 0;
    }
    let mut keep = vec![true; mesh.face_count()];
    let mut folds = vec![false; mesh.face_count()];
    for patch in &surface.patches {
        let f = patch.face as usize;
        if candidates[f] {
            keep[f] &= edges_are_straight(mesh, patch);
            folds[f] |= patch.fold_samples(mesh.face_normal(patch.face)) > 0;
        }
    }
    let flatten: Vec<bool> = (0..mesh.face_count())
        .map(|f| candidates[f] && keep[f] && folds[f])
        .collect();
    for patch in surface.patches.iter_mut() {
        if flatten[patch.face as usize] {
            *patch = flat_piece(mesh, patch);
        }
    }
    let count = flatten.iter().filter(|&&f| f).count();
    if count > 0 {
        surface.warnings.push(format!(
            "{}: {count} faces whose corners are all sharp folded inside their plane and are \
             flat triangles",
            surface.scheme
        ));
    }
    count
}

/// The point of `patch`'s face at face-barycentric `bary`, on the flat triangle.
fn on_face(mesh: &Mesh, face: u32, bary: DVec3) -> DVec3 {
    let [a, b, c] = mesh.faces()[face as usize].map(|v| mesh.positions()[v as usize]);
    bary.x * a + bary.y * b + bary.z * c
}

/// True if every edge of `patch` on an interior edge of its face (one with a neighbour) is
/// that straight edge, parametrised in proportion to length (to rounding: [`POSITION_REL`]
/// of the face's longest edge). Boundary edges have no neighbour to meet.
fn edges_are_straight(mesh: &Mesh, patch: &Patch) -> bool {
    let [a, b, c] = mesh.faces()[patch.face as usize].map(|v| mesh.positions()[v as usize]);
    let size = (b - a).length().max((c - b).length()).max((a - c).length());
    let corners = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)];
    (0..3).all(|e| {
        let (from, to) = (patch.domain[e], patch.domain[(e + 1) % 3]);
        // On face edge k (corner k to k + 1) the weight of corner k + 2 is zero.
        let on_edge = (0..3).find(|&w| from[w].abs() < DOMAIN_ZERO && to[w].abs() < DOMAIN_ZERO);
        let Some(w) = on_edge else {
            return true;
        };
        if mesh.neighbor(patch.face, (w + 1) % 3).is_none() {
            return true;
        }
        let (p, q) = (corners[e], corners[(e + 1) % 3]);
        (0..=EDGE_SAMPLES).all(|i| {
            let t = i as f64 / EDGE_SAMPLES as f64;
            let (u, v) = (p.0 + t * (q.0 - p.0), p.1 + t * (q.1 - p.1));
            let bary = (1.0 - u - v) * patch.domain[0] + u * patch.domain[1] + v * patch.domain[2];
            (patch.eval(u, v) - on_face(mesh, patch.face, bary)).length() <= POSITION_REL * size
        })
    })
}

/// The flat triangle over `patch`'s piece of its face, as a Bézier patch of the patch's
/// degree: its control point `b(i,j,k)` is the face's point at the piece's barycentric
/// `(i, j, k)/d` (a linear map's Bézier coefficients are its values on that grid).
fn flat_piece(mesh: &Mesh, patch: &Patch) -> Patch {
    let degree = match &patch.geometry {
        PatchGeometry::Bezier(net) => net.degree(),
        PatchGeometry::Blend(blend) => blend.degree(),
    };
    let d = degree as f64;
    let net = TriangleBezier::from_fn(degree, |i, j, k| {
        let bary =
            (i as f64 * patch.domain[0] + j as f64 * patch.domain[1] + k as f64 * patch.domain[2])
                / d;
        on_face(mesh, patch.face, bary)
    });
    Patch {
        geometry: PatchGeometry::Bezier(net),
        ..patch.clone()
    }
}

/// The warning for the `edges` edges a scheme made sharp at the faces `folded` of
/// `sharpened` (their edges, then their corners'; sorted, the first named in the file's
/// numbering).
pub(super) fn warning(scheme: &str, sharpened: &Mesh, edges: usize, folded: &[u32]) -> String {
    let first = match folded.first() {
        Some(&f) => format!("first: face {}", sharpened.input_face(f)),
        None => "at rings or edges the scheme refused".to_string(),
    };
    format!(
        "{scheme}: made {edges} edges sharp at {} faces over which the surface folded \
         ({first}), where no smooth surface follows the mesh: the surface is G0 \
         across them and the metrics count them as sharp joints; repair the mesh there, or \
         choose sharp edges with --crease-angle",
        folded.len(),
    )
}

/// The vertices whose faces fold over themselves (no normal sees them all from the front,
/// `mesh::front_facing`) and whose fan is one sector, in order.
pub(super) fn folded_rings(mesh: &Mesh) -> Vec<u32> {
    let Ok(estimate) = mesh.vertex_normals(NormalSource::Estimate) else {
        return Vec::new();
    };
    let front = front_facing_normals(mesh.positions(), mesh.faces(), &estimate);
    front
        .folded
        .into_iter()
        .filter(|&v| mesh.has_one_sector(v))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::Metrics;
    use crate::schemes::{Params, build, find};
    use crate::testing;
    use crate::tolerance::NORMAL_RAD;

    fn hostile(name: &str) -> Mesh {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("scenes/hostile")
            .join(format!("{name}.obj"));
        Mesh::load(&path).expect("corpus mesh loads").0
    }

    /// The scheme's own surface (no spike rule, no fold rounds) on `mesh`.
    fn own_surface(scheme: &str, mesh: &Mesh) -> crate::Result<Surface> {
        let spec = find(scheme).expect("registered");
        (spec.build)(mesh, &Params::resolve(spec, &[]).expect("defaults"))
    }

    /// Checks what every surface the rounds end in must be: no fold sample, G1 to rounding
    /// over the smooth joints (for the G1 schemes), G0 to rounding across the sharp ones, the
    /// vertices interpolated, and one warning counting the edges made sharp round folds.
    fn assert_fold_free(label: &str, scheme: &str, mesh: &Mesh, surface: &Surface) -> Metrics {
        let m = Metrics::measure(surface, mesh, 0.0);
        assert_eq!(m.folds, 0, "{label}");
        if scheme != "pn" {
            let g1 = m.g1_max_rad.unwrap_or(0.0);
            assert!(g1 <= NORMAL_RAD, "{label}: G1 {g1} rad");
        }
        if m.sharp_joints > 0 {
            let gap = m.sharp_g0_max_rel.expect("sharp joints measured");
            assert!(gap <= POSITION_REL, "{label}: G0 across sharp joints {gap}");
        }
        let interpolation = m.interp_max_rel.expect("vertices measured");
        assert!(interpolation <= POSITION_REL, "{label}: {interpolation}");
        m
    }

    /// Meshes on which a scheme's own surface still folds after its rules: the hostile
    /// corpus's sliver sphere (triangles of 0.8°–1°; hb, loop94 and Fang–Mann folded on 837,
    /// 169 and 192 samples) and loop94 on the irregular bunny (8). With the faces that fold
    /// made sectors of their own, and their corners fully sharp where that is not enough,
    /// nothing folds, and the surface keeps its continuity over every other joint.
    /// The rounds' edges between faces that never folded are taken away where the surface
    /// then still folds nowhere: the pruned mesh keeps 0 fold samples with fewer sharp edges,
    /// every one of them among the rounds' own.
    #[test]
    fn edges_the_final_surface_does_not_need_are_given_back() {
        let spec_of = |scheme: &str| find(scheme).expect("registered");
        let mut pruned_any = false;
        for (name, scheme) in [
            ("sliver-sphere", "hb"),
            ("sliver-sphere", "loop94"),
            ("sliver-sphere", "fang-mann"),
            ("bunny-irregular", "loop94"),
        ] {
            let mesh = match name {
                "sliver-sphere" => hostile(name),
                _ => testing::scene(name),
            };
            let spec = spec_of(scheme);
            let params = Params::resolve(spec, &[]).expect("defaults");
            let build_on = |mesh: &Mesh| {
                (spec.build)(mesh, &params).map(|mut surface| {
                    flatten_sharp_faces(mesh, &mut surface);
                    surface
                })
            };
            let rounds = fold_rounds(mesh.clone(), build_on(&mesh), build_on);
            assert_eq!(rounds.samples, 0, "{name} {scheme}");
            let rounds_edges = sharp_edges_with_faces(&rounds.mesh);
            let pruned = prune_rounds(&mesh, rounds, build_on);
            assert_eq!(pruned.samples, 0, "{name} {scheme}");
            let surface = pruned.built.as_ref().expect("builds");
            assert_eq!(folding_faces(&pruned.mesh, surface).1, 0, "{name} {scheme}");
            let kept = sharp_edges_with_faces(&pruned.mesh);
            assert!(
                kept.iter().all(|e| rounds_edges.contains(e)),
                "{name} {scheme}"
            );
            assert!(kept.len() <= rounds_edges.len(), "{name} {scheme}");
            pruned_any |= kept.len() < rounds_edges.len();
            println!(
                "{name} {scheme}: {} -> {} sharp edges",
                rounds_edges.len(),
                kept.len()
            );
        }
        assert!(pruned_any, "some round's edge is given back");
    }

    #[test]
    fn faces_that_still_fold_get_sharp_edges_until_none_does() {
        let cases = [
            ("sliver-sphere", "hb"),
            ("sliver-sphere", "loop94"),
            ("sliver-sphere", "fang-mann"),
            ("bunny-irregular", "loop94"),
        ];
        for (name, scheme) in cases {
            let mesh = match name {
                "sliver-sphere" => hostile(name),
                _ => testing::scene(name),
            };
            let label = format!("{name} {scheme}");
            let own = own_surface(scheme, &mesh).expect("builds");
            let (_, own_folds) = folding_faces(&mesh, &own);
            assert!(own_folds > 0, "{label}");
            let surface = build(scheme, &mesh, &[]).expect("builds");
            let m = assert_fold_free(&label, scheme, &mesh, &surface);
            assert!(
                m.spike_edges > 0 && m.sharp_joints >= m.spike_edges,
                "{label}: {m:?}"
            );
            testing::the_warning(&surface, "over which the surface folded");
            println!(
                "{label}: {own_folds} fold samples -> 0, {} edges sharp",
                m.spike_edges
            );
        }
    }

    /// Every edge of the bunny sharp (`--crease-angle 0.01`; all but the few between faces
    /// coplanar to 0.01°): each face whose corners are all fully sharp is a sector of its own
    /// at each corner, its boundary curves are its straight edges, and every scheme that
    /// keeps sharp edges builds each face inside its plane with no fold. With `Ψ` linear
    /// (HB00 eq. 20, Loop94 eq. 4: `psi=linear`) HB00's split folds inside the plane of the
    /// 9°-sliver face 321 (14 samples) and Loop's patch inside one face, before those faces
    /// become flat triangles; with their default harmonic `Ψ` neither folds there. With crease
    /// tangents all of one mean length at a vertex, as before they took their edges' own, hb
    /// folded on 1291 samples.
    #[test]
    fn faces_whose_corners_are_all_sharp_are_flat_and_fold_nowhere() {
        let mesh = testing::creased(&testing::scene("bunny"), 0.01);
        let fully = fully_sharp_vertices(&mesh);
        let sharp_faces: Vec<bool> = mesh
            .faces()
            .iter()
            .map(|face| face.iter().all(|&v| fully[v as usize]))
            .collect();
        let count = sharp_faces.iter().filter(|&&s| s).count();
        // A few pairs of faces of the scan are coplanar to 0.01°.
        assert!(count + 20 >= mesh.face_count(), "{count}");
        let diagonal = mesh.bounds().diagonal();
        let linear = [("psi".to_string(), "linear".to_string())];
        for (scheme, params) in [
            ("hb", &[][..]),
            ("hb", &linear[..]),
            ("loop94", &[]),
            ("loop94", &linear[..]),
            ("pn", &[]),
            ("piper", &[]),
            ("nielson", &[]),
            ("fang-mann", &[]),
        ] {
            let surface = build(scheme, &mesh, params).expect("builds");
            assert_fold_free(scheme, scheme, &mesh, &surface);
            let positions = mesh.positions();
            for patch in surface
                .patches
                .iter()
                .filter(|p| sharp_faces[p.face as usize])
            {
                let face = mesh.faces()[patch.face as usize];
                let normal = mesh.face_normal(patch.face);
                let off = patch
                    .control_points()
                    .map(|p| (p - positions[face[0] as usize]).dot(normal).abs())
                    .fold(0.0, f64::max);
                assert!(
                    off <= POSITION_REL * diagonal,
                    "{scheme} face {}: {off}",
                    patch.face
                );
            }
            let flat = surface
                .warnings
                .iter()
                .any(|w| w.contains("flat triangles"));
            assert_eq!(
                flat,
                !params.is_empty(),
                "{scheme} {params:?}: {:?}",
                surface.warnings
            );
        }
    }

    /// A vertex of the bunny dragged across its ring past a neighbour (a fold a scan's
    /// registration leaves): its faces fold over themselves, so no normal sees them all from
    /// the front and piper, Nielson and Fang–Mann refuse it on their own. The registry makes
    /// the vertex and what still folds round it sharp, and all three build without a fold.
    #[test]
    fn a_ring_folded_over_itself_builds_with_its_corners_sharp() {
        let bunny = testing::scene("bunny");
        let dragged = (0..bunny.vertex_count() as u32)
            .filter(|&v| !bunny.is_boundary_vertex(v))
            .find_map(|v| {
                let w = bunny.one_ring(v)[0];
                let mut positions = bunny.positions().to_vec();
                let (p, q) = (positions[v as usize], positions[w as usize]);
                positions[v as usize] = p + 1.5 * (q - p);
                let (mesh, _) = Mesh::from_triangles(positions, bunny.faces().to_vec()).ok()?;
                let folded = folded_rings(&mesh);
                (mesh.vertex_count() == bunny.vertex_count() && folded.contains(&v))
                    .then_some((mesh, v))
            });
        let (mesh, v) = dragged.expect("a vertex whose ring folds when dragged");
        for scheme in ["piper", "nielson", "fang-mann"] {
            let label = format!("{scheme}, vertex {v} dragged");
            match own_surface(scheme, &mesh) {
                Err(crate::Error::FoldedVertex { vertex, .. }) => {
                    assert!(folded_rings(&mesh).contains(&(vertex as u32)), "{label}")
                }
                other => panic!("{label}: {:?}", other.map(|s| s.patches.len())),
            }
            let surface = build(scheme, &mesh, &[]).expect("builds");
            let m = assert_fold_free(&label, scheme, &mesh, &surface);
            assert!(m.spike_edges > 0, "{label}");
        }
    }
}
