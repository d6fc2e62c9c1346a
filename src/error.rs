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
    /// The angle-weighted face normals around a vertex cancel, so it has no normal: its ring
    /// is folded flat, or its faces are needles round a vertex far from the others.
    #[error(
        "vertex {vertex} has no defined normal: the normals of the faces around it cancel (its \
         faces fold flat onto each other, or are needles, as a vertex far from the others \
         makes); repair the mesh at that vertex, or use the flat scheme"
    )]
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
    /// With default parameters, the surface still folds over faces of the mesh after the fold
    /// rounds (a mesh with needle faces), or an approximating surface turns away from needle
    /// faces: a scheme builds its default surface with no fold or not at all.
    #[error(
        "scheme '{scheme}' with default parameters cannot build a surface without a fold: it \
         folds over {faces} faces ({samples} samples; among them face {face}, at vertex {vertex}) \
         and {after}{remedy}"
    )]
    FoldedSurface {
        /// The scheme.
        scheme: String,
        /// Faces the surface folds over.
        faces: usize,
        /// Fold samples of the surface (the metrics' `folds`).
        samples: usize,
        /// The face named, in the input's numbering.
        face: usize,
        /// A corner of that face where the surface folds.
        vertex: usize,
        /// Why no sharp edge settles it.
        after: String,
        /// What to do: `; that face is a needle, …` where the mesh, not a parameter, is the
        /// cause, else to repair the mesh at the vertex; and the scheme that cannot fold.
        remedy: String,
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
    #[error("scheme '{scheme}' fails at edge ({a}, {b}): {reason}{}", more_edges(.also))]
    DegenerateEdge {
        /// The scheme.
        scheme: String,
        /// The vertex of the edge at fault (or the edge's first vertex).
        a: usize,
        /// The other vertex of the edge.
        b: usize,
        /// Why.
        reason: String,
        /// The other edges where the construction fails as well, in mesh order.
        also: Vec<(usize, usize)>,
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
    /// A configuration key — of a scene file, a figure spec, a mode's section, the viewer's
    /// page, a command-line option — has a value it does not take.
    #[error("{}", .problem.message(.key))]
    Config {
        /// The key as the user wrote it, with its section (`zebra.stripes`), and the flag
        /// setting it where there is one (`render.sweep (--sweep)`).
        key: String,
        /// What is wrong with its value.
        problem: Problem,
    },
    /// A name is not one of a fixed set (a render mode, a curvature quantity, an EXR
    /// compression).
    #[error("unknown {what} '{name}' (known: {known})")]
    UnknownName {
        /// What the name names (`render mode`).
        what: &'static str,
        /// The name given.
        name: String,
        /// The known names, comma separated.
        known: String,
    },
    /// An error found in a named place (a file, an entry of a figure spec): the place, then
    /// the error.
    #[error("{place}: {error}")]
    In {
        /// Where (`scene.toml`, `modes[2] (zebra)`).
        place: String,
        /// What went wrong there.
        error: Box<Error>,
    },
    /// Anything else that is refused: a damaged record or part file, a failed encoding, an
    /// operation that cannot be done.
    #[error("{0}")]
    Invalid(String),
}

/// What is wrong with the value of a configuration key ([`Error::Config`]). Values are kept as
/// the text the message shows.
#[derive(Clone, Debug, PartialEq)]
pub enum Problem {
    /// The key is not one the section takes: `SECTION: unknown field `KEY`, expected one of
    /// …` (`section` is None for the top level).
    UnknownKey {
        /// The section it was found in.
        section: Option<String>,
        /// The keys the section takes, each quoted as `` `name` ``.
        known: Vec<String>,
    },
    /// The value has the wrong type: `KEY = VALUE is not EXPECTED`.
    WrongType {
        /// The value as written.
        value: String,
        /// What the key takes, with its article (`a number`).
        expected: String,
    },
    /// An array has the wrong length: `KEY = VALUE: invalid length N, expected M elements`.
    WrongLength {
        /// The value as written.
        value: String,
        /// Its length.
        len: usize,
        /// The length the key takes.
        expected: usize,
    },
    /// An element of an array has the wrong type: `KEY element VALUE is not EXPECTED`.
    WrongElement {
        /// The element as written.
        element: String,
        /// What the elements are (`a number`).
        expected: &'static str,
    },
    /// `KEY = VALUE must be a positive number`.
    NotPositive {
        /// The value.
        value: String,
    },
    /// `KEY = VALUE must be in RANGE` (`[1e-3, 1e0]`, `1..=360`).
    OutOfRange {
        /// The value.
        value: String,
        /// The range, as written in the message.
        range: String,
    },
    /// `KEY = VALUE must lie in [0, 1]`.
    NotFraction {
        /// The value.
        value: String,
    },
    /// `KEY = VALUE must be at least MIN`.
    BelowMinimum {
        /// The value.
        value: String,
        /// The smallest value taken.
        min: String,
    },
    /// `KEY = VALUE must be finite`.
    NotFinite {
        /// The value.
        value: String,
    },
    /// `KEY = VALUE must be non-zero`.
    Zero {
        /// The value.
        value: String,
    },
    /// `KEY = VALUE must be non-negative linear RGB`.
    NotColour {
        /// The value.
        value: String,
    },
    /// `KEY 'VALUE' is not one of A, B, C`.
    NotOneOf {
        /// The value.
        value: String,
        /// The values taken.
        known: Vec<String>,
    },
    /// `KEY = VALUE is neither A nor B`: the value is none of the forms the key takes.
    Neither {
        /// The value as the message shows it, with what precedes it (`= thick2`, `'up'`).
        value: String,
        /// The forms taken, as the message lists them (`thin, medium nor …`).
        forms: String,
    },
    /// `KEY and OTHER both set: give one`.
    Conflict {
        /// The other key.
        other: String,
    },
    /// `KEY and OTHER exclude each other`.
    Excludes {
        /// The other key.
        other: String,
    },
    /// `KEY[ = VALUE] needs NEEDED`: the key takes effect only with another.
    Needs {
        /// The value, when the message shows it.
        value: Option<String>,
        /// What it needs.
        needed: String,
    },
    /// `KEY VALUE must be REQUIREMENT`: a requirement of its own.
    Must {
        /// The value as the message shows it, with what precedes it (`= 3`, `[1.0, -1.0]`),
        /// or empty.
        value: String,
        /// What it must be (`be non-negative`, `not be parallel to highlight.plane_normal`).
        requirement: String,
    },
    /// `KEY: REASON`: the value was refused by a check that gives its own reason.
    Refused {
        /// Why.
        reason: String,
    },
    /// `KEY TEXT`: a sentence of its own about the key.
    Other {
        /// What follows the key.
        text: String,
    },
    /// `MESSAGE`: a sentence of its own that names the key in its own words, not first
    /// (`the view cannot set the scene key 'render.output'`).
    Stated {
        /// The whole message.
        message: String,
    },
}

impl Problem {
    /// The message of `key` having this problem, as the user sees it.
    pub fn message(&self, key: &str) -> String {
        match self {
            Problem::UnknownKey { section, known } => {
                let place = section
                    .as_ref()
                    .map(|s| format!("{s}: "))
                    .unwrap_or_default();
                if known.is_empty() {
                    format!("{place}unknown field `{key}`: the section takes no keys")
                } else {
                    format!(
                        "{place}unknown field `{key}`, expected one of {}",
                        known.join(", ")
                    )
                }
            }
            Problem::WrongType { value, expected } => format!("{key} = {value} is not {expected}"),
            Problem::WrongLength {
                value,
                len,
                expected,
            } => format!("{key} = {value}: invalid length {len}, expected {expected} elements"),
            Problem::WrongElement { element, expected } => {
                format!("{key} element {element} is not {expected}")
            }
            Problem::NotPositive { value } => format!("{key} = {value} must be a positive number"),
            Problem::OutOfRange { value, range } => format!("{key} = {value} must be in {range}"),
            Problem::NotFraction { value } => format!("{key} = {value} must lie in [0, 1]"),
            Problem::BelowMinimum { value, min } => {
                format!("{key} = {value} must be at least {min}")
            }
            Problem::NotFinite { value } => format!("{key} = {value} must be finite"),
            Problem::Zero { value } => format!("{key} = {value} must be non-zero"),
            Problem::NotColour { value } => {
                format!("{key} = {value} must be non-negative linear RGB")
            }
            Problem::NotOneOf { value, known } => {
                format!("{key} '{value}' is not one of {}", known.join(", "))
            }
            Problem::Neither { value, forms } => format!("{key} {value} is neither {forms}"),
            Problem::Conflict { other } => format!("{key} and {other} both set: give one"),
            Problem::Excludes { other } => format!("{key} and {other} exclude each other"),
            Problem::Needs { value, needed } => match value {
                Some(value) => format!("{key} = {value} needs {needed}"),
                None => format!("{key} needs {needed}"),
            },
            Problem::Must { value, requirement } => {
                if value.is_empty() {
                    format!("{key} must {requirement}")
                } else {
                    format!("{key} {value} must {requirement}")
                }
            }
            Problem::Refused { reason } => format!("{key}: {reason}"),
            Problem::Other { text } => format!("{key} {text}"),
            Problem::Stated { message } => message.clone(),
        }
    }
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
            Error::FoldedSurface {
                scheme,
                faces,
                samples,
                face,
                vertex,
                after,
                remedy,
            } => Error::FoldedSurface {
                scheme,
                faces,
                samples,
                face,
                vertex: input(vertex),
                after,
                remedy,
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
                also,
            } => Error::DegenerateEdge {
                scheme,
                a: input(a),
                b: input(b),
                reason,
                also: also
                    .into_iter()
                    .map(|(a, b)| (input(a), input(b)))
                    .collect(),
            },
            other => other,
        }
    }
}

/// " (and N more edges, the next (a, b))" of [`Error::DegenerateEdge`], empty without more.
fn more_edges(also: &[(usize, usize)]) -> String {
    match also.first() {
        Some((a, b)) => format!(" (and {} more edges, the next ({a}, {b}))", also.len()),
        None => String::new(),
    }
}

/// The results of a construction's elements in mesh order, or its first error; where that is
/// an [`Error::DegenerateEdge`], with the edges of every later one in `also`, so that a
/// caller can treat them all at once.
pub(crate) fn collect_in_order<T>(results: Vec<Result<T>>) -> Result<Vec<T>> {
    let mut values = Vec::with_capacity(results.len());
    let mut first: Option<Error> = None;
    for result in results {
        match (result, &mut first) {
            (Ok(value), None) => values.push(value),
            (Ok(_), Some(_)) => {}
            (Err(error), None) => first = Some(error),
            (Err(Error::DegenerateEdge { a, b, .. }), Some(Error::DegenerateEdge { also, .. })) => {
                also.push((a, b))
            }
            (Err(_), Some(_)) => {}
        }
    }
    match first {
        Some(error) => Err(error),
        None => Ok(values),
    }
}

/// The names of `choices` (name, help), in order: the `NAMES` of a type whose values have
/// names (a theme, an EXR compression) from its `CHOICES`.
pub(crate) const fn names<const N: usize>(
    choices: [(&'static str, &'static str); N],
) -> [&'static str; N] {
    let mut out = [""; N];
    let mut k = 0;
    while k < N {
        out[k] = choices[k].0;
        k += 1;
    }
    out
}

/// The library's result type.
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// The error of `key` having `problem` ([`Error::Config`]).
    pub fn config(key: impl Into<String>, problem: Problem) -> Self {
        Error::Config {
            key: key.into(),
            problem,
        }
    }

    /// The error of `name` not being one of the `known` names of `what` ([`Error::UnknownName`]).
    pub fn unknown_name(what: &'static str, name: &str, known: &[&str]) -> Self {
        Error::UnknownName {
            what,
            name: name.to_string(),
            known: known.join(", "),
        }
    }

    /// This error found in `place` ([`Error::In`]).
    pub fn within(self, place: impl Into<String>) -> Self {
        Error::In {
            place: place.into(),
            error: Box::new(self),
        }
    }

    /// Wraps an I/O error with the file it concerns.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            source,
        }
    }
}

/// What the tests of the validators check of a configuration error.
#[cfg(test)]
pub(crate) mod test_support {
    use super::{Error, Problem};

    /// Asserts that `err` is [`Error::Config`] of `key` with a problem that `is_kind`
    /// accepts, and that the user reads `text`.
    #[track_caller]
    pub(crate) fn assert_config_error(
        err: &Error,
        key: &str,
        is_kind: fn(&Problem) -> bool,
        text: impl AsRef<str>,
    ) {
        let Error::Config {
            key: found,
            problem,
        } = err
        else {
            panic!("not a configuration error: {err:?}");
        };
        assert_eq!(found, key, "{err:?}");
        assert!(is_kind(problem), "{err:?}");
        assert_eq!(err.to_string(), text.as_ref());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The message of `key` having `problem`, through [`Error::Config`]'s Display.
    fn shown(key: &str, problem: Problem) -> String {
        Error::config(key, problem).to_string()
    }

    /// The wording of every problem, as the user reads it.
    #[test]
    fn problem_wording() {
        let s = String::from;
        assert_eq!(
            shown(
                "strpes",
                Problem::UnknownKey {
                    section: Some(s("zebra")),
                    known: vec![s("`stripes`"), s("`duty`")],
                }
            ),
            "zebra: unknown field `strpes`, expected one of `stripes`, `duty`"
        );
        assert_eq!(
            shown(
                "x",
                Problem::UnknownKey {
                    section: None,
                    known: vec![],
                }
            ),
            "unknown field `x`: the section takes no keys"
        );
        assert_eq!(
            shown(
                "zebra.duty",
                Problem::WrongType {
                    value: s("\"a\""),
                    expected: s("a number"),
                }
            ),
            "zebra.duty = \"a\" is not a number"
        );
        assert_eq!(
            shown(
                "camera.eye",
                Problem::WrongLength {
                    value: s("[1, 2]"),
                    len: 2,
                    expected: 3,
                }
            ),
            "camera.eye = [1, 2]: invalid length 2, expected 3 elements"
        );
        assert_eq!(
            shown(
                "camera.eye",
                Problem::WrongElement {
                    element: s("\"a\""),
                    expected: "a number",
                }
            ),
            "camera.eye element \"a\" is not a number"
        );
        assert_eq!(
            shown("--spp", Problem::NotPositive { value: s("0") }),
            "--spp = 0 must be a positive number"
        );
        assert_eq!(
            shown(
                "zebra.stripes",
                Problem::OutOfRange {
                    value: s("0"),
                    range: s("1..=360"),
                }
            ),
            "zebra.stripes = 0 must be in 1..=360"
        );
        assert_eq!(
            shown("zebra.duty", Problem::NotFraction { value: s("2") }),
            "zebra.duty = 2 must lie in [0, 1]"
        );
        assert_eq!(
            shown(
                "bvh.max_leaves",
                Problem::BelowMinimum {
                    value: s("0"),
                    min: s("1"),
                }
            ),
            "bvh.max_leaves = 0 must be at least 1"
        );
        assert_eq!(
            shown("render.line_width", Problem::NotFinite { value: s("inf") }),
            "render.line_width = inf must be finite"
        );
        assert_eq!(
            shown(
                "highlight.plane_normal",
                Problem::Zero {
                    value: s("[0, 0, 0]")
                }
            ),
            "highlight.plane_normal = [0, 0, 0] must be non-zero"
        );
        assert_eq!(
            shown(
                "render.background",
                Problem::NotColour {
                    value: s("[-1, 0, 0]")
                }
            ),
            "render.background = [-1, 0, 0] must be non-negative linear RGB"
        );
        assert_eq!(
            shown(
                "render.overlay",
                Problem::NotOneOf {
                    value: s("thick"),
                    known: vec![s("none"), s("edges")],
                }
            ),
            "render.overlay 'thick' is not one of none, edges"
        );
        assert_eq!(
            shown(
                "render.line_width",
                Problem::Neither {
                    value: s("= thick2"),
                    forms: s("thin, medium nor a number"),
                }
            ),
            "render.line_width = thick2 is neither thin, medium nor a number"
        );
        assert_eq!(
            shown(
                "camera.fov",
                Problem::Conflict {
                    other: s("camera.ortho")
                }
            ),
            "camera.fov and camera.ortho both set: give one"
        );
        assert_eq!(
            shown(
                "--turntable",
                Problem::Excludes {
                    other: s("--sweep")
                }
            ),
            "--turntable and --sweep exclude each other"
        );
        assert_eq!(
            shown(
                "render.surface",
                Problem::Needs {
                    value: Some(s("false")),
                    needed: s("render.curves"),
                }
            ),
            "render.surface = false needs render.curves"
        );
        assert_eq!(
            shown(
                "--turntable-axis",
                Problem::Needs {
                    value: None,
                    needed: s("--turntable"),
                }
            ),
            "--turntable-axis needs --turntable"
        );
        assert_eq!(
            shown(
                "orbit angle",
                Problem::Must {
                    value: s("NaN"),
                    requirement: s("be finite"),
                }
            ),
            "orbit angle NaN must be finite"
        );
        assert_eq!(
            shown(
                "camera eye, target and up",
                Problem::Must {
                    value: String::new(),
                    requirement: s("be finite"),
                }
            ),
            "camera eye, target and up must be finite"
        );
        assert_eq!(
            shown(
                "crease_angle",
                Problem::Refused {
                    reason: s("too large")
                }
            ),
            "crease_angle: too large"
        );
        assert_eq!(
            shown(
                "--bind",
                Problem::Other {
                    text: s("0.0.0.0: no")
                }
            ),
            "--bind 0.0.0.0: no"
        );
        assert_eq!(
            shown(
                "render.output",
                Problem::Stated {
                    message: s("the view cannot set the scene key 'render.output'"),
                }
            ),
            "the view cannot set the scene key 'render.output'"
        );
    }

    /// A construction's results in mesh order: the first error wins whatever order a
    /// parallel run finished in, and the later failing edges ride along in its message.
    #[test]
    fn the_first_failing_edge_is_reported_with_the_others() {
        let edge = |a: usize, b: usize| Error::DegenerateEdge {
            scheme: "nielson".into(),
            a,
            b,
            reason: "folds".into(),
            also: Vec::new(),
        };
        let results = vec![
            Ok(1),
            Err(edge(3, 4)),
            Ok(2),
            Err(edge(7, 8)),
            Err(edge(9, 2)),
        ];
        match collect_in_order(results) {
            Err(Error::DegenerateEdge { a, b, also, .. }) => {
                assert_eq!((a, b, also.clone()), (3, 4, vec![(7, 8), (9, 2)]));
                let text = edge(3, 4).to_string();
                assert_eq!(text, "scheme 'nielson' fails at edge (3, 4): folds");
                let with = Error::DegenerateEdge {
                    scheme: "nielson".into(),
                    a,
                    b,
                    reason: "folds".into(),
                    also,
                }
                .to_string();
                assert!(
                    with.ends_with("folds (and 2 more edges, the next (7, 8))"),
                    "{with}"
                );
            }
            other => panic!("{other:?}"),
        }
        assert_eq!(collect_in_order(vec![Ok(1), Ok(2)]).unwrap(), vec![1, 2]);
        let renamed = edge(3, 4).in_input_numbering(&|v| v + 10);
        assert!(renamed.to_string().contains("(13, 14)"));
    }
}
