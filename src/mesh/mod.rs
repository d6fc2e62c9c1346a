//! Triangle meshes: OBJ, PLY, OFF and STL input, welding, validation with typed errors,
//! half-edge topology, ordered one-rings and vertex normals. Every scheme reads its input
//! through [`Mesh`].
//!
//! Loading runs one pipeline for every source ([`Mesh::from_triangles`], [`Mesh::load`],
//! [`Mesh::parse_obj`], [`Mesh::parse_format`]). Every file reader produces the same
//! intermediate, positions and polygons in file order, and then:
//! 1. reject an empty mesh, faces with fewer than three corners, out-of-range indices,
//!    non-finite coordinates;
//! 2. split planar convex polygons into triangles, a fan from their first corner, with a
//!    warning stating how many (within [`PLANARITY_TOLERANCE`] and [`CONVEXITY_TOLERANCE`]);
//!    refuse any other polygon naming it;
//! 3. reject coordinates out of the supported range ([`MAX_COORDINATE_MAGNITUDE`],
//!    [`MIN_COORDINATE_SPAN`]);
//! 4. drop vertices used by no face and weld vertices closer than the weld tolerance
//!    ([`LoadOptions::weld_tolerance`], by default [`DEFAULT_WELD_TOLERANCE`] of the
//!    bounding-box diagonal), rejecting a face two of whose corners welding would merge;
//!    identical positions are always welded, which connects the separate facets of an STL file;
//! 5. reject degenerate and duplicate faces, non-manifold edges (areas are measured on
//!    coordinates normalised to unit size, so the verdict does not depend on the scale);
//! 6. orient every connected component consistently (or report a non-orientable one);
//! 7. build the half-edge topology and the ordered one-rings, rejecting bow-tie vertices.
//!
//! Errors name vertices as the input numbers them (the index into `positions`, or for a file
//! the 0-based position of the vertex in the file; for STL `3·facet + corner`), so a user can
//! find the element at fault. Faces are numbered in input order, 0-based, as the file numbers
//! its polygons. After loading, the mesh has its own vertex numbering (see
//! [`Mesh::from_triangles`]) and numbers triangles, not polygons.

mod formats;
pub(crate) mod front_facing;
pub mod generate;
mod normals;
mod obj;
mod polygon;
pub(crate) mod repair;
mod sharp;
mod topology;
mod unfold;
mod validate;
mod weld;

use std::path::Path;

use glam::DVec3;

use crate::error::{Error, Result};
use crate::geom::Aabb;

pub use formats::MeshFormat;
pub use normals::OBJ_NORMAL_ANGLE_TOLERANCE;
pub use polygon::{CONVEXITY_TOLERANCE, PLANARITY_TOLERANCE};
pub use repair::{Element, Repair, RepairKind};
pub(crate) use sharp::turn_angle;
pub use sharp::{SharpEdges, crease_tangent};
pub use validate::{DEGENERATE_AREA_RATIO, MAX_COORDINATE_MAGNITUDE, MIN_COORDINATE_SPAN};
pub use weld::{DEFAULT_WELD_TOLERANCE, PointWelder, check_weld_tolerance};

use normals::ObjNormals;
use topology::{NO_TWIN, Topology};

/// Cosine of the angle between the two sharp edges of an interior vertex above which their
/// crease turns back there (a hairpin, less than a right angle between them) and its two
/// sectors take the edges' plane for their normals (`Mesh::hairpin_normals`): a crease line
/// through the vertex would leave each edge by more than half a right angle.
pub(crate) const HAIRPIN_COS: f64 = 0.0;

/// Where vertex normals come from (`--param normals=estimate|obj`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum NormalSource {
    /// Angle-weighted average of the incident face normals.
    #[default]
    Estimate,
    /// The normals stored in the OBJ file (error if there are none or they disagree per vertex).
    Obj,
}

/// How a mesh is loaded.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LoadOptions {
    /// Vertices closer than this fraction of the bounding-box diagonal are welded into one
    /// (default [`DEFAULT_WELD_TOLERANCE`]; 0 welds identical positions only). Must be in
    /// [0, 1), see [`check_weld_tolerance`].
    pub weld_tolerance: f64,
    /// Edges whose faces' normals are more than this many degrees apart are sharp (the
    /// surface is only G0 across them), and so are the edges the file marks sharp (OBJ
    /// smoothing groups, per-corner normals); None (the default) marks none. Must be in
    /// [0, 180], see [`check_crease_angle`].
    pub crease_angle: Option<f64>,
    /// Refuse every repair (`--strict`): the first repair loading would make is an
    /// [`Error::RepairRefused`] naming the element instead (default false: repair and warn).
    pub strict: bool,
}

impl Default for LoadOptions {
    fn default() -> Self {
        LoadOptions {
            weld_tolerance: DEFAULT_WELD_TOLERANCE,
            crease_angle: None,
            strict: false,
        }
    }
}

impl LoadOptions {
    /// These options with [`LoadOptions::crease_angle`] set to `degrees`.
    pub fn with_crease_angle(self, degrees: Option<f64>) -> Self {
        LoadOptions {
            crease_angle: degrees,
            ..self
        }
    }
}

/// Checks a crease angle in degrees: finite and in [0, 180] (the angle between two face
/// normals; 180 marks only the edges the file marks sharp).
pub fn check_crease_angle(degrees: f64) -> std::result::Result<f64, String> {
    if (0.0..=180.0).contains(&degrees) {
        Ok(degrees)
    } else {
        Err(format!(
            "crease angle {degrees} is not in [0, 180] degrees (the angle between the normals \
             of an edge's two faces above which the edge is sharp)"
        ))
    }
}

/// What loading did to the input besides parsing: welded vertices, re-oriented faces, warnings.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LoadReport {
    /// Vertices merged into an earlier vertex at the same position or within the weld
    /// tolerance.
    pub welded: usize,
    /// Of the welded vertices, those at a different position from the vertex they were
    /// merged into (closer than the tolerance, not identical; −0.0 and 0.0 are identical).
    /// Loading warns when there are any.
    pub welded_near: usize,
    /// The largest distance between a welded vertex and the vertex it was merged into.
    pub weld_max_distance: f64,
    /// Faces whose orientation was flipped (for consistency within their component, or with
    /// the whole component to face outward); each is also counted in a [`Repair`].
    pub reoriented_faces: usize,
    /// The repairs made, in the order they were made (each also one line of `warnings`).
    pub repairs: Vec<Repair>,
    /// Human-readable warnings (one line each).
    pub warnings: Vec<String>,
    /// Edges marked sharp (by the crease angle or by the file, see [`SharpEdges`]).
    pub sharp_edges: usize,
}

/// One undirected mesh edge with its one or two faces.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MeshEdge {
    /// Smaller vertex index.
    pub a: u32,
    /// Larger vertex index.
    pub b: u32,
    /// The face on one side, and the face on the other (None on a boundary edge).
    pub faces: (u32, Option<u32>),
}

/// A validated, consistently oriented, manifold triangle mesh with its topology.
#[derive(Clone, Debug)]
pub struct Mesh {
    positions: Vec<DVec3>,
    faces: Vec<[u32; 3]>,
    /// The input face (polygon) each triangle was cut from.
    face_origin: Vec<u32>,
    /// The input vertex each vertex stands for, as the file numbers its vertices (the first
    /// of those welded into it; a vertex split off by a repair names the one it was split
    /// from).
    vertex_origin: Vec<u32>,
    /// The repairs loading made.
    repairs: Vec<Repair>,
    obj_normals: ObjNormals,
    topology: Topology,
    sharp: SharpEdges,
}

impl Mesh {
    /// Builds and validates a mesh (weld, checks, orientation, topology) with the default
    /// [`LoadOptions`].
    ///
    /// Vertices used by no face are dropped (one warning line) and vertices closer than the
    /// weld tolerance are welded into the nearest earlier survivor; the remaining vertices keep
    /// their input order, so a clean input keeps its numbering. Faces keep their input order; a
    /// face is only ever re-oriented by swapping its last two corners, so `faces()[f][0]` is
    /// always the first corner given for face `f`.
    pub fn from_triangles(
        positions: Vec<DVec3>,
        faces: Vec<[u32; 3]>,
    ) -> Result<(Mesh, LoadReport)> {
        Mesh::from_triangles_with(positions, faces, &LoadOptions::default())
    }

    /// [`Mesh::from_triangles`] with the given options.
    pub fn from_triangles_with(
        positions: Vec<DVec3>,
        faces: Vec<[u32; 3]>,
        options: &LoadOptions,
    ) -> Result<(Mesh, LoadReport)> {
        let origin = (0..faces.len() as u32).collect();
        validate::assemble(
            positions,
            faces,
            origin,
            None,
            validate::FileMarks::none("the mesh was not read from an OBJ file"),
            options,
            repair::Repairs::new(options.strict),
        )
    }

    /// Builds a mesh from `positions` and polygons of any number of corners with `options`,
    /// by the pipeline every file reader takes (see the module docs): planar convex polygons
    /// are split into triangles with a warning, any other polygon is refused naming it, and
    /// errors and repairs name polygons by their index. `corners` are the polygons' vertex
    /// indices one polygon after the other, `arities` the number of corners of each (their sum
    /// must be `corners.len()`). The mesh carries no normals and no sharp edges of its own
    /// (a crease angle in `options` still marks edges sharp).
    pub fn from_polygons_with(
        positions: Vec<DVec3>,
        corners: Vec<u32>,
        arities: Vec<u32>,
        options: &LoadOptions,
    ) -> Result<(Mesh, LoadReport)> {
        let total: u64 = arities.iter().map(|&a| u64::from(a)).sum();
        if total != corners.len() as u64 {
            return Err(Error::Invalid(format!(
                "the polygons' corner counts add up to {total}, but {} corners are given",
                corners.len()
            )));
        }
        polygon::assemble(
            polygon::PolygonMesh {
                positions,
                corners,
                arities,
            },
            None,
            Err("the mesh was given as polygons, which carry no normals".to_string()),
            &[],
            options,
        )
    }

    /// Loads a mesh file in the format its extension names ([`MeshFormat::from_path`], case
    /// ignored), with the default [`LoadOptions`].
    ///
    /// A missing or unreadable file is [`Error::Io`] naming the path, an unknown extension
    /// [`Error::UnknownMeshFormat`] listing the supported ones. See [`Mesh::parse_obj`] for
    /// what is read from OBJ; PLY, OFF and STL give positions and faces only.
    pub fn load(path: &Path) -> Result<(Mesh, LoadReport)> {
        Mesh::load_with(path, &LoadOptions::default())
    }

    /// [`Mesh::load`] with the given options.
    pub fn load_with(path: &Path, options: &LoadOptions) -> Result<(Mesh, LoadReport)> {
        let format = MeshFormat::from_path(path)?;
        let bytes = std::fs::read(path).map_err(|source| Error::io(path, source))?;
        formats::parse(&bytes, format, path, options)
    }

    /// Parses the bytes of a mesh file in `format` (for embedded meshes and tests); errors
    /// name the data as `<PLY data>` and so on.
    pub fn parse_format(
        bytes: &[u8],
        format: MeshFormat,
        options: &LoadOptions,
    ) -> Result<(Mesh, LoadReport)> {
        let origin = format!("<{} data>", format.name());
        formats::parse(bytes, format, Path::new(&origin), options)
    }

    /// Loads an OBJ file whatever its extension (position indices only; normals kept per
    /// position when consistent).
    ///
    /// See [`Mesh::parse_obj`] for what is read; a missing or unreadable file is
    /// [`Error::Io`] naming the path.
    pub fn load_obj(path: &Path) -> Result<(Mesh, LoadReport)> {
        Mesh::load_obj_with(path, &LoadOptions::default())
    }

    /// [`Mesh::load_obj`] with the given options.
    pub fn load_obj_with(path: &Path, options: &LoadOptions) -> Result<(Mesh, LoadReport)> {
        let bytes = std::fs::read(path).map_err(|source| Error::io(path, source))?;
        formats::parse(&bytes, MeshFormat::Obj, path, options)
    }

    /// Parses OBJ text (for embedded meshes and tests).
    ///
    /// Only positions, normals and faces are read; objects, groups and materials are ignored, so
    /// all objects of a file form one mesh. Per-corner normal and texture indices never split a
    /// vertex. The mesh keeps the file's vertex order, less unused and welded vertices, and
    /// errors name vertices by their 0-based position among the file's `v` records. The file's
    /// normals are kept for [`NormalSource::Obj`] when every face corner names one and each
    /// vertex gets one direction (within [`OBJ_NORMAL_ANGLE_TOLERANCE`]). Polygons with more
    /// than three corners are split into triangles when planar and convex, and refused
    /// otherwise ([`Error::NonPlanarFace`], [`Error::NonConvexFace`]): how a bent or concave
    /// polygon is split changes every surface built on it, so that choice stays with the
    /// modeller that made the file. A UTF-8 byte-order mark is skipped, and lines may end in
    /// LF, CR LF or CR alone (old Mac files).
    pub fn parse_obj(text: &str) -> Result<(Mesh, LoadReport)> {
        Mesh::parse_obj_with(text, &LoadOptions::default())
    }

    /// [`Mesh::parse_obj`] with the given options.
    pub fn parse_obj_with(text: &str, options: &LoadOptions) -> Result<(Mesh, LoadReport)> {
        obj::parse(text, Path::new("<OBJ text>"), options)
    }

    /// Vertex positions.
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }
    /// Faces as counter-clockwise vertex triples (consistently oriented).
    pub fn faces(&self) -> &[[u32; 3]] {
        &self.faces
    }
    /// The input face that triangle `t` was cut from, as the input numbers its faces
    /// (polygons); `t` itself for a triangle mesh loaded without repairs. Panics if `t` is not
    /// a face.
    pub fn input_face(&self, t: u32) -> usize {
        self.face_origin[t as usize] as usize
    }
    /// The input vertex that vertex `v` stands for, as the file numbers its vertices (an OBJ
    /// file's `v` records from 0): the first input vertex welded into it, or for a vertex split
    /// off by a repair the one it was split from; `v` itself for a mesh loaded without welds or
    /// repairs. Messages name vertices by this number. Panics if `v` is not a vertex.
    pub fn input_vertex(&self, v: u32) -> usize {
        self.vertex_origin[v as usize] as usize
    }
    /// The input face of every triangle (see [`Mesh::input_face`]).
    pub fn face_origins(&self) -> &[u32] {
        &self.face_origin
    }
    /// The repairs loading made to the input (also in [`LoadReport::repairs`]).
    pub fn repairs(&self) -> &[Repair] {
        &self.repairs
    }
    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }
    /// Number of faces.
    pub fn face_count(&self) -> usize {
        self.faces.len()
    }
    /// Number of undirected edges.
    pub fn edge_count(&self) -> usize {
        // Every interior edge has two half-edges, every boundary edge one.
        let boundary = self.topology.boundary_half_edges;
        (3 * self.faces.len() + boundary) / 2
    }
    /// Euler characteristic V − E + F (2 − 2g for a closed surface of genus g).
    pub fn euler_characteristic(&self) -> i64 {
        self.vertex_count() as i64 - self.edge_count() as i64 + self.face_count() as i64
    }
    /// Number of edges at vertex `v`.
    pub fn valence(&self, v: u32) -> usize {
        self.one_ring(v).len()
    }
    /// Neighbours of `v` ordered so that `(v, ring[j], ring[j+1])` is a face (indices mod n
    /// for an interior vertex; for a boundary vertex the fan starts and ends at the boundary).
    ///
    /// For a boundary vertex, `(v, ring[0])` is the boundary edge whose face runs from `v` to
    /// `ring[0]`, and `(ring[n-1], v)` is the other boundary edge. Returns a slice into stored
    /// arrays (no allocation). Panics if `v` is not a vertex of the mesh.
    pub fn one_ring(&self, v: u32) -> &[u32] {
        self.topology.one_ring(v)
    }
    /// `ring_faces(v)[j]` is the face `(v, one_ring(v)[j], one_ring(v)[j+1])`.
    ///
    /// It has n entries for an interior vertex of valence n and n − 1 for a boundary vertex.
    pub fn ring_faces(&self, v: u32) -> &[u32] {
        self.topology.ring_faces(v)
    }
    /// True if `v` lies on a boundary edge.
    pub fn is_boundary_vertex(&self, v: u32) -> bool {
        self.topology.boundary_vertex[v as usize]
    }
    /// True if no edge is a boundary edge.
    pub fn is_closed(&self) -> bool {
        self.topology.boundary_half_edges == 0
    }
    /// The first boundary edge, if any (for "needs a closed mesh" errors).
    ///
    /// The edge is returned in the direction its face runs along it.
    pub fn first_boundary_edge(&self) -> Option<(u32, u32)> {
        let he = self.topology.twin.iter().position(|&t| t == NO_TWIN)?;
        let face = self.faces[he / 3];
        Some((face[he % 3], face[(he + 1) % 3]))
    }
    /// The face across edge `e` of face `f` (edge e runs from `faces[f][e]` to
    /// `faces[f][(e+1)%3]`) and that edge's index in the neighbour; None on a boundary.
    /// Panics if `f` is not a face or `e` > 2.
    pub fn neighbor(&self, f: u32, e: usize) -> Option<(u32, usize)> {
        assert!(e < 3, "a triangle has edges 0, 1, 2; asked for edge {e}");
        let twin = self.topology.twin[3 * f as usize + e];
        (twin != NO_TWIN).then_some((twin / 3, (twin % 3) as usize))
    }
    /// The edge of every half-edge `3·f + e` as one number shared by exactly the edge's two
    /// half-edges (the smaller of them; a boundary half-edge is its own), for
    /// [`crate::surface::Surface::joints`]: distinct edges get distinct numbers even where two
    /// of them join the same two vertices, which the repairs of non-manifold input can leave
    /// (a face split off an edge whose ends stay one fan each).
    pub fn edge_ids(&self) -> Vec<u32> {
        (0..self.topology.twin.len() as u32)
            .map(|he| he.min(self.topology.twin[he as usize]))
            .collect()
    }
    /// All undirected edges, each once, in order of their first half-edge (face by face).
    pub fn edges(&self) -> Vec<MeshEdge> {
        let mut edges = Vec::with_capacity(self.edge_count());
        for (he, &twin) in self.topology.twin.iter().enumerate() {
            if twin != NO_TWIN && (twin as usize) < he {
                continue;
            }
            let face = self.faces[he / 3];
            let (from, to) = (face[he % 3], face[(he + 1) % 3]);
            edges.push(MeshEdge {
                a: from.min(to),
                b: from.max(to),
                faces: (he as u32 / 3, (twin != NO_TWIN).then_some(twin / 3)),
            });
        }
        edges
    }
    /// One unit normal per vertex.
    ///
    /// [`NormalSource::Estimate`] is the angle-weighted average of the incident face normals
    /// [Thürmer & Wüthrich 1998]; [`NormalSource::Obj`] returns the file's normals (unit length) or
    /// [`Error::MissingNormals`] saying why they cannot be used.
    pub fn vertex_normals(&self, source: NormalSource) -> Result<Vec<DVec3>> {
        match source {
            NormalSource::Estimate => normals::angle_weighted(&self.positions, &self.faces),
            NormalSource::Obj => self.obj_normals.per_vertex(),
        }
    }
    /// Unit normal of face `f` (from its counter-clockwise corners).
    pub fn face_normal(&self, f: u32) -> DVec3 {
        let [a, b, c] = self.faces[f as usize].map(|v| self.positions[v as usize]);
        (b - a).cross(c - a).normalize()
    }
    /// The sharp edges ([`LoadOptions::crease_angle`]; none by default).
    pub fn sharp_edges(&self) -> &SharpEdges {
        &self.sharp
    }
    /// True if edge `e` of face `f` (from `faces[f][e]` to `faces[f][(e+1)%3]`) is sharp.
    pub fn is_sharp(&self, f: u32, e: usize) -> bool {
        self.sharp.is_sharp(3 * f as usize + e)
    }
    /// The face pairs `(f, g)`, `f < g`, across every sharp edge, sorted.
    pub fn sharp_face_pairs(&self) -> Vec<(u32, u32)> {
        let mut pairs: Vec<(u32, u32)> = (0..self.topology.twin.len())
            .filter(|&he| self.sharp.is_sharp(he))
            .map(|he| {
                let (f, g) = (he as u32 / 3, self.topology.twin[he] / 3);
                (f.min(g), f.max(g))
            })
            .collect();
        pairs.sort_unstable();
        pairs.dedup();
        pairs
    }
    /// The mesh with the edges `edges` (vertex pairs, either order; each an interior edge)
    /// sharp as well: the edges a construction makes sharp where its smooth surface would
    /// fold (counted apart in [`SharpEdges::at_spikes`]). Edges already sharp stay as they
    /// are. Panics if a pair is not an interior edge of the mesh.
    pub fn with_spike_edges(&self, edges: &[(u32, u32)]) -> Mesh {
        let mut mesh = self.clone();
        for &(a, b) in edges {
            // A repaired non-manifold edge can leave two edges with the same ends: both.
            let halves: Vec<(usize, usize)> = self
                .ring_faces(a)
                .iter()
                .flat_map(|&f| (0..3).map(move |e| 3 * f as usize + e))
                .filter(|&he| {
                    let face = self.faces[he / 3];
                    let ends = (face[he % 3], face[(he + 1) % 3]);
                    ends == (a, b) || ends == (b, a)
                })
                .filter_map(|he| {
                    let twin = self.topology.twin[he];
                    (twin != NO_TWIN).then_some((he, twin as usize))
                })
                .collect();
            assert!(!halves.is_empty(), "({a}, {b}) is no interior edge");
            for (he, twin) in halves {
                mesh.sharp.mark_at_spike(he, twin, (a.min(b), a.max(b)));
            }
        }
        mesh
    }
    /// Number of sharp edges at vertex `v` (1 for a dart, 3 or more for a corner).
    pub fn sharp_valence(&self, v: u32) -> usize {
        self.sharp_cuts(v).count()
    }
    /// True if the fan of `v` is one smooth sector (no sharp edge, or a single one at an
    /// interior vertex: a dart), so that a vertex normal serves all its faces.
    pub fn has_one_sector(&self, v: u32) -> bool {
        match self.sharp_valence(v) {
            0 => true,
            1 => !self.is_boundary_vertex(v),
            _ => false,
        }
    }
    /// The fan positions `j` at which a sharp edge `(v, one_ring(v)[j])` separates
    /// `ring_faces(v)[j − 1]` from `ring_faces(v)[j]`, in fan order.
    pub fn sharp_cuts(&self, v: u32) -> impl Iterator<Item = usize> + '_ {
        let ring_faces = self.ring_faces(v);
        let closed = !self.is_boundary_vertex(v);
        (0..ring_faces.len()).filter(move |&j| {
            // On a boundary fan edge 0 is a boundary edge; every fan face j starts at edge j.
            (closed || j > 0) && {
                let f = ring_faces[j];
                let c = self.faces[f as usize].iter().position(|&x| x == v);
                c.is_some_and(|c| self.is_sharp(f, c))
            }
        })
    }
    /// One unit normal per face corner (`[f][c]` for vertex `faces()[f][c]`): one normal per
    /// sector of each vertex's fan (see [`SharpEdges`]). A vertex whose fan is one sector (no
    /// sharp edge, or a single one at an interior vertex) keeps its `vertex_normals` entry;
    /// the normal of a sector of a vertex cut into several is the angle-weighted average of
    /// the sector's face normals [Thürmer & Wüthrich 1998], so a flat sector gets its plane's
    /// normal, except at a corner, where it is the plane of the sector's two sharp edges when
    /// that plane faces all of the sector's faces (see `sector_normal`), and at a crease that
    /// turns back at an interior vertex, whose two sectors take its edges' plane where that
    /// fits them (see `hairpin_normals`).
    pub fn corner_normals(&self, vertex_normals: &[DVec3]) -> Vec<[DVec3; 3]> {
        let mut corners: Vec<[DVec3; 3]> = self
            .faces
            .iter()
            .map(|face| face.map(|v| vertex_normals[v as usize]))
            .collect();
        if self.sharp.is_empty() {
            return corners;
        }
        let mut cuts = Vec::new();
        for v in 0..self.vertex_count() as u32 {
            cuts.clear();
            cuts.extend(self.sharp_cuts(v));
            let closed = !self.is_boundary_vertex(v);
            if cuts.is_empty() || (closed && cuts.len() == 1) {
                continue;
            }
            let ring_faces = self.ring_faces(v);
            let n = ring_faces.len();
            // Sector starts: the cuts, and fan position 0 on a boundary fan.
            if !closed {
                cuts.insert(0, 0);
            }
            let sectors: Vec<(usize, usize)> = (0..cuts.len())
                .map(|s| {
                    let end = match cuts.get(s + 1) {
                        Some(&next) => next,
                        None if closed => cuts[0] + n,
                        None => n,
                    };
                    (cuts[s], end)
                })
                .collect();
            let mut sector_normals: Vec<DVec3> = sectors
                .iter()
                .map(|&(start, end)| {
                    let mut sum = DVec3::ZERO;
                    for f in (start..end).map(|j| ring_faces[j % n]) {
                        let face = self.faces[f as usize];
                        let c = face.iter().position(|&x| x == v).unwrap_or(0);
                        let p = face.map(|x| self.positions[x as usize]);
                        let angle =
                            normals::angle_between(p[(c + 1) % 3] - p[c], p[(c + 2) % 3] - p[c]);
                        sum += angle * self.face_normal(f);
                    }
                    self.sector_normal(v, sum, start, end, cuts.len())
                })
                .collect();
            if closed
                && let [a, b] = sectors[..]
                && let Some(hairpin) = self.hairpin_normals(v, a, b, &sector_normals)
            {
                sector_normals = hairpin.to_vec();
            }
            for (&(start, end), normal) in sectors.iter().zip(sector_normals) {
                for f in (start..end).map(|j| ring_faces[j % n]) {
                    let face = self.faces[f as usize];
                    let c = face.iter().position(|&x| x == v).unwrap_or(0);
                    corners[f as usize][c] = normal;
                }
            }
        }
        corners
    }

    /// The normals of the two sectors `a` and `b` (fan edges `start..end`) of a crease that
    /// turns back at interior vertex `v` (a *hairpin*: its two sharp edges `ê_a`, `ê_b` less
    /// than a right angle apart, [`HAIRPIN_COS`]), given their own normals `normals`: the
    /// normal of the edges' plane, `±ê_a × ê_b`, each oriented by its sector's own normal,
    /// when every face of each sector sees its one from the front by
    /// [`front_facing::FRONT_MARGIN`]; else `None` (the sectors keep their own normals).
    ///
    /// Two sectors with normals `n_a`, `n_b` share one crease line `n_a × n_b`, on which both
    /// sharp edges' tangents lie: a crease through `v`, its tangents opposite. Along a
    /// hairpin that line leaves both edges by more than half a right angle, and the narrow
    /// sector, whose faces span less than a right angle at `v`, has to turn through a half
    /// turn between them: its patches turn over their faces (hb folded on 343 of its 351 fold
    /// samples on `scenes/bunny.obj` at `--crease-angle 40` next to such vertices). With both
    /// normals normal to the edges' plane, the crease tangents are the edges themselves.
    fn hairpin_normals(
        &self,
        v: u32,
        a: (usize, usize),
        b: (usize, usize),
        normals: &[DVec3],
    ) -> Option<[DVec3; 2]> {
        /// Below this sine of the angle between the two sharp edges, their plane is left to
        /// rounding (as in `sector_normal`).
        const COLLINEAR: f64 = 0.05;
        let ring = self.one_ring(v);
        let ring_faces = self.ring_faces(v);
        let p = self.positions[v as usize];
        let unit_edge = |j: usize| (self.positions[ring[j % ring.len()] as usize] - p).normalize();
        let (ea, eb) = (unit_edge(a.0), unit_edge(b.0));
        if ea.dot(eb).is_nan() || ea.dot(eb) <= HAIRPIN_COS {
            return None;
        }
        let plane = ea.cross(eb);
        let sine = plane.length();
        if sine <= COLLINEAR {
            return None;
        }
        let plane = plane / sine;
        let oriented = |(start, end): (usize, usize), own: DVec3| {
            let n = if plane.dot(own) < 0.0 { -plane } else { plane };
            (start..end)
                .map(|j| self.face_normal(ring_faces[j % ring_faces.len()]))
                .all(|f| f.dot(n) >= front_facing::FRONT_MARGIN)
                .then_some(n)
        };
        let planes = [oriented(a, normals[0])?, oriented(b, normals[1])?];
        // The angle each sector's faces span at `v`, and the one its tangents turn through:
        // from its first edge to its last round its normal in the edges' plane, a half turn
        // along a crease line through `v`. The plane is taken where it fits the worse sector
        // better (a fin's tip, whose narrow sector has broad neighbours, may not).
        let span = |(start, end): (usize, usize)| -> f64 {
            (start..end)
                .map(|j| normals::angle_between(unit_edge(j), unit_edge(j + 1)))
                .sum()
        };
        let turn = |from: DVec3, to: DVec3, n: DVec3| {
            let angle = from.cross(to).dot(n).atan2(from.dot(to));
            if angle > 0.0 {
                angle
            } else {
                angle + 2.0 * std::f64::consts::PI
            }
        };
        let (span_a, span_b) = (span(a), span(b));
        let through = (span_a - std::f64::consts::PI)
            .abs()
            .max((span_b - std::f64::consts::PI).abs());
        let in_plane = (span_a - turn(ea, eb, planes[0]))
            .abs()
            .max((span_b - turn(eb, ea, planes[1])).abs());
        (in_plane < through).then_some(planes)
    }
    /// The normal of the sector of vertex `v` between fan edges `start` and `end` (modulo the
    /// ring on a closed fan), from the angle-weighted sum `average` of its face normals.
    ///
    /// At a corner (a sector bounded by two sharp edges `ê_a`, `ê_b` that do not belong to one
    /// crease through `v`) it is the normal of the edges' plane, `±ê_a × ê_b` oriented by
    /// `average`, when the edges are not (nearly) collinear and that plane sees every face of
    /// the sector from its front: then the crease line `n₀ × n₁` of two neighbouring sectors
    /// ([`crease_tangent`]) is their mesh edge itself, instead of swinging away from it when
    /// the sectors are nearly coplanar and turning a face's corner over. Everywhere else (and
    /// at a corner that fails either test) it is `average`, normalised — or, where a face of
    /// the sector sees that from behind or edge-on, the closest direction every face of the
    /// sector sees from the front ([`front_facing`], as for whole fans). Making the two sectors
    /// of a crease vertex orthogonal to the crease's mean direction was measured as well and
    /// turned more corners over on scans (the crease lines of a scan zig-zag), so it is not
    /// done.
    fn sector_normal(
        &self,
        v: u32,
        average: DVec3,
        start: usize,
        end: usize,
        cuts: usize,
    ) -> DVec3 {
        /// Below this sine of the angle between the two sharp edges, their plane is left to
        /// rounding.
        const COLLINEAR: f64 = 0.05;
        let ring = self.one_ring(v);
        let ring_faces = self.ring_faces(v);
        let closed = !self.is_boundary_vertex(v);
        // The average, or where a face of the sector sees it from behind or edge-on (a sector
        // of a fold or spike of a scan), the closest direction every face of the sector sees
        // from the front (as for whole fans, `front_facing`).
        let average = average.normalize_or_zero();
        let sector_faces: Vec<DVec3> = (start..end)
            .map(|j| self.face_normal(ring_faces[j % ring_faces.len()]))
            .collect();
        let average =
            match front_facing::front_facing_by(average, &sector_faces, front_facing::FRONT_MARGIN)
            {
                front_facing::FrontFacing::Moved { normal, .. } => normal,
                _ => average,
            };
        // On an open fan, edges 0 and `ring.len() − 1` are boundary edges.
        let between_sharp_edges = closed || (start > 0 && end < ring.len() - 1);
        if !between_sharp_edges || (closed && cuts == 2) {
            return average;
        }
        let p = self.positions[v as usize];
        let unit_edge = |j: usize| (self.positions[ring[j % ring.len()] as usize] - p).normalize();
        let plane = unit_edge(start).cross(unit_edge(end));
        let sine = plane.length();
        if sine.is_nan() || sine <= COLLINEAR {
            return average;
        }
        let n = plane / sine;
        let n = if n.dot(average) < 0.0 { -n } else { n };
        let front_facing = sector_faces.iter().all(|f| f.dot(n) > 0.0);
        if front_facing { n } else { average }
    }
    /// Bounding box of the vertices.
    pub fn bounds(&self) -> Aabb {
        Aabb::from_points(&self.positions)
    }

    /// The mesh with every position multiplied by `factor` (topology and file normals
    /// unchanged). With a power of two as `factor` the scaling is exact.
    pub fn scaled(&self, factor: f64) -> Mesh {
        Mesh {
            positions: self.positions.iter().map(|&p| p * factor).collect(),
            ..self.clone()
        }
    }
    /// The mesh moved by `−centre` and then scaled by `factor > 0` (a local frame of it):
    /// topology, validation and the directions of the file's normals are unchanged by a
    /// translation and a positive scale.
    pub fn framed(&self, centre: DVec3, factor: f64) -> Mesh {
        Mesh {
            positions: self
                .positions
                .iter()
                .map(|&p| (p - centre) * factor)
                .collect(),
            ..self.clone()
        }
    }

    /// The mesh as OBJ text: `header` as comment lines, then `v` and `f` records. Coordinates
    /// are written in Rust's shortest round-trip form, so parsing the text gives back the
    /// identical mesh.
    pub fn to_obj(&self, header: &str) -> String {
        obj::write(header, &self.positions, &self.faces)
    }
}
