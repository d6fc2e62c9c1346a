//! One render job from a parsed scene: camera resolution, tracer construction (exact or
//! tessellated), rendering. Shared by the `render` command and the gallery.

use glam::DVec3;

use crate::error::{Error, Result};
use crate::geom::Aabb;
use crate::mesh::Mesh;
use crate::render::camera::{Camera, Projection};
use crate::render::film::{Frame, RenderSettings, render};
use crate::render::intersect::{NewtonSettings, Tracer};
use crate::render::scene::SceneFile;
use crate::render::stats::RenderStats;
use crate::render::tessellate::TessellatedTracer;
use crate::surface::Surface;

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
            let tracer = Tracer::new(surface, &scene.criterion()?, NewtonSettings::default())?;
            render(&tracer, &camera, &settings)
        }
    }
}
