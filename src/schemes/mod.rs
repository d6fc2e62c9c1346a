//! The scheme registry: every surface construction is one module here and one entry in
//! [`SCHEMES`]. `build` checks the parameter names, fills in defaults and refuses meshes a
//! scheme cannot take (by name), so scheme code only sees valid input.

pub(crate) mod boundary_blend;
pub(crate) mod flat;
mod fold_corners;
pub(crate) mod gk;
pub(crate) mod hb;
pub(crate) mod loop94;
pub(crate) mod piper;
pub(crate) mod pn;
mod spikes;

pub(crate) mod vertex_rings;

use crate::error::{Error, Result};
use crate::mesh::front_facing::{FRONT_MARGIN, front_facing_normals};
use crate::mesh::{Mesh, NormalSource};
use crate::surface::{LocalFrame, Patch, Surface};

/// One parameter a scheme understands.
#[derive(Clone, Copy, Debug)]
pub struct ParamSpec {
    /// Name used in `--param name=value` and `[scheme.params]`.
    pub name: &'static str,
    /// Default value, as text.
    pub default: &'static str,
    /// One line of help.
    pub help: &'static str,
}

/// The `normals=estimate|obj` parameter shared by the normal-based schemes (read with
/// [`Params::normal_source`]).
pub const NORMALS_PARAM: ParamSpec = ParamSpec {
    name: "normals",
    default: "estimate",
    help: "vertex normals: estimate (angle-weighted) or obj (the file's vn)",
};

/// A registered scheme.
#[derive(Clone, Copy, Debug)]
pub struct SchemeSpec {
    /// Name used on the command line, in scenes and in results.
    pub name: &'static str,
    /// One line describing it, with its paper.
    pub summary: &'static str,
    /// Parameters it accepts.
    pub params: &'static [ParamSpec],
    /// True if it refuses meshes with boundary edges.
    pub needs_closed_mesh: bool,
    /// Peak memory of the construction per mesh face, in bytes: measured on the 81,920-face
    /// unit icosphere (valences 5 and 6; gk at k = 4), rounded up. [`build`] refuses a mesh
    /// whose estimate exceeds the memory limit before allocating ([`crate::budget`]).
    pub bytes_per_face: f64,
    /// Whether it keeps the mesh's sharp edges ([`crate::mesh::SharpEdges`]) sharp: G0
    /// across them, its own continuity elsewhere. [`build`] refuses a mesh with sharp edges
    /// for a scheme that cannot, with the reason.
    pub sharp_edges: SharpEdgeSupport,
    /// The construction.
    pub build: fn(&Mesh, &Params) -> Result<Surface>,
}

/// What a scheme does with sharp edges.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SharpEdgeSupport {
    /// G0 across sharp edges (both sides share one boundary curve), its continuity elsewhere.
    Builds,
    /// Refuses a mesh with sharp edges, for the reason given.
    Refuses(&'static str),
}

/// Every scheme, in the order the gallery and tables show them.
pub const SCHEMES: &[SchemeSpec] = &[
    flat::SPEC,
    pn::SPEC,
    hb::SPEC,
    loop94::SPEC,
    piper::SPEC,
    boundary_blend::nielson::SPEC,
    boundary_blend::fang_mann::SPEC,
    gk::SPEC,
];

/// Looks a scheme up by name.
pub fn find(name: &str) -> Result<&'static SchemeSpec> {
    SCHEMES
        .iter()
        .find(|s| s.name == name)
        .ok_or_else(|| Error::UnknownScheme {
            name: name.to_string(),
            known: names().join(", "),
        })
}

/// Registered scheme names.
pub fn names() -> Vec<&'static str> {
    SCHEMES.iter().map(|s| s.name).collect()
}

/// Builds `scheme` on `mesh` with the user's `name=value` pairs (unknown names are an error,
/// missing ones take their defaults): [`build_in_frame`], the surface then mapped into the
/// user's coordinates (for exports and the renderer, which take those).
pub fn build(scheme: &str, mesh: &Mesh, user: &[(String, String)]) -> Result<Surface> {
    let (surface, frame) = build_in_frame(scheme, mesh, user)?;
    Ok(surface.into_mapped(|q| frame.to_user(q)))
}

/// Builds `scheme` on `mesh` mapped into its [`LocalFrame`] (centred, power-of-two scale),
/// and returns the surface in that frame with the frame: no scheme needs to know where the
/// mesh lies, and the surface keeps full precision however far from the origin it is.
pub fn build_in_frame(
    scheme: &str,
    mesh: &Mesh,
    user: &[(String, String)],
) -> Result<(Surface, LocalFrame)> {
    build_in_frame_numbered(scheme, mesh, user)
        .map_err(|error| error.in_input_numbering(&|v| mesh.input_vertex(v as u32)))
}

/// [`build_in_frame`] with errors naming vertices in the loaded mesh's numbering.
fn build_in_frame_numbered(
    scheme: &str,
    mesh: &Mesh,
    user: &[(String, String)],
) -> Result<(Surface, LocalFrame)> {
    let spec = find(scheme)?;
    let params = Params::resolve(spec, user)?;
    if spec.needs_closed_mesh
        && let Some((a, b)) = mesh.first_boundary_edge()
    {
        return Err(Error::OpenMesh {
            scheme: spec.name.to_string(),
            a: a as usize,
            b: b as usize,
        });
    }
    if let (SharpEdgeSupport::Refuses(reason), Some((a, b))) =
        (spec.sharp_edges, mesh.sharp_edges().first())
    {
        return Err(Error::SharpEdgesUnsupported {
            scheme: spec.name.to_string(),
            reason: reason.to_string(),
            count: mesh.sharp_edges().count(),
            a: a as usize,
            b: b as usize,
        });
    }
    crate::budget::check_memory(
        &format!(
            "building scheme '{}' on {} faces",
            spec.name,
            mesh.face_count()
        ),
        spec.bytes_per_face * mesh.face_count() as f64,
        "use a mesh with fewer faces",
    )?;
    let _building = crate::progress::spinner(format!(
        "building {} on {} faces",
        spec.name,
        mesh.face_count()
    ));
    let frame = LocalFrame::of_points(mesh.positions());
    let local = mesh.framed(frame.centre, frame.scale);
    let surface = build_sharpening_spikes(spec, &local, &params, user)?;
    check_surface(&surface, &local, user)?;
    Ok((surface, frame))
}

/// Rounds of [`spikes::spike_edges`]: each rebuild can fold at a spike the last one did not.
const SPIKE_ROUNDS: usize = 4;

/// Builds `spec` on `mesh`; for a scheme that keeps sharp edges, where the surface folds at a
/// spike of the mesh, or the scheme refuses a vertex whose faces fold over themselves
/// ([`spikes`]), the spike's sharpest edges are made sharp and the surface is rebuilt, with
/// one warning counting them and naming the sharpest (in the file's numbering). A round of
/// sharp edges is kept only if the surface then folds less. Where it still folds, or the
/// scheme still refuses a folded ring or an edge, the edges of the faces that fold (then
/// every edge at their corners) and every edge at the refused rings and edges become sharp,
/// round by round, until nothing folds ([`fold_corners`], one more warning). A surface that
/// still folds is refused: the scheme's own refusal of a folded ring stands, or else
/// [`Error::FoldedSurface`] names where it folds (`user`: the parameters the user set).
fn build_sharpening_spikes(
    spec: &SchemeSpec,
    mesh: &Mesh,
    params: &Params,
    user: &[(String, String)],
) -> Result<Surface> {
    if spec.sharp_edges != SharpEdgeSupport::Builds {
        let mut surface = (spec.build)(mesh, params)?;
        let (faces, samples) = fold_corners::folding_faces(mesh, &surface);
        if let Some(&first) = faces.first() {
            // Over needles the cause is the mesh (a stray vertex), not the approximation.
            let site = fold_site(mesh, faces, samples);
            if user.is_empty() && face_aspect(mesh, site.face) > NEEDLE_ASPECT {
                return Err(fold_refusal(
                    spec.name,
                    mesh,
                    &site,
                    "it has no sharp edges to make there",
                ));
            }
            surface.warnings.push(format!(
                "{}: the surface turns more than 90° away from the normals of {} faces \
                 ({samples} samples; first: face {}), where it does not follow the mesh closely \
                 (an approximating surface over thin parts or small steep faces); it has no \
                 sharp edges to make there, and the metrics count the samples in `folds`",
                spec.name,
                site.faces,
                mesh.input_face(first)
            ));
        }
        return Ok(surface);
    }
    // Every build flattens the faces whose corners are all fully sharp where they fold.
    let build_on = |mesh: &Mesh| {
        (spec.build)(mesh, params).map(|mut surface| {
            fold_corners::flatten_sharp_faces(mesh, &mut surface);
            surface
        })
    };
    let mut sharpened = mesh.clone();
    let mut added: Vec<(u32, u32)> = Vec::new();
    let mut built = build_on(mesh);
    // A refusal of a folded ring is given up only for a surface that folds nowhere.
    let refusal = match &built {
        Err(Error::FoldedVertex { scheme, vertex }) => Some(Error::FoldedVertex {
            scheme: scheme.clone(),
            vertex: *vertex,
        }),
        _ => None,
    };
    // Fold samples of `built` when it is a surface, once counted.
    let mut folds = None;
    for _ in 0..SPIKE_ROUNDS {
        let edges = match &built {
            Ok(surface) => spikes::spike_edges(&sharpened, surface),
            Err(Error::FoldedVertex { .. }) => spikes::folded_ring_edges(&sharpened),
            Err(_) => Vec::new(),
        };
        if edges.is_empty() {
            break;
        }
        let candidate_mesh = sharpened.with_spike_edges(&edges);
        let candidate = build_on(&candidate_mesh);
        // Sharp edges are kept only where they leave fewer folds: on a mesh that is messy
        // around its spikes too, the sectors can fold more than the smooth surface did.
        if let Ok(current) = &built {
            let Ok(new) = &candidate else { break };
            let before = *folds.get_or_insert_with(|| spikes::fold_samples(&sharpened, current));
            let after = spikes::fold_samples(&candidate_mesh, new);
            if after >= before {
                break;
            }
            folds = Some(after);
        }
        sharpened = candidate_mesh;
        built = candidate;
        added.extend(edges);
    }
    let rounds = fold_corners::fold_rounds(sharpened.clone(), built, build_on);
    let rounds = fold_corners::prune_rounds(&sharpened, rounds, build_on);
    if let Some(refusal) = refusal
        && rounds.samples > 0
    {
        return Err(refusal);
    }
    let mut surface = rounds.built?;
    // `usize::MAX` counts an unusable surface, which the caller's check names.
    // With parameters the user set, a folded surface is theirs to study: it is built, and
    // said; with the defaults it is refused.
    if rounds.samples > 0 && rounds.samples != usize::MAX {
        let mesh = &rounds.mesh;
        let (faces, samples) = fold_corners::folding_faces(mesh, &surface);
        let site = fold_site(mesh, faces, samples);
        if user.is_empty() {
            return Err(fold_refusal(
                spec.name,
                mesh,
                &site,
                "no round of sharp edges round them unfolds it",
            ));
        }
        surface.warnings.push(format!(
            "{}: the surface {} folds over {} faces ({} samples; among them face {}, at vertex \
             {}) and no round of sharp edges round them unfolds it; the metrics count the \
             samples in `folds` (with the scheme's default parameters it is built without a \
             fold or refused)",
            spec.name,
            user_params(user),
            site.faces,
            site.samples,
            mesh.input_face(site.face),
            mesh.input_vertex(site.vertex),
        ));
    }
    if !added.is_empty() {
        surface
            .warnings
            .push(spikes::warning(spec.name, &sharpened, &mut added));
    }
    if rounds.edges > 0 {
        surface.warnings.push(fold_corners::warning(
            spec.name,
            &rounds.mesh,
            rounds.edges,
            &rounds.folded,
        ));
    }
    let before = mesh.sharp_face_pairs();
    surface.spike_face_pairs = rounds
        .mesh
        .sharp_face_pairs()
        .into_iter()
        .filter(|pair| before.binary_search(pair).is_err())
        .collect();
    Ok(surface)
}

/// Builds `scheme` on `mesh` ([`build`]) and returns the surface with the construction time
/// in ms.
pub fn build_timed(
    scheme: &str,
    mesh: &Mesh,
    params: &[(String, String)],
) -> Result<(Surface, f64)> {
    let start = std::time::Instant::now();
    let surface = build(scheme, mesh, params)?;
    Ok((surface, start.elapsed().as_secs_f64() * 1e3))
}

/// [`build_in_frame`] with the construction time in ms: the surface in its frame, for the
/// metrics ([`crate::metrics::Metrics::measure_in_frame`]).
pub fn build_timed_in_frame(
    scheme: &str,
    mesh: &Mesh,
    params: &[(String, String)],
) -> Result<(Surface, LocalFrame, f64)> {
    let start = std::time::Instant::now();
    let (surface, frame) = build_in_frame(scheme, mesh, params)?;
    Ok((surface, frame, start.elapsed().as_secs_f64() * 1e3))
}

/// How far (in mesh bounding-box diagonals) a built surface may reach beyond the mesh's
/// bounding box. Every scheme with sane parameters stays within a fraction of a diagonal on a
/// sane mesh; a surface beyond this comes from an absurd parameter, or from needle faces of
/// the mesh (one vertex 3e5 times the model's size away: the error then names the needle), and
/// would break the BVH (f32 boxes), the metrics and the exports.
pub const MAX_SURFACE_REACH: f64 = 1e3;

/// Checks a freshly built surface once, before anything uses it: every control point
/// finite, and the control net within [`MAX_SURFACE_REACH`] diagonals of the mesh's bounding
/// box. The error names the scheme, the parameters the user set (`user`) and the patch.
pub fn check_surface(surface: &Surface, mesh: &Mesh, user: &[(String, String)]) -> Result<()> {
    let unusable = |patch: usize, what: String| Error::UnusableSurface {
        scheme: surface.scheme.clone(),
        params: user_params(user),
        reason: format!(
            "patch {patch} (face {}) {what}",
            mesh.input_face(surface.patches[patch].face)
        ),
    };
    if let Some(patch) = surface.first_non_finite_patch() {
        return Err(unusable(patch, "has a non-finite control point".into()));
    }
    let region = mesh.bounds();
    let diag = region.diagonal();
    let reach = |p: &Patch| {
        let b = p.full_bounds();
        (region.min - b.min).max(b.max - region.max).max_element() / diag
    };
    let farthest = surface
        .patches
        .iter()
        .map(reach)
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(&b.1));
    match farthest {
        Some((patch, r)) if r > MAX_SURFACE_REACH => Err(unusable(
            patch,
            format!(
                "reaches {r:.3e} mesh diagonals beyond the mesh's bounding box \
                 (limit {MAX_SURFACE_REACH:e}){}",
                needle_hint(mesh, surface.patches[patch].face, user)
            ),
        )),
        _ => Ok(()),
    }
}

/// Where a built surface folds (after the fold rounds, for a scheme that makes them).
struct FoldSite {
    /// Faces the surface folds over.
    faces: usize,
    /// Its fold samples.
    samples: usize,
    /// The folding face named: the thinnest needle among them.
    face: u32,
    /// Its corner named: the needle's tip (opposite its shortest edge; where a stray vertex
    /// made the needles, that vertex) for a needle ([`NEEDLE_ASPECT`]), else its corner where
    /// the faces fold over themselves ([`fold_corners::folded_rings`]), else the corner most
    /// of the folding faces share.
    vertex: u32,
}

/// The [`FoldSite`] of a surface on `mesh` that folds over `faces` (sorted, not empty) at
/// `samples` samples ([`fold_corners::folding_faces`]).
fn fold_site(mesh: &Mesh, faces: Vec<u32>, samples: usize) -> FoldSite {
    let face = faces
        .iter()
        .copied()
        .max_by(|&f, &g| face_aspect(mesh, f).total_cmp(&face_aspect(mesh, g)))
        .unwrap_or(0);
    let corners = mesh.faces()[face as usize];
    let tip = || {
        let at = corners.map(|v| mesh.positions()[v as usize]);
        let opposite = |i: usize| (at[(i + 1) % 3] - at[(i + 2) % 3]).length();
        (0..3)
            .min_by(|&i, &j| opposite(i).total_cmp(&opposite(j)))
            .map(|i| corners[i])
    };
    let rings = fold_corners::folded_rings(mesh);
    let shared = |v: u32| {
        faces
            .iter()
            .filter(|&&f| mesh.faces()[f as usize].contains(&v))
            .count()
    };
    let vertex = (face_aspect(mesh, face) > NEEDLE_ASPECT)
        .then(tip)
        .flatten()
        .or_else(|| corners.iter().copied().find(|v| rings.contains(v)))
        .or_else(|| corners.iter().copied().max_by_key(|&v| shared(v)))
        .unwrap_or(corners[0]);
    FoldSite {
        faces: faces.len(),
        samples,
        face,
        vertex,
    }
}

/// The refusal of a default surface of `scheme` that folds at `site` on `mesh`, `after` saying
/// why no sharp edge settles it; the remedy names the needle where the face is one.
fn fold_refusal(scheme: &str, mesh: &Mesh, site: &FoldSite, after: &str) -> Error {
    let hint = needle_hint(mesh, site.face, &[]);
    Error::FoldedSurface {
        scheme: scheme.to_string(),
        faces: site.faces,
        samples: site.samples,
        face: mesh.input_face(site.face),
        vertex: site.vertex as usize,
        after: after.to_string(),
        remedy: if hint.is_empty() {
            "; repair the mesh at that vertex, or use the flat scheme".to_string()
        } else {
            format!("{hint}; or use the flat scheme")
        },
    }
}

/// The parameters the user set, as `with a=1, b=2`, or `with default parameters`.
fn user_params(user: &[(String, String)]) -> String {
    if user.is_empty() {
        return "with default parameters".to_string();
    }
    let set: Vec<String> = user.iter().map(|(n, v)| format!("{n}={v}")).collect();
    format!("with {}", set.join(", "))
}

/// Faces this many times longer than high are needles, where a surface with default
/// parameters can run far off (a mesh with one vertex 3e5 away from a model of unit size).
const NEEDLE_ASPECT: f64 = 1e3;

/// For a surface built with default parameters (`user` empty) that runs off at face `face`:
/// `; that face is a needle, …` when that face's longest edge is more than [`NEEDLE_ASPECT`]
/// times its height (the mesh, not a parameter, is then the cause), else nothing.
fn needle_hint(mesh: &Mesh, face: u32, user: &[(String, String)]) -> String {
    let aspect = face_aspect(mesh, face);
    if !user.is_empty() || aspect.is_nan() || aspect <= NEEDLE_ASPECT {
        return String::new();
    }
    format!(
        "; that face is a needle, its longest edge {aspect:.3e} times its height: repair or \
         remove it (a vertex far from the others, as a stray vertex of a corrupted file, makes \
         such faces)"
    )
}

/// The longest edge of `face` over its height (NaN or infinite for a face of zero area).
fn face_aspect(mesh: &Mesh, face: u32) -> f64 {
    let [a, b, c] = mesh.faces()[face as usize].map(|v| mesh.positions()[v as usize]);
    let longest = (b - a).length().max((c - b).length()).max((a - c).length());
    longest * longest / (b - a).cross(c - a).length()
}

/// A scheme's parameters with defaults filled in.
#[derive(Clone, Debug)]
pub struct Params {
    values: Vec<(String, String)>,
}

impl Params {
    /// Checks `user` against `spec` and fills in defaults.
    pub fn resolve(spec: &SchemeSpec, user: &[(String, String)]) -> Result<Params> {
        let mut values: Vec<(String, String)> = spec
            .params
            .iter()
            .map(|p| (p.name.to_string(), p.default.to_string()))
            .collect();
        for (name, value) in user {
            let slot =
                values
                    .iter_mut()
                    .find(|(n, _)| n == name)
                    .ok_or_else(|| Error::UnknownParam {
                        scheme: spec.name.to_string(),
                        name: name.clone(),
                        known: spec
                            .params
                            .iter()
                            .map(|p| p.name)
                            .collect::<Vec<_>>()
                            .join(", "),
                    })?;
            slot.1 = value.clone();
        }
        Ok(Params { values })
    }

    /// All values, defaults filled in, in the scheme's order.
    pub fn values(&self) -> &[(String, String)] {
        &self.values
    }

    /// The surface of `patches` built by scheme `scheme` with these parameters (both recorded
    /// in it, for export and the metrics).
    pub fn surface(&self, scheme: &str, patches: Vec<Patch>) -> Surface {
        Surface {
            scheme: scheme.to_string(),
            warnings: Vec::new(),
            spike_face_pairs: Vec::new(),
            params: self.values.clone(),
            patches,
        }
    }

    /// The text value of `name` (which the scheme declared).
    pub fn text(&self, name: &str) -> &str {
        self.values
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_str())
            .unwrap_or_else(|| panic!("scheme asked for undeclared parameter '{name}'"))
    }

    /// `name` as a finite number.
    pub fn number(&self, name: &str) -> Result<f64> {
        let text = self.text(name);
        match text.trim().parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            _ => Err(Error::BadParam {
                name: name.to_string(),
                reason: format!("'{text}' is not a finite number"),
            }),
        }
    }

    /// `name` as a finite number greater than zero; `why` says what a value ≤ 0 would break.
    pub fn positive_number(&self, name: &str, why: &str) -> Result<f64> {
        let x = self.number(name)?;
        if x > 0.0 {
            Ok(x)
        } else {
            Err(Error::BadParam {
                name: name.to_string(),
                reason: format!("must be > 0 ({why}), got {x}"),
            })
        }
    }

    /// `name` as one of `choices`.
    pub fn choice<'a>(&self, name: &str, choices: &[&'a str]) -> Result<&'a str> {
        let text = self.text(name);
        choices
            .iter()
            .find(|c| **c == text)
            .copied()
            .ok_or_else(|| Error::BadParam {
                name: name.to_string(),
                reason: format!("'{text}' is not one of {}", choices.join(", ")),
            })
    }

    /// The `normals` parameter shared by normal-based schemes.
    pub fn normal_source(&self) -> Result<NormalSource> {
        Ok(match self.choice("normals", &["estimate", "obj"])? {
            "obj" => NormalSource::Obj,
            _ => NormalSource::Estimate,
        })
    }
}

/// What a scheme does at a vertex whose faces fold over themselves (no front-facing normal).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AtFoldedVertex {
    /// Refuse with [`Error::FoldedVertex`] naming the vertex (schemes documented as G¹, whose
    /// surface would fold there).
    Refuse,
    /// Keep the estimate and say so in a warning (schemes that make no smoothness claim).
    Warn,
}

/// The unit vertex normals of a normal-based scheme (its `normals` parameter), with the
/// warnings to record in its surface.
///
/// Estimated normals are made front-facing ([`crate::mesh::front_facing`]): every face around
/// a vertex sees its normal from the front side by [`FRONT_MARGIN`] where one exists — the
/// angle-weighted estimate where it already is, else the admissible direction closest to it —
/// so that the surface, whose normal at the vertex is this one, does not turn over a face
/// there. Moved normals are counted in a warning naming the first vertex. A file's normals
/// (`normals=obj`) are never moved: one that a face sees from behind or edge-on gives a
/// warning naming the vertex (the surface folds or is singular there) and the remedy. A vertex
/// whose faces fold over themselves is handled by `folded`.
pub fn scheme_normals(
    mesh: &Mesh,
    params: &Params,
    scheme: &str,
    folded: AtFoldedVertex,
) -> Result<(Vec<glam::DVec3>, Vec<String>)> {
    let source = params.normal_source()?;
    let estimate = mesh.vertex_normals(source)?;
    let mut warnings = Vec::new();
    if source == NormalSource::Obj {
        let behind: Vec<(u32, f64)> = (0..mesh.vertex_count() as u32)
            .filter_map(|v| {
                let worst = mesh
                    .ring_faces(v)
                    .iter()
                    .map(|&f| estimate[v as usize].dot(mesh.face_normal(f)))
                    .fold(f64::INFINITY, f64::min);
                (worst < FRONT_MARGIN).then_some((v, worst))
            })
            .collect();
        if let Some(&(v, worst)) = behind.first() {
            warnings.push(format!(
                "{scheme}: the file's normals at {} vertices are seen from behind or edge-on by \
                 a face around them (first: vertex {}, cosine {worst:.3}), so the surface folds \
                 or is singular there; the file's normals are kept as given — use \
                 normals=estimate to have them made front-facing",
                behind.len(),
                mesh.input_vertex(v)
            ));
        }
        return Ok((estimate, warnings));
    }
    let mut front = front_facing_normals(mesh.positions(), mesh.faces(), &estimate);
    // A vertex whose fan sharp edges cut into sectors takes one normal per sector
    // (`Mesh::corner_normals`), not this one.
    front.folded.retain(|&v| mesh.has_one_sector(v));
    if let Some(&v) = front.folded.first() {
        if folded == AtFoldedVertex::Refuse {
            return Err(Error::FoldedVertex {
                scheme: scheme.to_string(),
                vertex: v as usize,
            });
        }
        warnings.push(format!(
            "{scheme}: the faces around {} vertices fold over themselves (first: vertex {}): \
             no normal sees them all from the front, so a surface there folds or parts along \
             sharp edges (the metrics count any fold in `folds`); repair the mesh at that \
             vertex",
            front.folded.len(),
            mesh.input_vertex(v)
        ));
    }
    if let Some(&(v, angle)) = front.moved.first() {
        let largest = front.moved.iter().map(|m| m.1).fold(0.0, f64::max);
        warnings.push(format!(
            "{scheme}: tilted {} vertex normals that a face around them saw from behind or \
             edge-on (first: vertex {}, by {:.2}°; largest {:.2}°), so that the surface does \
             not fold there",
            front.moved.len(),
            mesh.input_vertex(v),
            angle.to_degrees(),
            largest.to_degrees()
        ));
    }
    Ok((front.normals, warnings))
}

/// Parses `name=value` (the CLI's `--param`).
pub fn parse_param(text: &str) -> Result<(String, String)> {
    match text.split_once('=') {
        Some((n, v)) if !n.trim().is_empty() => Ok((n.trim().to_string(), v.trim().to_string())),
        _ => Err(Error::BadParam {
            name: text.to_string(),
            reason: "expected name=value".to_string(),
        }),
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use crate::mesh::{Mesh, generate};

    /// The octahedron flattened to a sheet (its equator vertices' rings fold over themselves),
    /// after an unused vertex that loading drops: the loaded mesh numbers every vertex one
    /// lower than the file.
    fn flat_sheet_after_an_unused_vertex() -> Mesh {
        let (positions, faces) = generate::octahedron();
        let positions: Vec<DVec3> = std::iter::once(DVec3::splat(5.0))
            .chain(positions.iter().map(|p| DVec3::new(p.x, p.y, p.z * 1e-9)))
            .collect();
        let faces = faces.iter().map(|f| f.map(|v| v + 1)).collect();
        let (mesh, _) = Mesh::from_triangles(positions, faces).expect("loads");
        assert_eq!((mesh.vertex_count(), mesh.input_vertex(0)), (6, 1));
        mesh
    }

    /// A thin, twisted tube with three vertices round it and pointed ends (an insect's leg
    /// in a scan): `segments` rings of radius 0.03 along a length of 1, each turned by 0.4 rad
    /// against the last.
    fn thin_twisted_tube(segments: u32) -> Mesh {
        let ring = |i: u32, k: u32| 1 + 3 * i + k % 3;
        let mut positions = vec![DVec3::new(0.0, 0.0, -0.05)];
        for i in 0..=segments {
            let z = f64::from(i) / f64::from(segments);
            for k in 0..3 {
                let a = std::f64::consts::TAU * f64::from(k) / 3.0 + 0.4 * f64::from(i % 2);
                positions.push(DVec3::new(0.03 * a.cos(), 0.03 * a.sin(), z));
            }
        }
        positions.push(DVec3::new(0.0, 0.0, 1.05));
        let tip = positions.len() as u32 - 1;
        let mut faces = Vec::new();
        for k in 0..3 {
            faces.push([0, ring(0, k + 1), ring(0, k)]);
            faces.push([tip, ring(segments, k), ring(segments, k + 1)]);
            for i in 0..segments {
                let (a, b) = (ring(i, k), ring(i, k + 1));
                let (c, d) = (ring(i + 1, k), ring(i + 1, k + 1));
                faces.extend([[a, b, d], [a, d, c]]);
            }
        }
        Mesh::from_triangles(positions, faces).expect("loads").0
    }

    /// The icosahedron with one vertex moved to distance `far` (a stray vertex): its five
    /// faces are needles. At 3e3 hb and loop94 build it with no fold (20 and 23 edges made
    /// sharp at the spike); at 3e4 hb's, and at 1e6 both surfaces still fold where no round
    /// of sharp edges unfolds them (267 and 455 / 107 samples, which they were built with
    /// before), and they are refused naming a needle and its tip, the stray vertex, with the remedy; so is
    /// gk's at 1e6, which turns away from 17 faces with no sharp edges to make (over faces
    /// that are not needles, as on VTK's ant, it is built with a warning). With a parameter
    /// the user set, a surface that folds is built with a warning.
    #[test]
    fn a_default_surface_that_still_folds_is_refused_naming_the_needle_tip() {
        let moved = |far: f64| {
            let (mut positions, faces) = crate::mesh::generate::icosahedron();
            positions[0] = DVec3::new(far, 0.0, 0.0);
            crate::testing::mesh((positions, faces))
        };
        for scheme in ["hb", "loop94"] {
            let mesh = moved(3e3);
            let surface = super::build(scheme, &mesh, &[]).expect("builds");
            let m = crate::metrics::Metrics::measure(&surface, &mesh, 0.0);
            assert_eq!(m.folds, 0, "{scheme} at 3e3");
            assert!(m.spike_edges > 0, "{scheme} at 3e3");
        }
        for (scheme, far) in [("hb", 3e4), ("hb", 1e6), ("loop94", 1e6), ("gk", 1e6)] {
            let mesh = moved(far);
            match super::build(scheme, &mesh, &[]) {
                Err(e @ crate::Error::FoldedSurface { .. }) => {
                    let crate::Error::FoldedSurface {
                        face,
                        vertex,
                        samples,
                        ..
                    } = &e
                    else {
                        unreachable!()
                    };
                    assert_eq!(*vertex, 0, "{scheme} at {far:e}: {e}");
                    assert!(mesh.faces()[*face].contains(&0), "{scheme} at {far:e}: {e}");
                    assert!(*samples > 0, "{e}");
                    let message = e.to_string();
                    assert!(
                        message.contains(
                            "with default parameters cannot build a surface without a fold"
                        ) && message.contains("that face is a needle")
                            && message.ends_with("; or use the flat scheme"),
                        "{message}"
                    );
                }
                other => panic!("{scheme} at {far:e}: {:?}", other.map(|s| s.warnings)),
            }
        }
        // A parameter the user set is theirs to study: HB00 with `alpha=0.5` (no longer
        // interpolating) folds on the cube, more with sharp edges, and is built and said.
        let alpha = [("alpha".to_string(), "0.5".to_string())];
        builds_folding_and_says_so(
            ("hb", &alpha),
            &crate::testing::scene("cube"),
            "hb: the surface with alpha=0.5 folds",
            "among them face ",
        );
    }

    /// Builds `scheme` with `params` on `mesh`, whose surface folds, and checks that its one
    /// warning containing `fragment` counts the metrics' fold samples, followed by `then`.
    fn builds_folding_and_says_so(
        (scheme, params): (&str, &[(String, String)]),
        mesh: &Mesh,
        fragment: &str,
        then: &str,
    ) {
        let surface = super::build(scheme, mesh, params).expect("builds");
        let m = crate::metrics::Metrics::measure(&surface, mesh, 0.0);
        assert!(m.folds > 0, "{scheme}: {m:?}");
        let warned = crate::testing::the_warning(&surface, fragment);
        assert!(
            warned.contains(&format!("({} samples; {then}", m.folds)),
            "{warned}"
        );
    }

    /// gk approximates: over a thin twisted tube its surface turns more than 90° away from a
    /// few faces' normals. It has no sharp edges to make, so it says so, counting what the
    /// metrics count in `folds`.
    #[test]
    fn gk_says_where_its_surface_turns_away_from_the_faces() {
        builds_folding_and_says_so(
            ("gk", &[]),
            &thin_twisted_tube(6),
            "turns more than 90° away from",
            "first: face ",
        );
    }

    /// A surface that runs off over a needle face of the mesh (the icosahedron with one vertex
    /// moved 3e5 away) is refused naming the face as the cause and the remedy; with a
    /// parameter set by the user the message stays about the parameter.
    #[test]
    fn a_surface_running_off_over_a_needle_names_the_needle() {
        let (mut positions, faces) = crate::mesh::generate::icosahedron();
        positions[0] = DVec3::new(3e5, 0.0, 0.0);
        let mesh = crate::testing::mesh((positions, faces));
        let message = match super::build("hb", &mesh, &[]) {
            Err(e @ crate::Error::UnusableSurface { .. }) => e.to_string(),
            other => panic!("hb: {:?}", other.map(|s| s.warnings)),
        };
        assert!(
            message.contains("mesh diagonals beyond")
                && message.contains("that face is a needle, its longest edge")
                && message.contains("repair or remove it"),
            "{message}"
        );
        let needles: Vec<u32> = (0..mesh.face_count() as u32)
            .filter(|&f| !super::needle_hint(&mesh, f, &[]).is_empty())
            .collect();
        assert_eq!(needles.len(), 5, "the far vertex's five faces: {needles:?}");
        let user = [("alpha".to_string(), "1".to_string())];
        assert!(
            needles
                .iter()
                .all(|&f| super::needle_hint(&mesh, f, &user).is_empty())
        );
    }

    /// pn keeps its normal there and warns; every scheme that keeps sharp edges makes the
    /// sheet's rim sharp instead ([`super::spikes`]), so each side is a smooth sector that
    /// does not fold; both name vertices in the file's numbering.
    #[test]
    fn a_folded_vertex_is_named_in_the_files_numbering() {
        let mesh = flat_sheet_after_an_unused_vertex();
        let surface = super::build("pn", &mesh, &[]).expect("pn");
        let folded: Vec<&String> = surface
            .warnings
            .iter()
            .filter(|w| w.contains("fold over themselves"))
            .collect();
        assert_eq!(folded.len(), 1, "pn: {:?}", surface.warnings);
        assert!(folded[0].contains("(first: vertex 1)"), "{}", folded[0]);
        for scheme in ["hb", "loop94", "piper", "nielson", "fang-mann"] {
            let surface = super::build(scheme, &mesh, &[]).expect(scheme);
            let sharpened: Vec<&String> = surface
                .warnings
                .iter()
                .filter(|w| w.contains("made 4 edges sharp at spikes"))
                .collect();
            assert_eq!(sharpened.len(), 1, "{scheme}: {:?}", surface.warnings);
            assert!(
                sharpened[0].contains("(sharpest: edge (1, 3), its faces turning 180.0°"),
                "{}",
                sharpened[0]
            );
            let m = crate::metrics::Metrics::measure(&surface, &mesh, 0.0);
            assert_eq!((m.folds, m.spike_edges), (0, 4), "{scheme}");
            assert!(
                m.g1_max_rad.unwrap() <= 1e-9,
                "{scheme}: {:?}",
                m.g1_max_rad
            );
        }
    }
}
