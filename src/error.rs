//! The one error type of the library. Every variant names the element at fault (vertex, face,
//! edge, scheme, parameter) so that the CLI can print one clear line.

use std::path::PathBuf;

/// Everything that can go wrong between reading a mesh and writing a result.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// What the operating system said.
        source: std::io::Error,
    },
    /// The OBJ parser rejected the file.
    #[error("{path}: malformed OBJ: {message}")]
    MalformedObj {
        /// The file.
        path: PathBuf,
        /// What the parser said.
        message: String,
    },
    /// A mesh file (PLY, OFF, STL) is malformed: bad header, truncated data, unreadable
    /// number, an element the format requires is missing.
    #[error("{path}: malformed {format}: {message}")]
    MalformedMesh {
        /// The file.
        path: PathBuf,
        /// The format it was read as (`PLY`, `OFF`, `STL`).
        format: &'static str,
        /// What is wrong, naming the element, line or byte offset at fault.
        message: String,
    },
    /// The file's extension names no supported mesh format.
    #[error("{path}: unknown mesh format {extension}; supported extensions: {supported}")]
    UnknownMeshFormat {
        /// The file.
        path: PathBuf,
        /// The extension found, quoted, or `(no extension)`.
        extension: String,
        /// The supported extensions, comma separated.
        supported: String,
    },
    /// A face has fewer than three corners.
    #[error("face {face} has {corners} corners; a face needs at least 3")]
    NotATriangle {
        /// Face index in the file.
        face: usize,
        /// Number of corners found.
        corners: usize,
    },
    /// A polygon with more than three corners is not planar, so how it is split into
    /// triangles would change the surface.
    #[error(
        "face {face} ({corners} corners) is not planar: a corner lies {deviation:.3e} of its \
         diameter off its plane, above the tolerance {tolerance:.0e}; split it into triangles \
         in the modeller"
    )]
    NonPlanarFace {
        /// Face index in the file.
        face: usize,
        /// Number of corners.
        corners: usize,
        /// The largest distance of a corner from the face's plane, relative to its diameter.
        deviation: f64,
        /// The relative tolerance (see `mesh::PLANARITY_TOLERANCE`).
        tolerance: f64,
    },
    /// A polygon with more than three corners is not strictly convex.
    #[error(
        "face {face} ({corners} corners) is not convex: it turns the wrong way or not at all at \
         corner {corner} (vertex {vertex}); split it into triangles in the modeller"
    )]
    NonConvexFace {
        /// Face index in the file.
        face: usize,
        /// Number of corners.
        corners: usize,
        /// The corner (0-based position in the face) at fault.
        corner: usize,
        /// Its vertex, as numbered by the input.
        vertex: usize,
    },
    /// A face refers to a vertex that does not exist.
    #[error("face {face} refers to vertex {vertex}, but the mesh has only {count} vertices")]
    VertexIndexOutOfRange {
        /// Face index.
        face: usize,
        /// The bad vertex index.
        vertex: usize,
        /// Number of vertices.
        count: usize,
    },
    /// Loading would have to repair the mesh, and `--strict` (or the `strict` key) refuses
    /// every repair.
    #[error("{element}: {problem}; --strict refuses the repair that loading would make: {repair}")]
    RepairRefused {
        /// The first element needing the repair, in the input's numbering (`face 3`).
        element: String,
        /// What is wrong with it.
        problem: String,
        /// The repair, as its warning would say it.
        repair: String,
    },
    /// The mesh has no faces.
    #[error("the mesh is empty (no faces)")]
    EmptyMesh,
    /// A vertex coordinate or normal is NaN or infinite.
    #[error("vertex {vertex} has a non-finite coordinate")]
    NonFiniteVertex {
        /// Vertex index as numbered by the input (for an OBJ file: 0-based, in file order).
        vertex: usize,
    },
    /// A face has (numerically) zero area or a repeated corner.
    #[error("face {face} is degenerate (zero area or repeated corner)")]
    DegenerateFace {
        /// Face index.
        face: usize,
    },
    /// Welding vertices closer than the weld tolerance merged two corners of a face.
    #[error(
        "welding collapses face {face}: its corners {a} and {b} are {distance:.3e} apart, within \
         the weld tolerance {tolerance:.3e}; use a smaller --weld-tolerance"
    )]
    WeldCollapsesFace {
        /// Face index.
        face: usize,
        /// One of the merged corners (vertex as numbered by the input).
        a: usize,
        /// The other merged corner.
        b: usize,
        /// Distance between the two corners.
        distance: f64,
        /// The weld tolerance as a distance (relative tolerance × bounding-box diagonal).
        tolerance: f64,
    },
    /// The coordinates are too large or span too small a box for f64 geometry.
    #[error(
        "coordinates span {span:.1e} (bounding-box diagonal), largest magnitude {largest:.1e} at \
         vertex {vertex}; smoothlab supports meshes spanning at least {min_span:.0e} with \
         coordinates up to {max_magnitude:.0e} in magnitude: rescale the mesh"
    )]
    CoordinateRange {
        /// Bounding-box diagonal of the used vertices.
        span: f64,
        /// Largest coordinate magnitude.
        largest: f64,
        /// The vertex with the largest coordinate magnitude.
        vertex: usize,
        /// Smallest supported span.
        min_span: f64,
        /// Largest supported coordinate magnitude.
        max_magnitude: f64,
    },
    /// Two faces use the same three vertices.
    #[error("face {face} repeats face {first} (same three vertices)")]
    DuplicateFace {
        /// The later face.
        face: usize,
        /// The earlier face it repeats.
        first: usize,
    },
    /// More than two faces share an edge.
    #[error("edge ({a}, {b}) is non-manifold: shared by {faces} faces")]
    NonManifoldEdge {
        /// First vertex of the edge.
        a: usize,
        /// Second vertex of the edge.
        b: usize,
        /// How many faces share it.
        faces: usize,
    },
    /// The faces around a vertex do not form a single fan (a "bow-tie").
    #[error("vertex {vertex} is non-manifold: its faces form {fans} separate fans")]
    NonManifoldVertex {
        /// Vertex index.
        vertex: usize,
        /// Number of fans found around it.
        fans: usize,
    },
    /// A scheme that needs a closed mesh was given one with a boundary.
    #[error("scheme '{scheme}' needs a closed mesh, but edge ({a}, {b}) is a boundary edge")]
    OpenMesh {
        /// The scheme.
        scheme: String,
        /// First vertex of a boundary edge.
        a: usize,
        /// Second vertex of a boundary edge.
        b: usize,
    },
    /// A scheme that cannot keep sharp edges sharp was given a mesh with some.
    #[error(
        "scheme '{scheme}' cannot build sharp edges ({reason}), but the mesh has {count} \
         (first: edge ({a}, {b})); build it without --crease-angle, or with another scheme"
    )]
    SharpEdgesUnsupported {
        /// The scheme.
        scheme: String,
        /// Why the scheme cannot take them.
        reason: String,
        /// Number of sharp edges.
        count: usize,
        /// First vertex of the first sharp edge.
        a: usize,
        /// Second vertex of the first sharp edge.
        b: usize,
    },
    /// The OBJ has no usable per-vertex normals but they were asked for.
    #[error("normals=obj asked for, but {reason}")]
    MissingNormals {
        /// Why the file's normals cannot be used.
        reason: String,
    },
    /// The angle-weighted face normals around a vertex cancel, so it has no normal.
    #[error("vertex {vertex} has no defined normal: the normals of the faces around it cancel")]
    UndefinedNormal {
        /// Vertex index.
        vertex: usize,
    },
    /// The faces around a vertex fold over themselves: no direction sees them all from the
    /// front, so every surface with a tangent plane there folds over one of them.
    #[error(
        "scheme '{scheme}' cannot build a surface without a fold at vertex {vertex}: the faces \
         around it fold over themselves (no normal sees them all from their front side); \
         repair the mesh at that vertex, or use the pn or flat scheme"
    )]
    FoldedVertex {
        /// The scheme.
        scheme: String,
        /// The vertex (the first such one).
        vertex: usize,
    },
    /// The scheme name is not registered.
    #[error("unknown scheme '{name}' (known: {known})")]
    UnknownScheme {
        /// The name given.
        name: String,
        /// The registered names, comma separated.
        known: String,
    },
    /// A parameter name is not understood by the scheme.
    #[error("scheme '{scheme}' has no parameter '{name}' (known: {known})")]
    UnknownParam {
        /// The scheme.
        scheme: String,
        /// The parameter name given.
        name: String,
        /// The parameters it knows, comma separated.
        known: String,
    },
    /// A parameter value is malformed or out of range.
    #[error("bad value for parameter '{name}': {reason}")]
    BadParam {
        /// The parameter name.
        name: String,
        /// Why the value is rejected.
        reason: String,
    },
    /// Data for a Hermite curve violates its constraints (coincident consecutive points, zero
    /// tangent, mismatched counts).
    #[error("Hermite curve data, point {point}: {reason}")]
    HermiteData {
        /// Index of the point (or tangent) at fault.
        point: usize,
        /// What is wrong with it.
        reason: String,
    },
    /// A scheme's construction has no valid result at a mesh edge (e.g. a vertex normal along
    /// the edge leaves no tangent direction for it).
    #[error("scheme '{scheme}' fails at edge ({a}, {b}): {reason}")]
    DegenerateEdge {
        /// The scheme.
        scheme: String,
        /// The vertex of the edge at fault (or the edge's first vertex).
        a: usize,
        /// The other vertex of the edge.
        b: usize,
        /// Why.
        reason: String,
    },
    /// A scheme built a surface that cannot be used: a control point is NaN or infinite, or
    /// the surface reaches absurdly far beyond the mesh (typically an extreme parameter).
    #[error("scheme '{scheme}' {params} built an unusable surface: {reason}")]
    UnusableSurface {
        /// The scheme.
        scheme: String,
        /// The parameters the user set, as `with a=1, b=2`, or `with default parameters`.
        params: String,
        /// What is wrong, naming the patch and its face.
        reason: String,
    },
    /// A result (metric, exported value) came out NaN or infinite.
    #[error("{what} is not finite ({value})")]
    NonFiniteResult {
        /// The figure or value, e.g. `metric g1_mean_rad of scheme 'hb'`.
        what: String,
        /// Its value.
        value: f64,
    },
    /// A size or resource estimate exceeds its limit.
    #[error("{what} needs about {estimate}, above the limit of {limit}; {remedy}")]
    TooLarge {
        /// What would be built (e.g. `the BVH of scheme 'hb'`).
        what: String,
        /// The estimate, with its unit.
        estimate: String,
        /// The limit, with its unit and where it comes from.
        limit: String,
        /// How to get below the limit or raise it.
        remedy: String,
    },
    /// A scene file or command-line option is invalid.
    #[error("{0}")]
    Invalid(String),
}

impl Error {
    /// The error with the mesh vertices it names (a scheme's errors, raised on the loaded mesh)
    /// renamed by `input`, from the loaded mesh's numbering to the file's
    /// ([`crate::mesh::Mesh::input_vertex`]), so that the message names the element the user
    /// wrote. Errors naming no mesh vertex are unchanged.
    pub fn in_input_numbering(self, input: &dyn Fn(usize) -> usize) -> Error {
        match self {
            Error::FoldedVertex { scheme, vertex } => Error::FoldedVertex {
                scheme,
                vertex: input(vertex),
            },
            Error::UndefinedNormal { vertex } => Error::UndefinedNormal {
                vertex: input(vertex),
            },
            Error::OpenMesh { scheme, a, b } => Error::OpenMesh {
                scheme,
                a: input(a),
                b: input(b),
            },
            Error::SharpEdgesUnsupported {
                scheme,
                reason,
                count,
                a,
                b,
            } => Error::SharpEdgesUnsupported {
                scheme,
                reason,
                count,
                a: input(a),
                b: input(b),
            },
            Error::DegenerateEdge {
                scheme,
                a,
                b,
                reason,
            } => Error::DegenerateEdge {
                scheme,
                a: input(a),
                b: input(b),
                reason,
            },
            other => other,
        }
    }
}

/// The library's result type.
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// Wraps an I/O error with the file it concerns.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            source,
        }
    }
}
