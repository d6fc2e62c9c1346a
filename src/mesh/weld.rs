//! Welding: vertices used by no face are dropped and vertices with bit-identical coordinates
//! are merged, so that faces written with repeated vertices (one copy per object, or per
//! corner) become connected.

use std::collections::HashMap;
use std::collections::hash_map::Entry;

use glam::DVec3;

/// The result of dropping unused vertices and welding identical ones.
pub(super) struct Welding {
    /// The surviving positions, in input order.
    pub(super) positions: Vec<DVec3>,
    /// The faces renumbered to the surviving vertices.
    pub(super) faces: Vec<[u32; 3]>,
    /// For each surviving vertex, the first input vertex merged into it (names it in errors).
    pub(super) representative: Vec<u32>,
    /// Used input vertices merged into an earlier one.
    pub(super) welded: usize,
    /// Input vertices used by no face.
    pub(super) unused: usize,
}

/// Drops vertices used by no face and merges used vertices with bit-identical coordinates
/// into the first of them. Survivors keep their relative input order.
pub(super) fn weld(positions: &[DVec3], mut faces: Vec<[u32; 3]>) -> Welding {
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

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use crate::error::Error;
    use crate::mesh::generate::{self, bad};
    use crate::mesh::{LoadReport, Mesh};

    fn load((positions, faces): (Vec<DVec3>, Vec<[u32; 3]>)) -> crate::Result<(Mesh, LoadReport)> {
        Mesh::from_triangles(positions, faces)
    }

    #[test]
    fn welding_merges_identical_positions_and_drops_unused_vertices() {
        let (mesh, report) = load(bad::octahedron_with_duplicate_vertices()).unwrap();
        assert_eq!(report.welded, 2);
        assert_eq!(
            report.warnings,
            vec!["dropped 1 vertices used by no face".to_string()]
        );
        let (positions, faces) = generate::octahedron();
        assert_eq!(mesh.positions(), &positions[..]);
        assert_eq!(mesh.faces(), &faces[..]);
    }

    #[test]
    fn welding_is_by_bit_pattern_so_negative_zero_stays_apart() {
        // A square as two triangles, the second written with copies of the diagonal's ends.
        // With an exact copy of the origin both copies weld and the square loads; with -0.0
        // the triangles share only the corner (1, 1, 0), which makes it a bow-tie.
        let square = |origin_copy: DVec3| {
            let positions = vec![
                DVec3::ZERO,
                DVec3::X,
                DVec3::new(1.0, 1.0, 0.0),
                origin_copy,
                DVec3::new(1.0, 1.0, 0.0),
                DVec3::Y,
            ];
            load((positions, vec![[0, 1, 2], [3, 4, 5]]))
        };
        let (mesh, report) = square(DVec3::ZERO).unwrap();
        assert_eq!(report.welded, 2);
        assert_eq!(mesh.vertex_count(), 4);
        let error = square(DVec3::new(-0.0, 0.0, 0.0)).unwrap_err();
        assert!(
            matches!(error, Error::NonManifoldVertex { vertex: 2, fans: 2 }),
            "{error}"
        );
    }
}
