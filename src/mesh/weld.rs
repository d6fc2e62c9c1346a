//! Welding: vertices used by no face are dropped, and used vertices closer than a tolerance
//! relative to the bounding-box diagonal are merged, so that faces written with repeated
//! vertices (one copy per object or per corner, or the seam of a parametric surface whose
//! copies differ by rounding) become connected.
//!
//! Merging is greedy in input order: each vertex joins the nearest earlier surviving vertex
//! within the tolerance, or survives itself. Survivors are found through a hash grid of cells
//! several tolerances wide, so each vertex looks in its own cell and at most 7 neighbours, and
//! welding takes O(n) expected time. A merged vertex therefore never moves by more than the tolerance,
//! and distinct survivors are always more than the tolerance apart.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hash, Hasher};

use glam::{BVec3, DVec3, I64Vec3};

use crate::error::Result;
use crate::geom::Aabb;

/// Default weld tolerance relative to the bounding-box diagonal (see [`super::LoadOptions`]).
///
/// Far below the spacing of distinct vertices of any real scan (a 10⁶-vertex scan has its
/// vertices ~10⁻³ diagonals apart), far above f64 rounding (~10⁻¹⁶ of the coordinates), so it
/// welds copies written with rounding differences, signed zeros and 1-ulp offsets, and nothing
/// else.
pub const DEFAULT_WELD_TOLERANCE: f64 = 1e-10;

/// The result of dropping unused vertices and welding close ones.
pub(super) struct Welding {
    /// The surviving positions, in input order.
    pub(super) positions: Vec<DVec3>,
    /// The faces renumbered to the surviving vertices.
    pub(super) faces: Vec<[u32; 3]>,
    /// For each surviving vertex, the first input vertex merged into it (names it in errors).
    pub(super) representative: Vec<u32>,
    /// Used input vertices merged into an earlier one.
    pub(super) welded: usize,
    /// Of those, the ones at a different position (closer than the tolerance, not equal; −0.0
    /// equals 0.0).
    pub(super) welded_near: usize,
    /// Largest distance between a merged vertex and the survivor it was merged into.
    pub(super) max_distance: f64,
    /// The tolerance as a distance.
    pub(super) tolerance: f64,
    /// Input vertices used by no face.
    pub(super) unused: usize,
    /// For each input vertex, the surviving vertex it became (`u32::MAX` if unused).
    pub(super) remap: Vec<u32>,
    /// The first face two of whose corners, at different positions, were merged.
    pub(super) first_collapse: Option<WeldCollapse>,
}

/// A face two of whose corners welding merged although they were at different positions.
#[derive(Clone, Copy, Debug)]
pub(super) struct WeldCollapse {
    /// The face (triangle index).
    pub(super) face: usize,
    /// One merged corner, as the input numbers it.
    pub(super) a: usize,
    /// The other.
    pub(super) b: usize,
    /// Their distance.
    pub(super) distance: f64,
}

/// Checks a relative weld tolerance: finite, 0 (identical positions only) or more, below 1.
pub fn check_weld_tolerance(relative: f64) -> std::result::Result<f64, String> {
    if (0.0..1.0).contains(&relative) {
        Ok(relative)
    } else {
        Err(format!(
            "weld tolerance {relative} is not in [0, 1) (a fraction of the bounding-box diagonal)"
        ))
    }
}

/// Drops vertices not flagged in `used` and merges used vertices closer than
/// `relative · diagonal` (the diagonal of `bounds`, the used vertices' bounding box) into the
/// nearest earlier survivor; survivors keep their relative input order. `name` gives an input
/// vertex's number for [`Welding::first_collapse`], the first face two of whose corners at
/// different positions were merged (the degenerate-face repair removes it and names the weld).
pub(super) fn weld(
    positions: &[DVec3],
    used: &[bool],
    bounds: Aabb,
    mut faces: Vec<[u32; 3]>,
    relative: f64,
    name: &dyn Fn(usize) -> usize,
) -> Result<Welding> {
    let diagonal = (bounds.max - bounds.min).length();
    let tolerance = relative * diagonal;
    let mut welder = PointWelder::new(bounds, tolerance, positions.len());

    let mut remap = vec![u32::MAX; positions.len()];
    let mut representative = Vec::with_capacity(positions.len());
    let (mut welded, mut welded_near, mut max_distance, mut unused) = (0, 0, 0.0f64, 0);
    for (i, &p) in positions.iter().enumerate() {
        if !used[i] {
            unused += 1;
            continue;
        }
        remap[i] = match welder.nearest(p) {
            Some((survivor, d)) => {
                welded += 1;
                if p != welder.positions[survivor as usize] {
                    welded_near += 1;
                    max_distance = max_distance.max(d);
                }
                survivor
            }
            None => {
                representative.push(i as u32);
                welder.push(p)
            }
        };
    }
    let mut first_collapse = None;
    for (f, face) in faces.iter_mut().enumerate() {
        let input = *face;
        *face = input.map(|v| remap[v as usize]);
        if first_collapse.is_some() {
            continue;
        }
        for (c, d) in [(0, 1), (1, 2), (2, 0)] {
            let (a, b) = (input[c] as usize, input[d] as usize);
            if face[c] == face[d] && positions[a] != positions[b] {
                first_collapse = Some(WeldCollapse {
                    face: f,
                    a: name(a),
                    b: name(b),
                    distance: distance(positions[a], positions[b]),
                });
                break;
            }
        }
    }
    Ok(Welding {
        positions: welder.positions,
        faces,
        representative,
        welded,
        welded_near,
        max_distance,
        tolerance,
        unused,
        remap,
        first_collapse,
    })
}

/// Greedy point welding in insertion order: a point within `tolerance` of an earlier
/// survivor becomes that survivor (the nearest, ties to the earlier), otherwise it survives.
/// Survivors are therefore more than the tolerance apart and a welded point moves by at most
/// the tolerance. Lookups go through a hash grid ([`Grid`]), so welding n points takes O(n)
/// expected time. Used by the mesh loader and by the welded OBJ tessellation
/// (`export::obj`).
pub struct PointWelder {
    grid: Grid,
    tolerance: f64,
    /// The survivors, in insertion order.
    pub positions: Vec<DVec3>,
}

impl PointWelder {
    /// An empty welder for points inside `bounds` merging within `tolerance` (a distance,
    /// 0 or more), with room for `capacity` survivors.
    pub fn new(bounds: Aabb, tolerance: f64, capacity: usize) -> PointWelder {
        let diagonal = (bounds.max - bounds.min).length();
        PointWelder {
            grid: Grid::new(bounds.min, tolerance, diagonal, capacity),
            tolerance,
            positions: Vec::with_capacity(capacity),
        }
    }

    /// The nearest survivor within the tolerance of `p` and its distance.
    pub fn nearest(&self, p: DVec3) -> Option<(u32, f64)> {
        self.grid
            .near(p)
            .map(|s| (s, distance(p, self.positions[s as usize])))
            .filter(|&(_, d)| d <= self.tolerance)
            .min_by(|x, y| x.1.total_cmp(&y.1).then(x.0.cmp(&y.0)))
    }

    /// Adds `p` as a survivor (whether or not one is near) and returns its number.
    pub fn push(&mut self, p: DVec3) -> u32 {
        let id = self.positions.len() as u32;
        self.grid.insert(p, id);
        self.positions.push(p);
        id
    }

    /// The survivor `p` welds to, added first when none is within the tolerance.
    pub fn weld(&mut self, p: DVec3) -> u32 {
        match self.nearest(p) {
            Some((survivor, _)) => survivor,
            None => self.push(p),
        }
    }
}

/// The distance from `p` to `q`, without underflow when they differ by subnormal amounts.
fn distance(p: DVec3, q: DVec3) -> f64 {
    let d = p - q;
    let plain = d.length();
    let largest = d.abs().max_element();
    if plain > 0.0 || largest == 0.0 {
        plain
    } else {
        largest * (d / largest).length()
    }
}

/// Ends a chain of survivors in a grid cell.
const END: u32 = u32::MAX;

/// A hash grid of surviving vertices. Cells are at least 8 tolerances wide, so the ball of
/// radius `tolerance` about a point reaches at most one neighbouring cell on each axis, and
/// only when the point lies within `reach` (the tolerance plus a thousandth of a cell for
/// rounding) of that cell's face: most points look in their own cell alone. The width is also
/// at least 2⁻⁴⁰ diagonals, which keeps cell indices far inside i64 when the tolerance is tiny
/// or zero. Survivors are more than the tolerance apart, so a cell holds at most a few hundred
/// of them even when the tolerance is as large as the mesh's edges.
struct Grid {
    origin: DVec3,
    inverse_width: f64,
    /// The tolerance plus a rounding margin, in cells (at most 0.126).
    reach: f64,
    /// First survivor of each occupied cell; the others are chained through `next`.
    first: HashMap<Cell, u32, BuildHasherDefault<CellHasher>>,
    /// The next survivor in the same cell ([`END`] ends the chain), per survivor.
    next: Vec<u32>,
}

impl Grid {
    /// An empty grid with room for `capacity` survivors.
    fn new(origin: DVec3, tolerance: f64, diagonal: f64, capacity: usize) -> Grid {
        let width = (8.0 * tolerance).max(diagonal * 2f64.powi(-40));
        // A zero diagonal (every vertex at one point) leaves one occupied cell of any width.
        let width = if width > 0.0 { width } else { 1.0 };
        Grid {
            origin,
            inverse_width: 1.0 / width,
            reach: tolerance / width + 1e-3,
            first: HashMap::with_capacity_and_hasher(capacity, Default::default()),
            next: Vec::with_capacity(capacity),
        }
    }

    /// Cell coordinates of `p` (continuous: the integer part is the cell).
    fn scaled(&self, p: DVec3) -> DVec3 {
        (p - self.origin) * self.inverse_width
    }

    fn insert(&mut self, p: DVec3, id: u32) {
        let cell = Cell(self.scaled(p).floor().as_i64vec3());
        let previous = self.first.insert(cell, id).unwrap_or(END);
        debug_assert_eq!(self.next.len(), id as usize);
        self.next.push(previous);
    }

    /// The survivors in the cells that the ball of radius `reach` about `p` meets: a superset
    /// of those within the tolerance.
    fn near(&self, p: DVec3) -> impl Iterator<Item = u32> + '_ {
        let scaled = self.scaled(p);
        let cell = scaled.floor();
        let within = scaled - cell;
        // On each axis, the neighbour on the side of the nearer face, and whether p is within
        // reach of that face.
        let lower = within.cmplt(DVec3::splat(0.5));
        let toward = DVec3::select(lower, DVec3::NEG_ONE, DVec3::ONE);
        let reaches = (within.cmplt(DVec3::splat(self.reach))
            | within.cmpgt(DVec3::splat(1.0 - self.reach)))
        .bitmask();
        let (own, neighbour) = (cell.as_i64vec3(), (cell + toward).as_i64vec3());
        // Bit k of `corner` picks the neighbour on axis k; only axes within reach.
        (0..8u32)
            .filter(move |corner| corner & !reaches == 0)
            .flat_map(move |corner| {
                let pick = BVec3::new(corner & 1 != 0, corner & 2 != 0, corner & 4 != 0);
                let first = self.first.get(&Cell(I64Vec3::select(pick, neighbour, own)));
                std::iter::successors(first.copied(), |&s| {
                    Some(self.next[s as usize]).filter(|&n| n != END)
                })
            })
    }
}

/// A grid cell; hashed by [`CellHasher`].
#[derive(Clone, Copy, PartialEq, Eq)]
struct Cell(I64Vec3);

impl Hash for Cell {
    fn hash<H: Hasher>(&self, state: &mut H) {
        for coordinate in self.0.to_array() {
            state.write_u64(coordinate as u64);
        }
    }
}

/// A fast multiplicative hasher for [`Cell`] keys. The grid never sees adversarial keys, and
/// the standard SipHash makes welding 2.5 times slower (0.52 s instead of 0.21 s for 10⁶
/// vertices).
#[derive(Default)]
struct CellHasher(u64);

impl Hasher for CellHasher {
    fn write(&mut self, bytes: &[u8]) {
        for &byte in bytes {
            self.write_u64(u64::from(byte));
        }
    }
    fn write_u64(&mut self, value: u64) {
        // Odd constant near 2⁶⁴/φ; the rotation spreads the high product bits downwards.
        self.0 = (self.0 ^ value)
            .wrapping_mul(0x9e37_79b9_7f4a_7c15)
            .rotate_left(29);
    }
    fn finish(&self) -> u64 {
        self.0
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use crate::error::Error;
    use crate::geom::Aabb;
    use crate::mesh::generate::{self, bad};
    use crate::mesh::{DEFAULT_WELD_TOLERANCE, Element, LoadOptions, LoadReport, Mesh, RepairKind};

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

    /// A square as two triangles, the second written with `origin_copy` for (0, 0, 0) and
    /// `corner_copy` for (1, 1, 0). If both copies weld the square loads with 4 vertices; if
    /// only the corner does, the triangles share one vertex, a bow-tie.
    fn square(
        origin_copy: DVec3,
        corner_copy: DVec3,
        weld_tolerance: f64,
    ) -> crate::Result<(Mesh, LoadReport)> {
        let positions = vec![
            DVec3::ZERO,
            DVec3::X,
            DVec3::new(1.0, 1.0, 0.0),
            origin_copy,
            corner_copy,
            DVec3::Y,
        ];
        let options = LoadOptions {
            weld_tolerance,
            ..Default::default()
        };
        Mesh::from_triangles_with(positions, vec![[0, 1, 2], [3, 4, 5]], &options)
    }

    #[test]
    fn signed_zero_copies_weld_silently_even_with_zero_tolerance() {
        let corner = DVec3::new(1.0, 1.0, 0.0);
        for origin_copy in [DVec3::new(-0.0, 0.0, 0.0), DVec3::splat(-0.0)] {
            for tolerance in [DEFAULT_WELD_TOLERANCE, 0.0] {
                let (mesh, report) = square(origin_copy, corner, tolerance).unwrap();
                assert_eq!(mesh.vertex_count(), 4);
                assert_eq!((report.welded, report.welded_near), (2, 0));
                assert_eq!(report.weld_max_distance, 0.0);
                assert!(report.warnings.is_empty(), "{:?}", report.warnings);
                // The first copy's position is kept.
                assert_eq!(mesh.positions()[0].x.to_bits(), 0.0f64.to_bits());
            }
        }
    }

    #[test]
    fn one_ulp_copies_weld_with_a_warning_unless_the_tolerance_is_zero() {
        let origin_copy = DVec3::new(f64::from_bits(1), 0.0, 0.0); // the smallest subnormal
        let corner_copy = DVec3::new(1.0f64.next_up(), 1.0, 0.0);
        let (mesh, report) = square(origin_copy, corner_copy, DEFAULT_WELD_TOLERANCE).unwrap();
        assert_eq!(mesh.vertex_count(), 4);
        assert_eq!((report.welded, report.welded_near), (2, 2));
        assert_eq!(report.weld_max_distance, f64::EPSILON);
        assert_eq!(report.warnings.len(), 1, "{:?}", report.warnings);
        let warning = &report.warnings[0];
        assert!(
            warning.starts_with("welded 2 vertices") && warning.contains("2.220e-16"),
            "{warning}"
        );
        // With tolerance 0 only identical positions weld: both copies stay apart, so the
        // triangles share no vertex and the mesh has a boundary all round.
        let (mesh, report) = square(origin_copy, corner_copy, 0.0).unwrap();
        assert_eq!((mesh.vertex_count(), report.welded), (6, 0));
    }

    #[test]
    fn seams_that_differ_by_rounding_weld_into_closed_meshes() {
        // (name, triangles, welded vertex count, Euler characteristic)
        let cases = [
            ("torus", bad::seamed_torus(24, 12), 24 * 12, 0),
            ("sphere", bad::seamed_sphere(16, 10), 16 * 9 + 2, 2),
            ("cylinder", bad::seamed_cylinder(20, 3), 20 * 4 + 2, 2),
        ];
        for (name, (positions, faces), vertices, euler) in cases {
            let used: std::collections::HashSet<u32> = faces.iter().flatten().copied().collect();
            // Exact welding leaves the seams open (or collapses the pole triangles).
            let exact = Mesh::from_triangles_with(
                positions.clone(),
                faces.clone(),
                &LoadOptions {
                    weld_tolerance: 0.0,
                    ..Default::default()
                },
            );
            assert!(
                exact.as_ref().map_or(true, |(mesh, _)| !mesh.is_closed()),
                "{name}: closed without tolerance"
            );
            let (mesh, report) = load((positions, faces)).unwrap();
            assert!(mesh.is_closed(), "{name}: open");
            assert_eq!(mesh.vertex_count(), vertices, "{name}");
            assert_eq!(mesh.euler_characteristic(), euler, "{name}");
            assert_eq!(report.welded, used.len() - vertices, "{name}");
            assert!(report.welded_near > 0, "{name}");
            assert!(
                report.weld_max_distance > 0.0 && report.weld_max_distance < 1e-15,
                "{name}: {}",
                report.weld_max_distance
            );
            assert_eq!(report.reoriented_faces, 0, "{name}");
            let welding_warnings = report.warnings.iter().filter(|w| w.starts_with("welded "));
            assert_eq!(welding_warnings.count(), 1, "{name}: {:?}", report.warnings);
        }
    }

    #[test]
    fn rounding_seam_torus_builds_hb_with_g1_joints() {
        let (mesh, _) = load(bad::seamed_torus(12, 8)).unwrap();
        let surface = crate::schemes::build("hb", &mesh, &[]).expect("hb on the welded torus");
        let metrics = crate::metrics::Metrics::measure(&surface, &mesh, 0.0);
        let figures = crate::testing::assert_g1_joints(&metrics, "seamed torus");
        eprintln!("seamed torus, hb: {figures:?}");
    }

    #[test]
    fn a_tolerance_that_collapses_an_edge_is_a_repair_naming_the_weld() {
        // The octahedron with face 5 split at a point 1e-6 from its first corner: faces 5, 8
        // and 9 are (a, b, m), (b, c, m), (c, a, m).
        let (mut positions, mut faces) = generate::octahedron();
        let [a, b, c] = faces[5];
        let corner = positions[a as usize];
        let centre = (corner + positions[b as usize] + positions[c as usize]) / 3.0;
        let m = positions.len() as u32;
        positions.push(corner + (centre - corner).normalize() * 1e-6);
        faces[5] = [a, b, m];
        faces.extend([[b, c, m], [c, a, m]]);
        let diagonal = 2.0 * 3f64.sqrt();
        let (mesh, report) = load((positions.clone(), faces.clone())).unwrap();
        assert_eq!((mesh.vertex_count(), report.welded), (7, 0));
        let mut options = LoadOptions {
            weld_tolerance: 2e-6 / diagonal,
            ..Default::default()
        };
        // Welding m into a collapses faces 5 and 9; face 8 becomes the octahedron's face 5.
        let (mesh, report) =
            Mesh::from_triangles_with(positions.clone(), faces.clone(), &options).unwrap();
        assert_eq!(mesh.face_count(), 8);
        let repair = &report.repairs[0];
        assert_eq!(
            (repair.kind, repair.count, repair.first),
            (RepairKind::DegenerateFaceCollapsed, 2, Element::Face(5))
        );
        assert!(
            repair.detail.starts_with(&format!(
                "welding merged its corners {m} and {a} (1.000e-6 apart, within the weld \
                 tolerance 2.000e-6; a smaller --weld-tolerance keeps them apart)"
            )),
            "{}",
            repair.detail
        );
        options.strict = true;
        let error = Mesh::from_triangles_with(positions, faces, &options).unwrap_err();
        assert!(matches!(error, Error::RepairRefused { .. }), "{error}");
        assert!(
            error.to_string().starts_with("face 5: welding merged"),
            "{error}"
        );
    }

    #[test]
    fn the_default_tolerance_merges_no_vertex_of_the_scans() {
        // The scans' closest vertices are 1.4e-2 diagonals apart: even 1e7 times the default
        // tolerance merges nothing.
        for scan in &generate::SCANNED_SCENES {
            let text = std::fs::read_to_string(scan.path()).unwrap();
            let vertex_records = text.lines().filter(|l| l.starts_with("v ")).count();
            for weld_tolerance in [DEFAULT_WELD_TOLERANCE, 1e7 * DEFAULT_WELD_TOLERANCE] {
                let options = LoadOptions {
                    weld_tolerance,
                    ..Default::default()
                };
                let (mesh, report) = Mesh::parse_obj_with(&text, &options).unwrap();
                assert_eq!(report.welded, 0, "{}", scan.name);
                assert_eq!(mesh.vertex_count(), vertex_records, "{}", scan.name);
            }
        }
    }

    #[test]
    fn grid_welding_matches_brute_force() {
        // Points in the unit cube, each followed by copies at distances up to twice the
        // tolerance in random directions, welded by the grid and by comparing every pair.
        let mut random = crate::testing::Rng::new(3);
        let mut unit = || random.next_f64();
        for tolerance in [0.0, 1e-15, 1e-9, 1e-3, 3e-2] {
            let mut positions: Vec<DVec3> = Vec::new();
            for _ in 0..400 {
                let base = DVec3::new(unit(), unit(), unit());
                positions.push(base);
                for _ in 0..3 {
                    let direction = DVec3::new(unit(), unit(), unit()) - 0.5;
                    let offset = direction.normalize() * 2.0 * tolerance * unit();
                    positions.push(base + offset);
                }
            }
            let used = vec![true; positions.len()];
            let bounds = Aabb::from_points(&positions);
            let diagonal = (bounds.max - bounds.min).length();
            // One (degenerate) face per vertex, to read back where it went.
            let faces = (0..positions.len() as u32).map(|v| [v; 3]).collect();
            let welding = super::weld(
                &positions,
                &used,
                bounds,
                faces,
                tolerance / diagonal,
                &|v| v,
            )
            .unwrap();
            let absolute = welding.tolerance;
            let mut survivors: Vec<usize> = Vec::new();
            let mut merges = 0;
            for (i, &p) in positions.iter().enumerate() {
                let nearest = survivors
                    .iter()
                    .enumerate()
                    .map(|(s, &input)| (s, super::distance(p, positions[input])))
                    .filter(|&(_, d)| d <= absolute)
                    .min_by(|x, y| x.1.total_cmp(&y.1));
                let expected = match nearest {
                    Some((s, _)) => {
                        merges += 1;
                        s
                    }
                    None => {
                        survivors.push(i);
                        survivors.len() - 1
                    }
                };
                assert_eq!(
                    welding.faces[i][0] as usize, expected,
                    "vertex {i}, tolerance {tolerance}"
                );
            }
            assert_eq!(welding.welded, merges, "tolerance {tolerance}");
            if tolerance > 0.0 {
                assert!(merges > 300, "tolerance {tolerance}: only {merges} merges");
            }
        }
    }

    #[test]
    fn welding_a_large_mesh_merges_every_copy() {
        // An icosphere of 163,842 vertices written with one copy of each vertex per face
        // (983,040 copies), every copy moved by at most 1e-15 on each axis.
        let sphere = generate::analytic::sphere(7);
        let mut positions = Vec::with_capacity(3 * sphere.faces.len());
        let mut faces = Vec::with_capacity(sphere.faces.len());
        let mut jitter = crate::testing::Rng::new(7);
        for face in &sphere.faces {
            let base = positions.len() as u32;
            for &v in face {
                let offset = DVec3::new(jitter.next_f64(), jitter.next_f64(), jitter.next_f64());
                positions.push(sphere.positions[v as usize] + (offset - 0.5) * 2e-15);
            }
            faces.push([base, base + 1, base + 2]);
        }
        let start = std::time::Instant::now();
        let (mesh, report) = load((positions, faces)).unwrap();
        eprintln!(
            "loaded {} copies into {} vertices in {:.2} s",
            3 * sphere.faces.len(),
            mesh.vertex_count(),
            start.elapsed().as_secs_f64()
        );
        assert_eq!(mesh.vertex_count(), sphere.positions.len());
        assert!(mesh.is_closed());
        assert_eq!(
            report.welded,
            3 * sphere.faces.len() - sphere.positions.len()
        );
    }
}
