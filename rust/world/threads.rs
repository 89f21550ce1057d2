//! The worker threads a world (or a batch of worlds) may use: `Settings::threads`
//! resolved to a count, and one rayon pool per count, shared by every world
//! that asks for it (a pool per world would start threads per build).
//!
//! Whatever runs in parallel gives the same bits for every count: work is split
//! into pieces whose arithmetic does not depend on the split (one body, one
//! world) and results land where the serial loop would put them.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

use rayon::{ThreadPool, ThreadPoolBuilder};

use crate::error::{Error, Result};

/// `None` → every core the process may use (`available_parallelism`, 1 when unknown).
pub fn resolve(threads: Option<u32>) -> usize {
    match threads {
        Some(n) => n.max(1) as usize,
        None => {
            // Asked once: it reads the process's CPU set and cgroup quota.
            static CORES: OnceLock<usize> = OnceLock::new();
            *CORES.get_or_init(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
        }
    }
}

/// The shared pool of `n` threads (made on first use).
pub fn pool(n: usize) -> Result<Arc<ThreadPool>> {
    static POOLS: OnceLock<Mutex<HashMap<usize, Arc<ThreadPool>>>> = OnceLock::new();
    let pools = POOLS.get_or_init(Default::default);
    // A poisoned lock only means another thread panicked while inserting: the
    // map itself is still a valid map.
    let mut map = pools.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(p) = map.get(&n) {
        return Ok(p.clone());
    }
    let p = ThreadPoolBuilder::new()
        .num_threads(n)
        .thread_name(|i| format!("rigidrs-{i}"))
        .build()
        .map_err(|e| Error::input(format!("could not start {n} worker threads: {e}")))?;
    let p = Arc::new(p);
    map.insert(n, p.clone());
    Ok(p)
}

/// Runs `f` on the pool of `n` threads (its parallel iterators use those
/// threads, one for `n` = 1), or right here when this thread already belongs
/// to a pool (a world stepped inside a batch uses the batch's threads).
pub fn install<R: Send>(n: usize, f: impl FnOnce() -> R + Send) -> R {
    if rayon::current_thread_index().is_some() {
        return f();
    }
    match pool(n) {
        Ok(p) => p.install(f),
        Err(_) => f(), // no threads to be had: the serial loop gives the same bits
    }
}

impl super::World {
    /// Sets the worker threads (≥ 1) of this world's parallel stages: not
    /// state, as every count gives the same bits.
    pub fn set_threads(&mut self, n: u32) {
        self.settings.threads = Some(n.max(1));
    }
}
