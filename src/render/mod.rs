//! The exact renderer: Bézier patches are ray-traced directly (BVH over subdivided patch bounds,
//! Newton in f64, no tessellation), so reflection lines, isophotes and curvature are computed
//! from the surface itself at every pixel.
//!
//! Pipeline: [`intersect::Tracer`] (BVH of [`bvh`] + Newton of [`intersect`]) → [`film::render`]
//! (camera rays, stratified supersampling, a [`modes::Mode`]) → [`output`] (PNG + EXR) and
//! [`stats::RenderStats`].

pub(crate) mod bundle;
pub(crate) mod bvh;
pub(crate) mod camera;
pub(crate) mod curves;
pub(crate) mod environment;
pub(crate) mod evaluate;
pub(crate) mod film;
pub(crate) mod interaction;
pub(crate) mod intersect;
pub(crate) mod job;
pub mod modes;
pub(crate) mod newton;
pub mod output;
pub(crate) mod ray;
pub(crate) mod sampler;
pub(crate) mod shaded;
pub(crate) mod stats;
pub(crate) mod tessellate;
pub(crate) mod theme;
pub(crate) mod trace;
pub(crate) mod tubes;

pub use bundle::BundleScratch;
pub use camera::{Camera, Projection};
pub use environment::Environment;
pub use film::{Frame, PixelGeometry, RenderSettings, check_frame_memory, render};
pub use intersect::{Hit, IntersectCounters, NewtonSettings, Tracer};
pub use job::{CameraSpec, Geometry, RenderJob, SurfaceSamples};
pub use modes::Mode;
pub use ray::Ray64;
pub use stats::RenderStats;
pub use theme::{Legend, LegendStyle, Theme};
pub use trace::SurfaceTracer;
