//! One render job as a value: what to render ([`RenderSettings`]), from where ([`CameraSpec`]),
//! which curves to draw and which tracer to use ([`Geometry`]). The command layer validates a
//! scene once into a [`RenderJob`]; [`RenderJob::render`] then needs only the surface (and
//! the mesh it was built on, for the curve network).

use glam::DVec3;
use rayon::prelude::*;

use crate::bezier::TriangleBezier;
use crate::error::{Error, Problem, Result};
use crate::geom::Aabb;
use crate::mesh::Mesh;
use crate::render::bvh::SubdivisionCriterion;
use crate::render::camera::{Camera, FramedPoints, Projection};
use crate::render::curves::CurveOverlay;
use crate::render::film::{Frame, RenderSettings, render_cancellable};
use crate::render::interaction::ShadingPoint;
use crate::render::intersect::{IntersectCounters, NewtonSettings, Ray64, Tracer};
use crate::render::modes::{Mode, Setup};
use crate::render::stats::RenderStats;
use crate::render::tessellate::TessellatedTracer;
use crate::render::trace::SurfaceTracer;
use crate::surface::{Patch, PatchGeometry, Surface};

/// Default vertical field of view, degrees.
pub(crate) const DEFAULT_FOV: f64 = 35.0;

/// Default image size of a render.
pub(crate) const DEFAULT_SIZE: [u32; 2] = [640, 480];
/// Default samples per pixel of a render.
pub(crate) const DEFAULT_SPP: u32 = 4;
/// The largest image side of a render (`render.size`, `--size`).
pub(crate) const MAX_SIDE: u32 = 16384;
/// The most samples per pixel a render takes (`render.spp`, `--spp`).
pub(crate) const MAX_SPP: u32 = 65536;
/// Default cell size of a figure.
pub(crate) const DEFAULT_CELL_SIZE: [u32; 2] = [256, 256];
/// The largest cell side of a figure.
pub(crate) const MAX_CELL_SIDE: u32 = 4096;
/// The most samples per pixel of a figure cell.
pub(crate) const MAX_CELL_SPP: u32 = 4096;

/// Steps of the framing grid on a patch's domain: `(i/N, j/N)`, `i + j ≤ N`.
const FRAMING_STEPS: u32 = 6;

/// Framing points per patch: the grid of [`FRAMING_STEPS`].
const FRAMING_POINTS: usize = ((FRAMING_STEPS + 1) * (FRAMING_STEPS + 2) / 2) as usize;

/// The framing points of one patch: the surface at the grid `(i/6, j/6)`, `i + j ≤ 6`, of its
/// domain (its corners among them).
fn patch_samples(patch: &Patch) -> [DVec3; FRAMING_POINTS] {
    let mut points = [DVec3::ZERO; FRAMING_POINTS];
    let mut k = 0;
    for j in 0..=FRAMING_STEPS {
        for i in 0..=FRAMING_STEPS - j {
            points[k] = patch.eval(
                f64::from(i) / f64::from(FRAMING_STEPS),
                f64::from(j) / f64::from(FRAMING_STEPS),
            );
            k += 1;
        }
    }
    points
}

/// The points that frame surfaces tightly: every patch sampled on a 28-point grid of its domain
/// ([`patch_samples`]), evaluated on demand and in parallel, never stored.
///
/// A patch lies in the convex hull of its control points (of its three sub-surfaces' for a
/// blend, a convex combination of them), so a patch whose hull stays inside what some framing
/// points already reach (the corners of the first patch of every run of [`FRAMING_RUN`]
/// patches) cannot change the box or a convex maximum, and is not evaluated; a whole run is
/// tested first by the box of its control points. The result is that of one pass over all the
/// points: a box and a maximum do not depend on the order, so it is the same for any thread
/// count.
pub struct SurfaceSamples<'a> {
    surfaces: Vec<&'a Surface>,
    /// The box of the control points of each run of [`FRAMING_RUN`] patches, in the order of
    /// [`SurfaceSamples::runs`]: made once, as the framing asks for many maxima.
    run_boxes: Vec<Aabb>,
}

impl<'a> SurfaceSamples<'a> {
    /// The framing points of all `surfaces` together.
    pub fn new(surfaces: &[&'a Surface]) -> SurfaceSamples<'a> {
        let mut samples = SurfaceSamples {
            surfaces: surfaces.to_vec(),
            run_boxes: Vec::new(),
        };
        samples.run_boxes = samples.runs().map(run_bounds).collect();
        samples
    }

    /// The framing points of one surface.
    pub fn of(surface: &'a Surface) -> SurfaceSamples<'a> {
        SurfaceSamples::new(&[surface])
    }

    /// Runs of up to [`FRAMING_RUN`] consecutive patches, in parallel.
    fn runs(&self) -> impl IndexedParallelIterator<Item = &'a [Patch]> + '_ {
        let runs: Vec<&'a [Patch]> = self
            .surfaces
            .iter()
            .flat_map(|s| s.patches.chunks(FRAMING_RUN))
            .collect();
        runs.into_par_iter()
    }

    /// The runs with their control boxes.
    fn boxed_runs(&self) -> impl ParallelIterator<Item = (&'a [Patch], Aabb)> + '_ {
        self.runs().zip(self.run_boxes.par_iter().copied())
    }

    /// All the points, in order (patch by patch): for tests and small surfaces.
    pub fn to_vec(&self) -> Vec<DVec3> {
        self.surfaces
            .iter()
            .flat_map(|s| &s.patches)
            .flat_map(patch_samples)
            .collect()
    }
}

/// The control points whose convex hull contains `patch`.
fn hull_points(patch: &Patch) -> impl Iterator<Item = DVec3> + '_ {
    let nets: &[TriangleBezier] = match &patch.geometry {
        PatchGeometry::Bezier(net) => std::slice::from_ref(net),
        PatchGeometry::Blend(blend) => blend.sub_surfaces(),
    };
    nets.iter().flat_map(|n| n.control_points())
}

/// Patches tested together by the automatic framing before they are tested one by one.
const FRAMING_RUN: usize = 64;

/// The box of the control points of every patch of `run`.
fn run_bounds(run: &[Patch]) -> Aabb {
    run.iter()
        .map(Patch::full_bounds)
        .fold(Aabb::EMPTY, Aabb::union)
}

/// The eight corners of `b`.
fn box_corners(b: Aabb) -> [DVec3; 8] {
    std::array::from_fn(|k| {
        DVec3::new(
            if k & 1 == 0 { b.min.x } else { b.max.x },
            if k & 2 == 0 { b.min.y } else { b.max.y },
            if k & 4 == 0 { b.min.z } else { b.max.z },
        )
    })
}

/// The surface at the three corners of `patch`'s domain (framing points themselves). For a
/// Bézier patch these are its corner control points: de Casteljau with the weights 0 and 1
/// reproduces them exactly (up to the sign of a zero), so they need no evaluation.
fn patch_corners(patch: &Patch) -> [DVec3; 3] {
    match &patch.geometry {
        PatchGeometry::Bezier(net) => {
            let d = net.degree();
            [net.point(d, 0), net.point(0, d), net.point(0, 0)]
        }
        PatchGeometry::Blend(_) => {
            [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)].map(|(u, v)| patch.eval(u, v))
        }
    }
}

impl FramedPoints for SurfaceSamples<'_> {
    fn bounds(&self) -> Aabb {
        // The corners of the first patch of every run: a patch is skipped only when its
        // control box lies inside theirs, so the extreme points lie in patches that are sampled.
        let corners = self
            .runs()
            .map(|run| Aabb::from_points(&patch_corners(&run[0])))
            .reduce(|| Aabb::EMPTY, Aabb::union);
        // Evaluation stays within a few ulps of the hull; this margin is far above that.
        let margin =
            1e-9 * (corners.diagonal() + corners.min.abs().max(corners.max.abs()).max_element());
        let (lo, hi) = (
            corners.min + DVec3::splat(margin),
            corners.max - DVec3::splat(margin),
        );
        let inside = |b: Aabb| b.min.cmpge(lo).all() && b.max.cmple(hi).all();
        self.boxed_runs()
            .map(|(run, run_box)| {
                if inside(run_box) {
                    return Aabb::EMPTY;
                }
                run.iter()
                    .map(|p| {
                        if inside(p.full_bounds()) {
                            Aabb::EMPTY
                        } else {
                            Aabb::from_points(&patch_samples(p))
                        }
                    })
                    .fold(Aabb::EMPTY, Aabb::union)
            })
            .reduce(|| Aabb::EMPTY, Aabb::union)
            .union(corners)
    }

    fn max_convex(&self, f: &(dyn Fn(DVec3) -> f64 + Sync), floor: f64, margin: f64) -> f64 {
        let largest = |points: &[DVec3]| points.iter().fold(f64::NEG_INFINITY, |m, &p| m.max(f(p)));
        // A lower bound of the maximum from the corners of the first patch of every run: any
        // framing points will do, as a patch is skipped only when all of its points lie below
        // their maximum, and the largest point then lies in a patch that is sampled.
        let corners = self
            .runs()
            .map(|run| largest(&patch_corners(&run[0])))
            .reduce(|| floor, f64::max);
        let below = |q: DVec3| f(q) < corners - margin;
        // A run of patches whose common control box lies below the running maximum (a convex
        // function's maximum over a box is at its corners) cannot raise it: one test of 8
        // corners instead of every patch's control points.
        self.boxed_runs()
            .map(|(run, run_box)| {
                if box_corners(run_box).into_iter().all(below) {
                    return corners;
                }
                run.iter()
                    .map(|p| {
                        if hull_points(p).all(below) {
                            corners
                        } else {
                            largest(&patch_samples(p))
                        }
                    })
                    .fold(corners, f64::max)
            })
            .reduce(|| corners, f64::max)
    }
}

/// Where the camera of a job is: given by eye (and target, up), or framed automatically.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraSpec {
    /// Eye position; `None` frames points sampled on the surface automatically.
    pub eye: Option<DVec3>,
    /// Point looked at (default: the centre of the surface's samples).
    pub target: Option<DVec3>,
    /// Up direction (default: +Y with an eye; the framing's own up without one).
    pub up: Option<DVec3>,
    /// Vertical field of view in degrees (perspective) or of the framing (orthographic).
    pub fov_deg: f64,
    /// Orthographic projection.
    pub orthographic: bool,
}

impl Default for CameraSpec {
    fn default() -> Self {
        CameraSpec {
            eye: None,
            target: None,
            up: None,
            fov_deg: DEFAULT_FOV,
            orthographic: false,
        }
    }
}

impl CameraSpec {
    /// The camera for `surface` and an image of aspect `aspect`: the given eye/target/up when
    /// an eye is given (target defaults to the surface's centre), automatic framing of points
    /// sampled on the surface otherwise (with the given up, if any, pointing up in the image;
    /// around the given target, if any).
    pub fn camera(&self, surface: &Surface, aspect: f64) -> Result<Camera> {
        let samples = SurfaceSamples::of(surface);
        let bounds = &samples.bounds();
        let fov = self.fov_deg;
        let camera = match self.eye {
            Some(eye) => Camera::look_at(
                eye,
                self.target.unwrap_or(bounds.center()),
                self.up.unwrap_or(DVec3::Y),
                Projection::Perspective { fov_deg: fov },
            )?,
            None => {
                let framed = match self.up {
                    Some(up) => Camera::frame_points_with_up(
                        &samples,
                        Camera::DEFAULT_VIEW,
                        up,
                        fov,
                        aspect,
                    )?,
                    None => Camera::frame_points(&samples, Camera::DEFAULT_VIEW, fov, aspect)?,
                };
                if let Some(target) = self.target {
                    // Same view direction, distance and up as the automatic framing, around
                    // `target`.
                    Camera::look_at(
                        framed.eye - bounds.center() + target,
                        target,
                        framed.up(),
                        Projection::Perspective { fov_deg: fov },
                    )?
                } else {
                    framed
                }
            }
        };
        if self.orthographic {
            camera.orthographic_of(fov)
        } else {
            Ok(camera)
        }
    }
}

/// Default of the most BVH leaves a job may build: 2^24 leaves, a few GB of BVH.
pub(crate) const DEFAULT_MAX_LEAVES: u64 = 1 << 24;

/// What the rays meet: the exact patches (through a BVH of subdivided patch bounds) or a
/// tessellation of them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Geometry {
    /// The exact patches.
    Exact {
        /// When a BVH leaf is fine enough.
        criterion: SubdivisionCriterion,
        /// The most leaves the BVH may have (checked by [`check_bvh_size`] before building).
        max_leaves: u64,
    },
    /// A tessellation with this many subdivisions per patch edge.
    Tessellated(u32),
}

impl Default for Geometry {
    fn default() -> Self {
        Geometry::Exact {
            criterion: SubdivisionCriterion::default(),
            max_leaves: DEFAULT_MAX_LEAVES,
        }
    }
}

/// A validated render job: everything but the surface.
#[derive(Clone, Debug, Default)]
pub struct RenderJob {
    /// Image, mode, overlay, samples (its `curves` are filled in by [`RenderJob::render`]).
    pub settings: RenderSettings,
    /// The camera.
    pub camera: CameraSpec,
    /// The curve-network overlay, built from the mesh's edges.
    pub curves: CurveOverlay,
    /// Exact or tessellated.
    pub geometry: Geometry,
}

/// The tracer of a job for one surface: the exact patches or a tessellation, as the job's
/// [`Geometry`] says, built once with the job's BVH settings and budget. An interactive view
/// builds it once and renders many cameras and settings of the same geometry with it.
pub enum JobTracer<'s> {
    /// The exact patches.
    Exact(Tracer<'s>),
    /// A tessellation of them.
    Tessellated(TessellatedTracer<'s>),
}

impl JobTracer<'_> {
    /// Renders with this tracer (see [`film::render_cancellable`](crate::render::film::render_cancellable)).
    fn render(
        &self,
        camera: &Camera,
        settings: &RenderSettings,
        cancelled: &(dyn Fn() -> bool + Sync),
    ) -> Result<Option<(Frame, RenderStats)>> {
        match self {
            JobTracer::Exact(t) => render_cancellable(t, camera, settings, cancelled),
            JobTracer::Tessellated(t) => render_cancellable(t, camera, settings, cancelled),
        }
    }

    /// The closest hit of `ray` and its shading point.
    fn shade(&self, ray: &Ray64) -> Option<ShadingPoint> {
        let mut counters = IntersectCounters::default();
        match self {
            JobTracer::Exact(t) => t
                .closest_hit(ray, 0.0, f64::INFINITY, &mut counters)
                .map(|hit| SurfaceTracer::shading_point(t, &hit, ray)),
            JobTracer::Tessellated(t) => {
                SurfaceTracer::closest_hit(t, ray, 0.0, f64::INFINITY, &mut counters)
                    .map(|hit| t.shading_point(&hit, ray))
            }
        }
    }
}

impl<'s> JobTracer<'s> {
    /// The tracer of `surface` for `geometry`: a tessellation, or the exact patches after the
    /// BVH's size and memory are checked against the budget ([`check_bvh_size`]), built with
    /// the geometry's BVH settings. Every render builds its tracer here.
    pub fn new(surface: &'s Surface, geometry: &Geometry) -> Result<JobTracer<'s>> {
        match geometry {
            Geometry::Tessellated(n) => {
                Ok(JobTracer::Tessellated(TessellatedTracer::new(surface, *n)?))
            }
            Geometry::Exact {
                criterion,
                max_leaves,
            } => {
                check_bvh_size(surface, criterion, *max_leaves)?;
                Ok(JobTracer::Exact(Tracer::new(
                    surface,
                    criterion,
                    NewtonSettings::default(),
                )?))
            }
        }
    }

    /// The surface it traces.
    pub fn surface(&self) -> &Surface {
        match self {
            JobTracer::Exact(t) => t.surface,
            JobTracer::Tessellated(t) => SurfaceTracer::surface(t),
        }
    }

    /// The frame of `settings` seen by `camera` (faces as the tracer numbers them: the
    /// surface's triangles), and its statistics.
    pub fn render_frame(
        &self,
        camera: &Camera,
        settings: &RenderSettings,
    ) -> Result<(Frame, RenderStats)> {
        self.render(camera, settings, &|| false)?
            .ok_or_else(|| Error::Invalid("a render that cannot be cancelled was".into()))
    }

    /// The automatic colour scale `mode` chooses for the view of `camera` at `width` ×
    /// `height` ([`crate::render::modes::ModeKind::measure_scale`]).
    pub fn measure_scale(
        &self,
        mode: &Mode,
        camera: &Camera,
        width: u32,
        height: u32,
    ) -> Option<f64> {
        match self {
            JobTracer::Exact(tracer) => mode.measure_scale(&Setup {
                tracer,
                camera,
                width,
                height,
            }),
            JobTracer::Tessellated(tracer) => mode.measure_scale(&Setup {
                tracer,
                camera,
                width,
                height,
            }),
        }
    }

    /// `mode` with what its set-up chooses from the view of `camera` at `width` × `height`
    /// (an automatic curvature range, a zebra stripe count) fixed
    /// ([`crate::render::modes::ModeKind::pinned`]): what a preview pass at another size or
    /// the other cells of a figure are rendered with, so that they show the stripes and
    /// colours of this view.
    pub fn pin_view(&self, mode: &Mode, camera: &Camera, width: u32, height: u32) -> Mode {
        let mut stats = RenderStats::default();
        match self {
            JobTracer::Exact(tracer) => mode.set_up(
                &Setup {
                    tracer,
                    camera,
                    width,
                    height,
                },
                &mut stats,
            ),
            JobTracer::Tessellated(tracer) => mode.set_up(
                &Setup {
                    tracer,
                    camera,
                    width,
                    height,
                },
                &mut stats,
            ),
        };
        mode.pinned(&stats)
    }

    /// Leaves of the BVH (0 for a tessellation's).
    pub fn leaf_count(&self) -> usize {
        match self {
            JobTracer::Exact(t) => SurfaceTracer::leaf_count(t),
            JobTracer::Tessellated(t) => SurfaceTracer::leaf_count(t),
        }
    }
}

/// `mode` as a surface built on `mesh` is rendered with: an open mesh's back shows, so the
/// quality modes tint it ([`Mode::with_back_faces_tinted`]).
pub(crate) fn mode_for_mesh(mode: &Mode, mesh: &Mesh) -> Mode {
    if mesh.is_closed() {
        mode.clone()
    } else {
        mode.with_back_faces_tinted()
    }
}

/// Refuses an image of `width` × `height` outside `1..=max_side` per side, naming `what`.
pub(crate) fn check_size(what: &str, width: u32, height: u32, max_side: u32) -> Result<()> {
    if width == 0 || height == 0 || width > max_side || height > max_side {
        return Err(Error::config(
            what,
            Problem::Must {
                value: format!("{width}x{height}"),
                requirement: format!("be between 1 and {max_side} per side"),
            },
        ));
    }
    Ok(())
}

/// Refuses samples per pixel outside `1..=max`, naming `what`.
pub(crate) fn check_spp(what: &str, spp: u32, max: u32) -> Result<()> {
    if spp == 0 || spp > max {
        return Err(Error::config(
            what,
            Problem::Must {
                value: spp.to_string(),
                requirement: format!("be in 1..={max}"),
            },
        ));
    }
    Ok(())
}

impl RenderJob {
    /// The settings this job renders `surface` (built on `mesh`) with: its own, the curve
    /// tubes built from the mesh's edges.
    pub fn settings_for(&self, surface: &Surface, mesh: &Mesh) -> Result<RenderSettings> {
        let mut settings = self.settings.clone();
        settings.curves = self.curves.tubes(surface, mesh)?;
        Ok(settings)
    }

    /// This job with its mode as a surface built on `mesh` is shown ([`mode_for_mesh`]).
    pub fn for_mesh(mut self, mesh: &Mesh) -> RenderJob {
        self.settings.mode = mode_for_mesh(&self.settings.mode, mesh);
        self
    }

    /// The camera this job renders `surface` with (as [`RenderJob::render`] computes it).
    pub fn camera_of(&self, surface: &Surface) -> Result<Camera> {
        let aspect = f64::from(self.settings.width) / f64::from(self.settings.height);
        self.camera.camera(surface, aspect)
    }

    /// The tracer this job renders `surface` with ([`JobTracer::new`] of its geometry).
    pub fn tracer<'s>(&self, surface: &'s Surface) -> Result<JobTracer<'s>> {
        JobTracer::new(surface, &self.geometry)
    }

    /// Renders `surface` (built on `mesh`) with this job's camera, settings and curves; the
    /// frame's faces are the mesh's input faces ([`Mesh::input_face`]).
    pub fn render(&self, surface: &Surface, mesh: &Mesh) -> Result<(Frame, RenderStats)> {
        let tracer = self.tracer(surface)?;
        self.render_with(&tracer, mesh, &|| false)?
            .ok_or_else(|| Error::Invalid("a render that cannot be cancelled was".into()))
    }

    /// Renders with `tracer` (this job's [`RenderJob::tracer`] of the surface built on `mesh`,
    /// or that of a job with the same geometry): the frame [`RenderJob::render`] gives, bit
    /// for bit, or `None` when `cancelled` answered true before a tile.
    pub fn render_with(
        &self,
        tracer: &JobTracer<'_>,
        mesh: &Mesh,
        cancelled: &(dyn Fn() -> bool + Sync),
    ) -> Result<Option<(Frame, RenderStats)>> {
        let surface = tracer.surface();
        let settings = self.settings_for(surface, mesh)?;
        let camera = self.camera_of(surface)?;
        let Some((mut frame, stats)) = tracer.render(&camera, &settings, cancelled)? else {
            return Ok(None);
        };
        // `face_id` names the face the user wrote: the input face (polygon) each triangle was
        // cut from ([`Mesh::input_face`]).
        let origins = mesh.face_origins();
        for g in frame.geometry.iter_mut().flatten() {
            if let Some(&input) = origins.get(g.face as usize) {
                g.face = input;
            }
        }
        Ok(Some((frame, stats)))
    }

    /// The exact hit through image point `(x, y)` (pixels from the top-left corner of this
    /// job's image; a pixel's centre is at `+0.5`), traced as the render traces the ray
    /// through a pixel centre, and its shading point (None: the ray misses).
    pub fn probe(&self, tracer: &JobTracer<'_>, x: f64, y: f64) -> Result<Option<ShadingPoint>> {
        Ok(tracer.shade(&self.pixel_ray(tracer.surface(), x, y)?))
    }

    /// The camera ray through image point `(x, y)` (pixels from the top-left corner; pixel
    /// centres at half-integers) of this job's image of `surface`.
    pub fn pixel_ray(&self, surface: &Surface, x: f64, y: f64) -> Result<Ray64> {
        let camera = self.camera_of(surface)?;
        let (w, h) = (
            f64::from(self.settings.width),
            f64::from(self.settings.height),
        );
        Ok(camera.ray(2.0 * x / w - 1.0, 1.0 - 2.0 * y / h, w / h))
    }
}

/// The largest distance of a control point of `net` from the plane through its three corners,
/// relative to the diagonal of its box (1 when the corners span no plane).
fn relative_flatness(net: &TriangleBezier) -> f64 {
    let d = net.degree();
    let [a, b, c] = [net.point(d, 0), net.point(0, d), net.point(0, 0)];
    let normal = (b - a).cross(c - a).normalize_or_zero();
    let size = net.control_bounds().diagonal();
    if normal == DVec3::ZERO || size <= 0.0 {
        return 1.0;
    }
    let far = net
        .control_points()
        .map(|p| (p - a).dot(normal).abs())
        .fold(0.0, f64::max);
    far / size
}

/// An estimate of the BVH leaves `criterion` makes of `surface`, before subdividing anything.
///
/// One 4-split halves a piece and quarters the distance of its net from the corner plane, so
/// the relative flatness halves per level: a patch whose net is `r` from flat reaches
/// `criterion.flatness` after about `log2(r / flatness)` levels (clamped to the criterion's
/// depth range), i.e. `4^depth` leaves. The normal-cone and tilt tests are not estimated, so
/// this is a lower bound for strongly curved patches.
pub fn estimate_leaves(surface: &Surface, criterion: &SubdivisionCriterion) -> f64 {
    // Whole numbers summed as integers: the same total for any thread count.
    let leaves: u64 = surface
        .patches
        .par_iter()
        .map(|patch| {
            let r = match &patch.geometry {
                PatchGeometry::Bezier(net) => relative_flatness(net),
                PatchGeometry::Blend(blend) => blend
                    .sub_surfaces()
                    .iter()
                    .map(relative_flatness)
                    .fold(0.0, f64::max),
            };
            let depth = (r / criterion.flatness).log2().ceil().clamp(
                f64::from(criterion.min_depth),
                f64::from(criterion.max_depth),
            );
            1u64 << (2 * depth as u32)
        })
        .sum();
    leaves as f64
}

/// Peak bytes per BVH leaf of a patch with `points` control points while the tracer is built:
/// the leaf records and power forms (or, for patches evaluated whole, their copy in the unit
/// frame), the wide BVH and the builder's temporaries. Measured with `cargo run --release
/// --example construction_memory -- SCHEME LEVEL` (peak growth during `Tracer::new`, one leaf
/// per patch): 657 B per leaf for `flat` (3 points), 1,309 for `hb` (21 points), 2,598 for
/// `nielson` (45 points); this fit, 600 + 50 per point, is at or above each.
fn leaf_bytes(points: usize) -> f64 {
    (600 + 50 * points) as f64
}

/// Refuses a BVH that would have more than `max_leaves` leaves or need more memory than is
/// available, by [`estimate_leaves`], before the subdivision allocates anything.
pub(crate) fn check_bvh_size(
    surface: &Surface,
    criterion: &SubdivisionCriterion,
    max_leaves: u64,
) -> Result<()> {
    let leaves = estimate_leaves(surface, criterion);
    let what = format!(
        "the BVH of scheme '{}' ({} patches, bvh.flatness {:e}, bvh.max_depth {})",
        surface.scheme,
        surface.patches.len(),
        criterion.flatness,
        criterion.max_depth
    );
    if leaves > max_leaves as f64 {
        return Err(Error::TooLarge {
            what,
            estimate: format!("{leaves:.3e} leaves"),
            limit: format!("{max_leaves} leaves (bvh.max_leaves)"),
            remedy: "raise bvh.flatness, lower bvh.max_depth or raise bvh.max_leaves".into(),
        });
    }
    let points = surface
        .patches
        .iter()
        .map(|p| p.control_points().count())
        .max()
        .unwrap_or(0);
    crate::budget::check_memory(
        &what,
        leaves * leaf_bytes(points),
        "use a coarser mesh or raise bvh.flatness",
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lazily evaluated framing points give the same box and the same framing as all the
    /// points in one list, on Bézier, blend and open surfaces, from several directions.
    #[test]
    fn surface_samples_frame_exactly_like_the_listed_points() {
        let mut meshes = crate::testing::closed_test_meshes();
        meshes.extend(crate::testing::open_test_meshes().into_iter().take(2));
        for (name, mesh) in &meshes {
            for scheme in ["hb", "nielson", "pn"] {
                let Ok(surface) = crate::schemes::build(scheme, mesh, &[]) else {
                    continue;
                };
                let lazy = SurfaceSamples::of(&surface);
                let listed = lazy.to_vec();
                assert_eq!(lazy.bounds(), listed.as_slice().bounds(), "{name} {scheme}");
                for from in [Camera::DEFAULT_VIEW, DVec3::X, DVec3::new(-0.3, -1.0, 0.2)] {
                    let a = Camera::frame_points(&lazy, from, 35.0, 1.5).expect("lazy");
                    let b =
                        Camera::frame_points(listed.as_slice(), from, 35.0, 1.5).expect("listed");
                    assert_eq!(a.eye, b.eye, "{name} {scheme} from {from}");
                }
            }
        }
    }

    /// A render with a tracer built once is the render of the job, bit for bit; a render
    /// cancelled before or during its tiles returns nothing; the probe of a pixel centre is
    /// that pixel's geometry record.
    #[test]
    fn render_with_a_built_tracer_cancels_between_tiles_and_probes_pixel_centres() {
        let surface = crate::testing::surfaces::octahedron_sphere(3, 1.5, 1);
        // No curves are drawn, so the mesh is not read.
        let mesh = crate::testing::closed_test_meshes().remove(0).1;
        let mut job = RenderJob::default();
        (job.settings.width, job.settings.height, job.settings.spp) = (64, 48, 2);
        job.settings.progress = false;
        let (frame, _) = job.render(&surface, &mesh).expect("render");
        let tracer = job.tracer(&surface).expect("tracer");
        let (again, _) = job
            .render_with(&tracer, &mesh, &|| false)
            .expect("render")
            .expect("not cancelled");
        assert_eq!(frame, again);
        assert!(
            job.render_with(&tracer, &mesh, &|| true)
                .expect("render")
                .is_none(),
            "cancelled before the first tile"
        );
        let asked = std::sync::atomic::AtomicUsize::new(0);
        let after_three = || asked.fetch_add(1, std::sync::atomic::Ordering::SeqCst) >= 3;
        assert!(
            job.render_with(&tracer, &mesh, &after_three)
                .expect("render")
                .is_none(),
            "cancelled after three tiles"
        );
        let tiles = (64usize / 16) * (48 / 16);
        assert!(asked.into_inner() <= tiles, "asked once per tile at most");
        let mut probed = 0;
        for (k, g) in frame.geometry.iter().enumerate() {
            let (x, y) = ((k % 64) as f64 + 0.5, (k / 64) as f64 + 0.5);
            let sp = job.probe(&tracer, x, y).expect("probe");
            assert_eq!(
                sp.as_ref().map(crate::render::PixelGeometry::new),
                *g,
                "pixel {k}"
            );
            probed += usize::from(g.is_some());
        }
        assert!(probed > 200, "{probed} pixels hit");
    }

    /// Two surfaces framed together: the union of their points, skipping included (the
    /// second surface is shifted so that each has patches the other's corners do not reach).
    #[test]
    fn surface_samples_of_several_surfaces() {
        // No curves are drawn, so the mesh is not read.
        let mesh = crate::testing::closed_test_meshes().remove(0).1;
        let a = crate::schemes::build("hb", &mesh, &[]).expect("hb");
        let b = a.mapped(|p| p * 0.5 + DVec3::new(0.3, -0.2, 0.1));
        let lazy = SurfaceSamples::new(&[&a, &b]);
        let listed = lazy.to_vec();
        assert_eq!(
            listed.len(),
            (a.patches.len() + b.patches.len()) * FRAMING_POINTS
        );
        assert_eq!(lazy.bounds(), listed.as_slice().bounds());
        let f = |p: DVec3| p.x - 0.7 * p.y.abs();
        assert_eq!(
            lazy.max_convex(&f, -10.0, 1e-9),
            listed.as_slice().max_convex(&f, -10.0, 1e-9)
        );
    }
}
