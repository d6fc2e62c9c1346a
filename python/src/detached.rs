//! Long calls run without the interpreter: the work goes to a thread of its own while the
//! calling thread, detached from Python, waits for it and every [`POLL`] attaches again to let
//! Python run its signal handlers (Ctrl-C). An interrupt sets the work's cancel flag and the
//! call raises the handler's exception (`KeyboardInterrupt`).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex};
use std::time::Duration;

use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;

/// How often the waiting thread lets Python check for signals.
const POLL: Duration = Duration::from_millis(25);

/// What to do with the work when an interrupt arrives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum OnInterrupt {
    /// Wait for the work to see the cancel flag and stop (renders: they stop between tiles,
    /// and nothing they write is begun after the flag is set).
    Join,
    /// Return at once; the work finishes in the background and its result is dropped (builds
    /// and metrics, which cannot stop half-way).
    Abandon,
}

/// The completion signal of one piece of work.
#[derive(Default)]
struct Done {
    finished: Mutex<bool>,
    woken: Condvar,
}

impl Done {
    fn set(&self) {
        *self
            .finished
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner) = true;
        self.woken.notify_all();
    }

    /// Waits up to `timeout`; true if the work has finished.
    fn wait(&self, timeout: Duration) -> bool {
        let guard = self
            .finished
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let (guard, _) = self
            .woken
            .wait_timeout_while(guard, timeout, |finished| !*finished)
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        *guard
    }
}

/// Runs `work` on a thread of its own with the interpreter released, answering Python's
/// signal handlers meanwhile. `work` gets the cancel flag, set when a handler raised (the
/// exception is then returned). A panic of the work is a `RuntimeError`.
pub(crate) fn run<T, F>(py: Python<'_>, on_interrupt: OnInterrupt, work: F) -> PyResult<T>
where
    T: Send + 'static,
    F: FnOnce(&AtomicBool) -> T + Send + 'static,
{
    let cancel = Arc::new(AtomicBool::new(false));
    let done = Arc::new(Done::default());
    let handle = {
        let (cancel, done) = (Arc::clone(&cancel), Arc::clone(&done));
        std::thread::Builder::new()
            .name("smoothlab".into())
            .spawn(move || {
                // Set also when the work panics, so that the waiting thread wakes.
                struct SetOnDrop(Arc<Done>);
                impl Drop for SetOnDrop {
                    fn drop(&mut self) {
                        self.0.set();
                    }
                }
                let _set = SetOnDrop(done);
                work(&cancel)
            })
            .map_err(|e| PyRuntimeError::new_err(format!("cannot start a thread: {e}")))?
    };
    loop {
        if py.detach(|| done.wait(POLL)) {
            break;
        }
        if let Err(interrupt) = py.check_signals() {
            cancel.store(true, Ordering::SeqCst);
            if on_interrupt == OnInterrupt::Join {
                // The result of a cancelled render is dropped either way.
                let _ = py.detach(|| handle.join());
            }
            return Err(interrupt);
        }
    }
    py.detach(|| handle.join()).map_err(|panic| {
        let what = panic
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| panic.downcast_ref::<&str>().copied())
            .unwrap_or("unknown panic");
        PyRuntimeError::new_err(format!("smoothlab failed internally: {what}"))
    })
}
