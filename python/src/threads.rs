//! Rayon's threads in a process forked from the one that imported the
//! package. The host's parallel loops run on rayon's global pool, whose
//! threads a `fork` does not copy: a child forked after the parent used the
//! pool (a batch, then `multiprocessing`'s default "fork" pool, or
//! `ProcessPoolExecutor` on Linux) would hand its first loop to threads
//! that do not exist and wait for ever. In such a child every command runs
//! in a pool of its own, made on first use; the importing process and
//! every spawned one (Dask's workers) keep the global pool.

use pyo3::Python;
use std::sync::{Arc, Mutex, OnceLock};

/// The process that imported the extension.
static IMPORTED_BY: OnceLock<u32> = OnceLock::new();

/// The pool of a forked process, with its process id (a grandchild forked
/// from it makes its own).
static FORKED_POOL: Mutex<Option<(u32, Arc<rayon::ThreadPool>)>> = Mutex::new(None);

/// Notes the importing process (the module's initialisation).
pub(crate) fn imported() {
    let _ = IMPORTED_BY.set(std::process::id());
}

/// `f` with the GIL released, on the threads of this process:
/// [`Python::allow_threads`] with the pool of a forked process installed.
pub(crate) fn allow<T: Send>(py: Python<'_>, f: impl FnOnce() -> T + Send) -> T {
    py.allow_threads(|| in_this_process(f))
}

fn in_this_process<T: Send>(f: impl FnOnce() -> T + Send) -> T {
    let pid = std::process::id();
    if IMPORTED_BY.get().is_none_or(|&p| p == pid) {
        return f();
    }
    let pool = {
        let mut slot = FORKED_POOL
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        match &*slot {
            Some((p, pool)) if *p == pid => Some(pool.clone()),
            _ => match rayon::ThreadPoolBuilder::new().build() {
                Ok(pool) => {
                    let pool = Arc::new(pool);
                    *slot = Some((pid, pool.clone()));
                    Some(pool)
                }
                Err(_) => None,
            },
        }
    };
    match pool {
        Some(pool) => pool.install(f),
        // No thread could be started: the loops would wait as before; say
        // nothing more here than the command's own error would.
        None => f(),
    }
}
