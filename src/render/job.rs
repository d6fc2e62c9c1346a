//! One render job from a parsed scene: camera resolution, tracer construction (exact or
//! tessellated), rendering. Shared by the `render` command and the gallery.

use glam::DVec3;

use crate::bezier::TriangleBezier;
use crate::error::{Error, Result};
use crate::geom::Aabb;
use crate::mesh::Mesh;
use crate::render::bvh::{Leaf, SubdivisionCriterion};
use crate::render::camera::{Camera, Projection};
use crate::render::film::{Frame, RenderSettings, render};
use crate::render::intersect::{NewtonSettings, Tracer};
use crate::render::scene::SceneFile;
use crate::render::stats::RenderStats;
use crate::render::tessellate::TessellatedTracer;
use crate::surface::{PatchGeometry, Surface};

/// Default vertical field of view, degrees.
pub const DEFAULT_FOV: f64 = 35.0;
/// Default image size.
pub const DEFAULT_SIZE: [u32; 2] = [640, 480];
/// Default samples per pixel.
pub const DEFAULT_SPP: u32 = 4;

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

/// The camera of `scene` for `surface` and an image of aspect `aspect`: the scene's
/// eye/target/up when an eye is given (target defaults to the surface's centre), automatic
/// framing of points sampled on the surface otherwise (with the scene's up, if given, pointing
/// up in the image; around the scene's target, if given).
pub fn scene_camera(scene: &SceneFile, surface: &Surface, aspect: f64) -> Result<Camera> {
    let samples = surface_samples(surface);
    let bounds = &Aabb::from_points(&samples);
    let c = &scene.camera;
    let fov = c.fov.unwrap_or(DEFAULT_FOV);
    let camera = match c.eye {
        Some(eye) => Camera::look_at(
            DVec3::from_array(eye),
            c.target.map_or(bounds.center(), DVec3::from_array),
            c.up.map_or(DVec3::Y, DVec3::from_array),
            Projection::Perspective { fov_deg: fov },
        )?,
        None => {
            let framed = match c.up {
                Some(up) => Camera::frame_points_with_up(
                    &samples,
                    Camera::DEFAULT_VIEW,
                    DVec3::from_array(up),
                    fov,
                    aspect,
                )?,
                None => Camera::frame_points(&samples, Camera::DEFAULT_VIEW, fov, aspect)?,
            };
            if let Some(target) = c.target {
                // Same view direction, distance and up as the automatic framing, around
                // `target`.
                let target = DVec3::from_array(target);
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
    if c.ortho.unwrap_or(false) {
        camera.orthographic_of(fov)
    } else {
        Ok(camera)
    }
}

/// The render settings of `scene`.
pub fn scene_settings(scene: &SceneFile) -> Result<RenderSettings> {
    let r = &scene.render;
    let [width, height] = r.size.unwrap_or(DEFAULT_SIZE);
    if width == 0 || height == 0 || width > 16384 || height > 16384 {
        return Err(Error::Invalid(format!(
            "render.size {width}x{height} must be between 1 and 16384 per side"
        )));
    }
    let spp = r.spp.unwrap_or(DEFAULT_SPP);
    if spp == 0 || spp > 65536 {
        return Err(Error::Invalid(format!(
            "render.spp {spp} must be in 1..=65536"
        )));
    }
    let mut settings = RenderSettings {
        width,
        height,
        spp,
        mode: scene.mode()?,
        overlay: scene.overlay()?,
        seed: r.seed.unwrap_or(0),
        ..RenderSettings::default()
    };
    if let Some(bg) = r.background {
        if bg.iter().any(|x| !(x.is_finite() && *x >= 0.0)) {
            return Err(Error::Invalid(format!(
                "render.background {bg:?} must be non-negative"
            )));
        }
        settings.background = DVec3::from_array(bg);
    }
    Ok(settings)
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

/// Bytes per BVH leaf of a patch with `points` control points: the leaf record, its
/// power-form coefficients (as many as control points), its share of the wide BVH's nodes
/// and indices and the build's temporary box.
fn leaf_bytes(points: usize) -> f64 {
    (std::mem::size_of::<Leaf>() + 24 * points + 64) as f64
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

/// Renders `surface` (built on `mesh`) as `scene` describes (exact patches, or a tessellation
/// when `render.tessellate` is set), with the curve-network tubes it asks for.
pub fn render_scene(
    surface: &Surface,
    mesh: &Mesh,
    scene: &SceneFile,
) -> Result<(Frame, RenderStats)> {
    let mut settings = scene_settings(scene)?;
    settings.curves = scene.curve_overlay()?.tubes(surface, mesh)?;
    settings.surface = scene.render.surface.unwrap_or(true);
    let aspect = f64::from(settings.width) / f64::from(settings.height);
    let camera = scene_camera(scene, surface, aspect)?;
    match scene.render.tessellate {
        Some(n) => {
            let tracer = TessellatedTracer::new(surface, n)?;
            render(&tracer, &camera, &settings)
        }
        None => {
            let criterion = scene.criterion()?;
            check_bvh_size(surface, &criterion, scene.max_leaves()?)?;
            let tracer = Tracer::new(surface, &criterion, NewtonSettings::default())?;
            render(&tracer, &camera, &settings)
        }
    }
}
