//! The loading pipeline shared by every mesh source: index and coordinate checks, welding,
//! degenerate / duplicate / non-manifold checks and consistent orientation. It ends by handing
//! the oriented faces to [`Topology::build`].

use std::collections::HashMap;
use std::collections::hash_map::Entry;

use glam::DVec3;

use super::normals::{self, CornerNormals};
use super::topology::{NO_TWIN, Topology};
use super::{LoadReport, Mesh};
use crate::error::{Error, Result};

/// A face is degenerate when `|(b−a)×(c−a)| <= DEGENERATE_AREA_RATIO · (longest edge)²`.
///
/// The ratio is scale-free: `|(b−a)×(c−a)| / longest²` is about the sine of the face's smallest
/// angle, so faces with an angle below ~1e-14 rad (a few ulps of a unit-size coordinate) are
/// rejected. Such faces have no usable normal or tangent plane and break every scheme.
pub const DEGENERATE_AREA_RATIO: f64 = 1e-14;

/// How loading names a vertex in errors: as the input numbered it.
struct VertexNames<'a> {
    /// For each welded vertex, the first input vertex merged into it.
    representative: &'a [u32],
    /// Input index → the caller's own number (an OBJ file's `v` order); identity when None.
    labels: Option<&'a [u32]>,
}

impl VertexNames<'_> {
    fn input(&self, input: usize) -> usize {
        self.labels
            .and_then(|labels| labels.get(input))
            .map_or(input, |&label| label as usize)
    }
    fn welded(&self, v: u32) -> usize {
        self.input(self.representative[v as usize] as usize)
    }
}

/// Validates `faces` over `positions` and builds the mesh (see the module docs of `mesh` for
/// the steps). `labels` renames input vertices in errors; `corner_normals` are the file's
/// normals per face corner, or why there are none.
pub(super) fn assemble(
    positions: Vec<DVec3>,
    faces: Vec<[u32; 3]>,
    labels: Option<&[u32]>,
    corner_normals: std::result::Result<CornerNormals, String>,
) -> Result<(Mesh, LoadReport)> {
    if faces.is_empty() {
        return Err(Error::EmptyMesh);
    }
    // Half-edges are numbered 3·face + corner in u32, with u32::MAX reserved.
    if faces.len() >= (u32::MAX / 3) as usize {
        return Err(Error::Invalid(format!(
            "the mesh has {} faces; at most {} are supported",
            faces.len(),
            u32::MAX / 3 - 1
        )));
    }
    let mut report = LoadReport::default();
    let names_in = VertexNames {
        representative: &[],
        labels,
    };
    check_indices(&positions, &faces)?;
    if let Some(v) = positions.iter().position(|p| !p.is_finite()) {
        return Err(Error::NonFiniteVertex {
            vertex: names_in.input(v),
        });
    }

    let welding = weld(&positions, faces);
    let mut faces = welding.faces;
    report.welded = welding.welded;
    if welding.unused > 0 {
        report.warnings.push(format!(
            "dropped {} vertices used by no face",
            welding.unused
        ));
    }
    let names = VertexNames {
        representative: &welding.representative,
        labels,
    };
    let positions = welding.positions;

    check_degenerate(&positions, &faces)?;
    check_duplicates(&faces)?;
    let (twin, same_direction) = link_half_edges(&faces, &names)?;
    // The file's normals are matched to vertices before any face is flipped, while faces
    // still list their corners in file order.
    let obj_normals = normals::per_vertex_from_corners(corner_normals, &faces, positions.len(), &|v| {
        names.welded(v)
    });
    let flipped = orientation_flips(&faces, &twin, &same_direction, &names)?;
    let twin = apply_flips(&mut faces, twin, &flipped);
    let reoriented: Vec<usize> = (0..faces.len()).filter(|&f| flipped[f]).collect();
    if let Some(&first) = reoriented.first() {
        report.reoriented_faces = reoriented.len();
        report.warnings.push(format!(
            "re-oriented {} faces to agree with their neighbours (first: face {first})",
            reoriented.len()
        ));
    }
    let topology = Topology::build(&faces, twin, positions.len(), |v| names.welded(v))?;
    Ok((
        Mesh {
            positions,
            faces,
            obj_normals,
            topology,
        },
        report,
    ))
}

fn check_indices(positions: &[DVec3], faces: &[[u32; 3]]) -> Result<()> {
    for (f, face) in faces.iter().enumerate() {
        if let Some(&v) = face.iter().find(|&&v| v as usize >= positions.len()) {
            return Err(Error::VertexIndexOutOfRange {
                face: f,
                vertex: v as usize,
                count: positions.len(),
            });
        }
    }
    Ok(())
}

/// The result of dropping unused vertices and welding identical ones.
struct Welding {
    positions: Vec<DVec3>,
    faces: Vec<[u32; 3]>,
    representative: Vec<u32>,
    welded: usize,
    unused: usize,
}

/// Drops vertices used by no face and merges used vertices with bit-identical coordinates
/// into the first of them. Survivors keep their relative input order.
fn weld(positions: &[DVec3], mut faces: Vec<[u32; 3]>) -> Welding {
    let mut used = vec![false; positions.len()];
    for &v in faces.iter().flatten() {
        used[v as usize] = true;
    }
    let mut remap = vec![u32::MAX; positions.len()];
    let mut first_at: HashMap<[u64; 3], u32> = HashMap::with_capacity(positions.len());
    let mut welded_positions = Vec::with_capacity(positions.len());
    let mut representative = Vec::with_capacity(positions.len());
    let (mut welded, mut unused) = (0, 0);
    for (i, p) in positions.iter().enumerate() {
        if !used[i] {
            unused += 1;
            continue;
        }
        match first_at.entry(p.to_array().map(f64::to_bits)) {
            Entry::Occupied(entry) => {
                remap[i] = *entry.get();
                welded += 1;
            }
            Entry::Vacant(entry) => {
                let id = welded_positions.len() as u32;
                entry.insert(id);
                remap[i] = id;
                welded_positions.push(*p);
                representative.push(i as u32);
            }
        }
    }
    for face in &mut faces {
        *face = face.map(|v| remap[v as usize]);
    }
    Welding {
        positions: welded_positions,
        faces,
        representative,
        welded,
        unused,
    }
}

/// Rejects faces with a repeated corner or (numerically) zero area, see
/// [`DEGENERATE_AREA_RATIO`].
fn check_degenerate(positions: &[DVec3], faces: &[[u32; 3]]) -> Result<()> {
    for (f, &[a, b, c]) in faces.iter().enumerate() {
        let repeated = a == b || b == c || c == a;
        let [pa, pb, pc] = [a, b, c].map(|v| positions[v as usize]);
        let longest_squared = (pb - pa)
            .length_squared()
            .max((pc - pb).length_squared())
            .max((pa - pc).length_squared());
        let twice_area = (pb - pa).cross(pc - pa).length();
        // Written so that a NaN from overflowing coordinates also counts as degenerate.
        let has_area = twice_area > DEGENERATE_AREA_RATIO * longest_squared;
        if repeated || !has_area {
            return Err(Error::DegenerateFace { face: f });
        }
    }
    Ok(())
}

/// Rejects two faces on the same three vertices, in any order or orientation.
fn check_duplicates(faces: &[[u32; 3]]) -> Result<()> {
    let mut keyed: Vec<([u32; 3], u32)> = faces
        .iter()
        .enumerate()
        .map(|(f, face)| {
            let mut key = *face;
            key.sort_unstable();
            (key, f as u32)
        })
        .collect();
    keyed.sort_unstable();
    match keyed.windows(2).find(|pair| pair[0].0 == pair[1].0) {
        Some(pair) => Err(Error::DuplicateFace {
            face: pair[1].1 as usize,
            first: pair[0].1 as usize,
        }),
        None => Ok(()),
    }
}

/// Pairs the half-edges (3·face + corner, running from corner to the next) of each undirected
/// edge. Returns each half-edge's twin (or [`NO_TWIN`]) and whether it runs the same way as its
/// twin (which an oriented mesh never does). O(F log F) by sorting edge keys.
fn link_half_edges(faces: &[[u32; 3]], names: &VertexNames) -> Result<(Vec<u32>, Vec<bool>)> {
    let half_edge_count = 3 * faces.len();
    let from = |he: usize| faces[he / 3][he % 3];
    let to = |he: usize| faces[he / 3][(he + 1) % 3];
    let mut keyed: Vec<(u64, u32)> = (0..half_edge_count)
        .map(|he| {
            let (a, b) = (from(he), to(he));
            let key = (u64::from(a.min(b)) << 32) | u64::from(a.max(b));
            (key, he as u32)
        })
        .collect();
    keyed.sort_unstable();
    let mut twin = vec![NO_TWIN; half_edge_count];
    let mut same_direction = vec![false; half_edge_count];
    let mut start = 0;
    while start < keyed.len() {
        let key = keyed[start].0;
        let end = start + keyed[start..].iter().take_while(|k| k.0 == key).count();
        match end - start {
            1 => {}
            2 => {
                let (h0, h1) = (keyed[start].1, keyed[start + 1].1);
                twin[h0 as usize] = h1;
                twin[h1 as usize] = h0;
                let same = from(h0 as usize) == from(h1 as usize);
                same_direction[h0 as usize] = same;
                same_direction[h1 as usize] = same;
            }
            count => {
                return Err(Error::NonManifoldEdge {
                    a: names.welded((key >> 32) as u32),
                    b: names.welded(key as u32),
                    faces: count,
                });
            }
        }
        start = end;
    }
    Ok((twin, same_direction))
}

/// Decides which faces to flip so that every interior edge is run in opposite directions by
/// its two faces: a flood fill over each connected component, keeping the component's
/// lowest-numbered face as it is. A component that needs a face both flipped and kept is not
/// orientable (a Möbius strip).
fn orientation_flips(
    faces: &[[u32; 3]],
    twin: &[u32],
    same_direction: &[bool],
    names: &VertexNames,
) -> Result<Vec<bool>> {
    const UNSEEN: u8 = 2;
    let mut flip = vec![UNSEEN; faces.len()];
    let mut stack = Vec::new();
    for start in 0..faces.len() {
        if flip[start] != UNSEEN {
            continue;
        }
        flip[start] = 0;
        stack.push(start);
        while let Some(f) = stack.pop() {
            for e in 0..3 {
                let he = 3 * f + e;
                let t = twin[he];
                if t == NO_TWIN {
                    continue;
                }
                let g = t as usize / 3;
                let wanted = flip[f] ^ u8::from(same_direction[he]);
                if flip[g] == UNSEEN {
                    flip[g] = wanted;
                    stack.push(g);
                } else if flip[g] != wanted {
                    return Err(Error::NonOrientable {
                        a: names.welded(faces[f][e]),
                        b: names.welded(faces[f][(e + 1) % 3]),
                    });
                }
            }
        }
    }
    Ok(flip.into_iter().map(|state| state == 1).collect())
}

/// Flips the chosen faces by swapping their last two corners and renumbers the twins: a face
/// (a, b, c) becomes (a, c, b), whose edges 0, 1, 2 are the old edges 2, 1, 0 reversed.
fn apply_flips(faces: &mut [[u32; 3]], twin: Vec<u32>, flipped: &[bool]) -> Vec<u32> {
    if !flipped.contains(&true) {
        return twin;
    }
    let renumber = |he: u32| -> u32 {
        let (f, e) = (he / 3, he % 3);
        if flipped[f as usize] { 3 * f + (2 - e) } else { he }
    };
    for (face, &flip) in faces.iter_mut().zip(flipped) {
        if flip {
            face.swap(1, 2);
        }
    }
    let mut renumbered = vec![NO_TWIN; twin.len()];
    for (he, &t) in twin.iter().enumerate() {
        if t != NO_TWIN {
            renumbered[renumber(he as u32) as usize] = renumber(t);
        }
    }
    renumbered
}
