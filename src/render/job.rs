//! One render job as a value: what to render ([`RenderSettings`]), from where ([`CameraSpec`]),
//! which curves to draw and which tracer to use ([`Geometry`]). The command layer validates a
//! scene once into a [`RenderJob`]; [`RenderJob::render`] then needs only the surface (and
//! the mesh it was built on, for the curve network).

use glam::DVec3;

use crate::bezier::TriangleBezier;
use crate::error::{Error, Result};
use crate::geom::Aabb;
use crate::mesh::Mesh;
use crate::render::bvh::SubdivisionCriterion;
use crate::render::camera::{Camera, Projection};
use crate::render::curves::CurveOverlay;
use crate::render::film::{Frame, RenderSettings, render};
use crate::render::intersect::{NewtonSettings, Tracer};
use crate::render::stats::RenderStats;
use crate::render::tessellate::TessellatedTracer;
use crate::surface::{PatchGeometry, Surface};

/// Default vertical field of view, degrees.
pub const DEFAULT_FOV: f64 = 35.0;

/// Points on `surface` (each patch on a 7×7 grid of its domain) for tight framing.
pub fn surface_samples(surface: &Surface) -> Vec<DVec3> {
    const N: u32 = 6;
    let mut points = Vec::with_capacity(surface.patches.len() * 28);
    for patch in &surface.patches {
        for j in 0..=N {
            for i in 0..=N - j {
                points.push(patch.eval(f64::from(i) / f64::from(N), f64::from(j) / f64::from(N)));
            }
        }
    }
    points
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
        let samples = surface_samples(surface);
        let bounds = &Aabb::from_points(&samples);
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
pub const DEFAULT_MAX_LEAVES: u64 = 1 << 24;

/// What the rays meet: the exact patches (through a BVH of subdivided patch bounds) or a
/// tessellation of them.
#[derive(Clone, Debug, PartialEq)]
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

impl RenderJob {
    /// The camera this job renders `surface` with (as [`RenderJob::render`] computes it).
    pub fn camera_of(&self, surface: &Surface) -> Result<Camera> {
        let aspect = f64::from(self.settings.width) / f64::from(self.settings.height);
        self.camera.camera(surface, aspect)
    }

    /// Renders `surface` (built on `mesh`) with this job's camera, settings and curves.
    pub fn render(&self, surface: &Surface, mesh: &Mesh) -> Result<(Frame, RenderStats)> {
        let mut settings = self.settings.clone();
        settings.curves = self.curves.tubes(surface, mesh)?;
        let aspect = f64::from(settings.width) / f64::from(settings.height);
        let camera = self.camera.camera(surface, aspect)?;
        match &self.geometry {
            Geometry::Tessellated(n) => {
                let tracer = TessellatedTracer::new(surface, *n)?;
                render(&tracer, &camera, &settings)
            }
            Geometry::Exact {
                criterion,
                max_leaves,
            } => {
                check_bvh_size(surface, criterion, *max_leaves)?;
                let tracer = Tracer::new(surface, criterion, NewtonSettings::default())?;
                render(&tracer, &camera, &settings)
            }
        }
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
        .points()
        .iter()
        .map(|p| (*p - a).dot(normal).abs())
        .fold(0.0, f64::max);
    far / size
}

/// An estimate of the BVH leaves `criterion` makes of `surface`, before subdividing anything.
///
/// One 4-split halves a piece and quarters the distance of its net from the corner plane, so
/// the relative flatness halves per level: a patch whose net is `r` from flat reaches
/// `criterion.flatness` after about `log2(r / flatness)` levels (clamped to the criterion's
/// depth range), i.e. `4^depth` leaves. The normal-cone test is not estimated, so this is a
/// lower bound for strongly curved patches.
pub fn estimate_leaves(surface: &Surface, criterion: &SubdivisionCriterion) -> f64 {
    surface
        .patches
        .iter()
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
            4f64.powf(depth)
        })
        .sum()
}

/// Peak bytes per BVH leaf of a patch with `points` control points while the tracer is built:
/// the surface's copy in the unit frame, the leaf records and power forms, the wide BVH and
/// the builder's temporaries. Measured with `cargo run --release --example
/// construction_memory -- SCHEME 6` (peak growth during `Tracer::new`, one leaf per patch):
/// 2,111 B per leaf for `flat` (3 points), 3,492 for `hb` (21 points), 3,123 for `nielson`;
/// this fit, 2000 + 80 per point, is at or above each.
fn leaf_bytes(points: usize) -> f64 {
    (2000 + 80 * points) as f64
}

/// Refuses a BVH that would have more than `max_leaves` leaves or need more memory than is
/// available, by [`estimate_leaves`], before the subdivision allocates anything.
pub fn check_bvh_size(
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
