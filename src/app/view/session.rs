//! The view's state and its frame scheduling: the surfaces built so far (one per scheme and
//! parameters asked for, each with its tracer), the settings the page asked for last, and the
//! one render worker that turns them into frames.
//!
//! Scheduling: every new setting from the page gets the next *generation*. The worker renders
//! the newest generation in three passes — a coarse frame (¼ of the size each way, one sample
//! per pixel), the full size at one sample, then the job's own samples per pixel (the
//! converged frame, the one `smoothlab render` of the saved scene gives) — and asks between
//! tiles whether the generation is still the newest ([`RenderJob::render_with`]); a frame of
//! an old camera is dropped within a tile's time instead of being finished. There is no queue:
//! a page that sends ten cameras while one frame renders gets frames of the last.

use std::collections::HashMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard, PoisonError};
use std::time::{Duration, Instant};

use crate::app::scene::SceneFile;
use crate::app::view::scene::BaseScene;
use crate::error::{Error, Problem, Result};
use crate::mesh::Mesh;
use crate::render::Frame;
use crate::render::interaction::ShadingPoint;
use crate::render::job::{JobTracer, RenderJob};
use crate::surface::Surface;

/// The most surfaces (schemes with their parameters) one view builds and keeps.
pub(crate) const MAX_SURFACES: usize = 8;

/// Side divisor of the coarse pass.
const COARSE: u32 = 4;

/// A scheme's name and its parameters (sorted by name): which surface a view renders.
pub(crate) type SchemeKey = (String, Vec<(String, String)>);

/// A surface of the view with its tracer. Both live as long as the process: a view keeps
/// every surface it built so that switching back to a scheme costs nothing, and their number
/// is bounded by [`MAX_SURFACES`].
pub(crate) struct Built {
    /// The surface.
    pub surface: &'static Surface,
    /// Its tracer (the base scene's geometry and BVH settings).
    pub tracer: JobTracer<'static>,
    /// Milliseconds the scheme took to build.
    pub build_ms: f64,
    /// Milliseconds the tracer took to build.
    pub tracer_ms: f64,
    /// The joints of the surface by the patch edges on either side, for the probe.
    pub joints: super::JointIndex,
}

/// What the page asked for: the merged scene table and its job, of one generation.
#[derive(Clone)]
pub(crate) struct Wanted {
    /// Generation (1, 2, …).
    pub generation: u64,
    /// The merged scene keys.
    pub table: toml::Table,
    /// The scheme and its parameters.
    pub scheme: SchemeKey,
    /// The validated job (the back faces tinted on an open mesh, as `render` does).
    pub job: RenderJob,
}

/// A finished frame as the page gets it.
#[derive(Clone)]
pub(crate) struct Published {
    /// Running number of published frames (1, 2, …).
    pub seq: u64,
    /// The generation it shows.
    pub generation: u64,
    /// Pass: 0 coarse, 1 full size at one sample, 2 converged.
    pub level: u8,
    /// Size in pixels.
    pub width: u32,
    /// Size in pixels.
    pub height: u32,
    /// Milliseconds from the generation's request to this frame's PNG.
    pub since_request_ms: f64,
    /// Milliseconds this pass took to render.
    pub render_ms: f64,
    /// The PNG bytes.
    pub png: Arc<Vec<u8>>,
}

/// The shared state of a view.
pub(crate) struct Session {
    /// The scene the command was started with.
    pub base: BaseScene,
    /// The mesh.
    pub mesh: &'static Mesh,
    /// Newest generation asked for (read by the render between tiles).
    generation: AtomicU64,
    state: Mutex<State>,
    /// Held while a surface is built, so that two requests never build the same one twice.
    building: Mutex<()>,
    /// Signalled when a request or a frame arrives.
    changed: Condvar,
}

struct State {
    wanted: Option<(Wanted, Instant)>,
    built: HashMap<SchemeKey, Arc<Built>>,
    latest: Option<Published>,
    /// The converged frame of the newest generation that has one.
    converged: Option<(u64, Arc<Frame>)>,
    /// The error of the newest generation's render, if it failed.
    error: Option<(u64, String)>,
    seq: u64,
}

/// `m` locked, also after a panic in another thread (the state stays consistent: every
/// change is one assignment).
fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(PoisonError::into_inner)
}

/// The scheme name and parameters of a scene.
pub(crate) fn scheme_of(scene: &SceneFile) -> Result<SchemeKey> {
    let name = scene.scheme.name.clone().ok_or_else(|| {
        Error::config(
            "scheme.name (--scheme)",
            Problem::Stated {
                message: format!(
                    "no scheme given: pass --scheme NAME (one of {}) or set [scheme] name in the \
                     scene",
                    crate::schemes::names().join(", ")
                ),
            },
        )
    })?;
    crate::schemes::find(&name)?;
    let mut params = scene.scheme_params();
    params.sort();
    Ok((name, params))
}

impl Session {
    /// A view of `mesh` starting from `base`.
    pub(crate) fn new(base: BaseScene, mesh: Mesh) -> Session {
        Session {
            base,
            mesh: Box::leak(Box::new(mesh)),
            generation: AtomicU64::new(0),
            state: Mutex::new(State {
                wanted: None,
                built: HashMap::new(),
                latest: None,
                converged: None,
                error: None,
                seq: 0,
            }),
            building: Mutex::new(()),
            changed: Condvar::new(),
        }
    }

    /// The surface and tracer of `scheme` with its parameters, built on first use with the
    /// job's geometry (at most [`MAX_SURFACES`] of them).
    pub(crate) fn built(&self, scheme: &SchemeKey, job: &RenderJob) -> Result<Arc<Built>> {
        if let Some(b) = lock(&self.state).built.get(scheme) {
            return Ok(b.clone());
        }
        let _one_build_at_a_time = lock(&self.building);
        if let Some(b) = lock(&self.state).built.get(scheme) {
            return Ok(b.clone());
        }
        if lock(&self.state).built.len() >= MAX_SURFACES {
            return Err(Error::Invalid(format!(
                "this view has built {MAX_SURFACES} surfaces, the most it keeps: restart it to \
                 compare others"
            )));
        }
        let start = Instant::now();
        let surface: &'static Surface = Box::leak(Box::new(crate::schemes::build(
            &scheme.0, self.mesh, &scheme.1,
        )?));
        let build_ms = start.elapsed().as_secs_f64() * 1e3;
        let start = Instant::now();
        let tracer = job.tracer(surface)?;
        let tracer_ms = start.elapsed().as_secs_f64() * 1e3;
        let built = Arc::new(Built {
            surface,
            tracer,
            build_ms,
            tracer_ms,
            joints: super::JointIndex::new(surface, self.mesh),
        });
        lock(&self.state)
            .built
            .insert(scheme.clone(), built.clone());
        Ok(built)
    }

    /// Checks the page's `settings` and makes them the newest generation; returns it. The
    /// render of an older generation stops at its next tile.
    pub(crate) fn request(&self, settings: &serde_json::Value) -> Result<Wanted> {
        let (table, scene, job) = self.base.with_page(settings)?;
        let scheme = scheme_of(&scene)?;
        let mut job = job.for_mesh(self.mesh);
        job.settings.progress = false;
        let mut state = lock(&self.state);
        let generation = self.generation.fetch_add(1, Ordering::SeqCst) + 1;
        let wanted = Wanted {
            generation,
            table,
            scheme,
            job,
        };
        state.wanted = Some((wanted.clone(), Instant::now()));
        drop(state);
        self.changed.notify_all();
        Ok(wanted)
    }

    /// The newest request, if any.
    pub(crate) fn wanted(&self) -> Option<Wanted> {
        lock(&self.state).wanted.as_ref().map(|(w, _)| w.clone())
    }

    /// The first published frame with a sequence number above `after`, waiting up to
    /// `timeout` for it; also returns the newest render error, if any.
    pub(crate) fn frame_after(
        &self,
        after: u64,
        timeout: Duration,
    ) -> (Option<Published>, Option<String>) {
        let deadline = Instant::now() + timeout;
        let mut state = lock(&self.state);
        loop {
            let newest = self.generation.load(Ordering::SeqCst);
            if let Some((g, e)) = &state.error
                && *g == newest
            {
                return (None, Some(e.clone()));
            }
            if let Some(p) = &state.latest
                && p.seq > after
            {
                return (Some(p.clone()), None);
            }
            let now = Instant::now();
            if now >= deadline {
                return (None, None);
            }
            state = self
                .changed
                .wait_timeout(state, deadline - now)
                .unwrap_or_else(PoisonError::into_inner)
                .0;
        }
    }

    /// The exact hit under image point `(x, y)` (pixels of the full-size frame) of the
    /// newest request.
    pub(crate) fn probe(
        &self,
        x: f64,
        y: f64,
    ) -> Result<(Wanted, Option<ShadingPoint>, Option<super::JointUnder>)> {
        let wanted = self
            .wanted()
            .ok_or_else(|| Error::Invalid("nothing is shown yet".into()))?;
        let built = self.built(&wanted.scheme, &wanted.job)?;
        let sp = wanted.job.probe(&built.tracer, x, y)?;
        let joint = match &sp {
            Some(sp) => built.joints.near(&wanted.job, built.surface, x, y, sp)?,
            None => None,
        };
        Ok((wanted, sp, joint))
    }

    /// The converged frame of `wanted`: the one rendered for the page if it is of that
    /// generation, else rendered now (never cancelled).
    pub(crate) fn converged(&self, wanted: &Wanted) -> Result<Arc<Frame>> {
        if let Some((g, frame)) = &lock(&self.state).converged
            && *g == wanted.generation
        {
            return Ok(frame.clone());
        }
        let built = self.built(&wanted.scheme, &wanted.job)?;
        let (frame, _) = wanted
            .job
            .render_with(&built.tracer, self.mesh, &|| false)?
            .ok_or_else(|| Error::Invalid("a render that cannot be cancelled was".into()))?;
        Ok(Arc::new(frame))
    }

    /// The render worker: runs for the life of the process, rendering the passes of the
    /// newest generation as frames for the page.
    pub(crate) fn run_worker(&self) {
        let mut done = 0u64;
        loop {
            let (wanted, since) = {
                let mut state = lock(&self.state);
                loop {
                    match &state.wanted {
                        Some((w, t)) if w.generation > done => break (w.clone(), *t),
                        _ => {
                            state = self
                                .changed
                                .wait(state)
                                .unwrap_or_else(PoisonError::into_inner);
                        }
                    }
                }
            };
            done = wanted.generation;
            if let Err(e) = self.render_passes(&wanted, since) {
                lock(&self.state).error = Some((wanted.generation, e.to_string()));
                self.changed.notify_all();
            }
        }
    }

    /// The passes of one generation, each published as it is done; stops when a newer
    /// generation is asked for.
    fn render_passes(&self, wanted: &Wanted, since: Instant) -> Result<()> {
        let built = self.built(&wanted.scheme, &wanted.job)?;
        let generation = wanted.generation;
        let cancelled = || self.generation.load(Ordering::SeqCst) != generation;
        // Every pass in the stripes and colours of the full-size view: what the mode chooses
        // from the view (a zebra stripe count, an automatic curvature range) is chosen once,
        // at full size, and the coarse pass takes it.
        let mut job = wanted.job.clone();
        let (w, h, spp) = (job.settings.width, job.settings.height, job.settings.spp);
        let camera = job.camera_of(built.tracer.surface())?;
        job.settings.mode = built.tracer.pin_view(&job.settings.mode, &camera, w, h);
        let job = &job;
        let mut passes: Vec<(u8, u32, u32, u32)> = Vec::new();
        if w >= 2 * COARSE && h >= 2 * COARSE {
            passes.push((0, w / COARSE, h / COARSE, 1));
        }
        if spp > 1 {
            passes.push((1, w, h, 1));
        }
        passes.push((2, w, h, spp));
        for (level, pw, ph, pspp) in passes {
            let mut pass = job.clone();
            (pass.settings.width, pass.settings.height, pass.settings.spp) = (pw, ph, pspp);
            let start = Instant::now();
            let Some((frame, _)) = pass.render_with(&built.tracer, self.mesh, &cancelled)? else {
                return Ok(());
            };
            let render_ms = start.elapsed().as_secs_f64() * 1e3;
            let png = super::png_bytes(&frame)?;
            let mut state = lock(&self.state);
            if cancelled() {
                return Ok(());
            }
            state.seq += 1;
            state.latest = Some(Published {
                seq: state.seq,
                generation,
                level,
                width: pw,
                height: ph,
                since_request_ms: since.elapsed().as_secs_f64() * 1e3,
                render_ms,
                png: Arc::new(png),
            });
            if level == 2 {
                state.converged = Some((generation, Arc::new(frame)));
            }
            drop(state);
            self.changed.notify_all();
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::test_support::assert_config_error;

    /// A scene without a scheme is a configuration error of `scheme.name`, worded as before.
    #[test]
    fn no_scheme_is_a_config_error() {
        let scene = SceneFile::parse("mesh = \"m.obj\"\n").expect("scene");
        let err = scheme_of(&scene).expect_err("no scheme");
        assert_config_error(
            &err,
            "scheme.name (--scheme)",
            |p| matches!(p, Problem::Stated { .. }),
            format!(
                "no scheme given: pass --scheme NAME (one of {}) or set [scheme] name in the scene",
                crate::schemes::names().join(", ")
            ),
        );
    }
}
