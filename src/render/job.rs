//! One render job from a parsed scene: camera resolution, tracer construction (exact or
//! tessellated), rendering. Shared by the `render` command and the gallery.

use glam::DVec3;

use crate::error::{Error, Result};
use crate::geom::Aabb;
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

/// The camera of `scene` for a surface with `bounds` and an image of aspect `aspect`: the
/// scene's eye/target/up when an eye is given, automatic framing otherwise.
pub fn scene_camera(scene: &SceneFile, bounds: &Aabb, aspect: f64) -> Result<Camera> {
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
            let framed = Camera::frame(bounds, Camera::DEFAULT_VIEW, fov, aspect)?;
            if let Some(target) = c.target {
                // Same view direction and distance as the automatic framing, around `target`.
                let target = DVec3::from_array(target);
                Camera::look_at(
                    framed.eye - bounds.center() + target,
                    target,
                    c.up.map_or(DVec3::Y, DVec3::from_array),
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

/// Renders `surface` as `scene` describes (exact patches, or a tessellation when
/// `render.tessellate` is set).
pub fn render_scene(surface: &Surface, scene: &SceneFile) -> Result<(Frame, RenderStats)> {
    let settings = scene_settings(scene)?;
    let aspect = f64::from(settings.width) / f64::from(settings.height);
    let camera = scene_camera(scene, &surface.bounds(), aspect)?;
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
