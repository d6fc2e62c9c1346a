//! The exact renderer: Bézier patches are ray-traced directly (BVH over subdivided patch bounds,
//! Newton in f64, no tessellation), so reflection lines, isophotes and curvature are computed
//! from the surface itself at every pixel.
//!
//! Pipeline: [`intersect::Tracer`] (BVH of [`bvh`] + Newton of [`intersect`]) → [`film::render`]
//! (camera rays, stratified supersampling, a [`modes::Mode`]) → [`output`] (PNG + EXR) and
//! [`stats::RenderStats`].

pub mod bvh;
pub mod camera;
pub mod curves;
pub mod environment;
pub(crate) mod evaluate;
pub mod film;
pub mod interaction;
pub mod intersect;
pub mod job;
pub mod modes;
pub(crate) mod newton;
pub mod output;
pub mod ray;
pub mod sampler;
pub mod shaded;
pub mod stats;
pub mod tessellate;
pub mod theme;
pub mod trace;
pub(crate) mod tubes;

pub use camera::{Camera, Projection};
pub use film::{Frame, PixelGeometry, RenderSettings, render};
pub use intersect::{Hit, NewtonSettings, Ray64, Tracer};
pub use job::{CameraSpec, Geometry, RenderJob};
pub use modes::Mode;
pub use stats::RenderStats;
pub use theme::{Legend, LegendStyle, Theme};
pub use trace::SurfaceTracer;
