//! A second thread kept spinning through a step, so that a pass over two
//! halves of the contacts (see [`super::seams`]) hands one half over in well
//! under a microsecond. Rayon's hand-off, a sleeping worker woken for each of
//! a substep's passes (30–60 µs of work each), made the 1000-ball pit's warm
//! start and velocity passes 1.9× slower on two threads than on one (935
//! against 501 µs a step).
//!
//! The helper is a task on the world's pool, alive while [`with_team`] runs.
//! A half it has not taken when the caller's half is done is taken back and
//! run by the caller: a helper that never started (its pool busy elsewhere)
//! costs nothing, and which thread runs a half never changes its arithmetic.
//! While it spins, the pool's other parallel loops of the step run on the
//! stepping thread alone.

use std::cell::{Cell, UnsafeCell};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::Mutex;

/// Nothing posted.
const IDLE: u8 = 0;
/// A job posted, not taken.
const POSTED: u8 = 1;
/// The helper is running the job.
const TAKEN: u8 = 2;
/// The helper finished the job.
const DONE: u8 = 3;
/// The helper's job panicked.
const FAILED: u8 = 4;
/// The helper is to return.
const STOP: u8 = 5;

/// The mailbox between the thread that steps and its helper.
struct Team {
    state: AtomicU8,
    /// The posted job, valid while `state` is `POSTED` or `TAKEN`.
    job: UnsafeCell<Option<*const (dyn Fn() + Sync)>>,
}

// SAFETY: `job` is written only by the posting thread while no job is
// posted, and read only by the thread that took it (the state's
// acquire/release orders the two).
unsafe impl Sync for Team {}

thread_local! {
    /// The team of the step running on this thread, if any.
    static CURRENT: Cell<*const Team> = const { Cell::new(std::ptr::null()) };
}

/// Runs `f` with a helper on the current rayon pool when `on` (the caller is
/// on the pool's threads); [`both`] called within `f` then runs its second
/// half on the helper. The helper spins until `f` returns.
pub(crate) fn with_team<R: Send>(on: bool, f: impl FnOnce() -> R + Send) -> R {
    if !on || active() || rayon::current_num_threads() < 2 {
        return f();
    }
    let team = Team { state: AtomicU8::new(IDLE), job: UnsafeCell::new(None) };
    rayon::scope(|s| {
        s.spawn(|_| team.serve());
        // Stops the helper however `f` ends (a panic included: the scope
        // would wait for it forever).
        struct Stop<'a>(&'a Team, *const Team);
        impl Drop for Stop<'_> {
            fn drop(&mut self) {
                CURRENT.with(|c| c.set(self.1));
                self.0.state.store(STOP, Ordering::Release);
            }
        }
        let _stop = Stop(&team, CURRENT.with(|c| c.replace(&team)));
        f()
    })
}

/// Whether this thread runs a step with a helper (see [`with_team`]).
pub(crate) fn active() -> bool {
    CURRENT.with(|c| !c.get().is_null())
}

/// Runs `a` and `b`, which must touch disjoint data, and returns what they
/// return: `b` on the helper of [`with_team`] when there is one and it is
/// free, else both here, `a` first. Panics if `b` panicked on the helper.
pub(crate) fn both<A, B: Send>(a: impl FnOnce() -> A, b: impl FnOnce() -> B + Send) -> (A, B) {
    let team = CURRENT.with(|c| c.get());
    // SAFETY: a non-null `CURRENT` points to the team of a `with_team` still
    // running on this thread.
    let team = unsafe { team.as_ref() }.filter(|t| t.state.load(Ordering::Acquire) == IDLE);
    let Some(team) = team else {
        let first = a();
        return (first, b());
    };
    let (cell, out) = (Mutex::new(Some(b)), Mutex::new(None));
    let job = || {
        if let Some(b) = lock(&cell).take() {
            *lock(&out) = Some(b());
        }
    };
    let job: *const (dyn Fn() + Sync + '_) = &job;
    // SAFETY: no job is posted (state IDLE), so the helper does not read the
    // slot; the pointer outlives its use: this function waits below until the
    // helper is done with it or takes the job back, even if `a` panics.
    unsafe { *team.job.get() = Some(std::mem::transmute::<*const (dyn Fn() + Sync + '_), *const (dyn Fn() + Sync)>(job)) };
    team.state.store(POSTED, Ordering::Release);
    let first = catch_unwind(AssertUnwindSafe(a));
    let taken_back = team.state.compare_exchange(POSTED, IDLE, Ordering::AcqRel, Ordering::Acquire).is_ok();
    let failed = !taken_back && {
        let mut idle = Idle::default();
        let end = loop {
            match team.state.load(Ordering::Acquire) {
                TAKEN => idle.wait(),
                s => break s,
            }
        };
        team.state.store(IDLE, Ordering::Release);
        end == FAILED
    };
    let first = first.unwrap_or_else(|e| std::panic::resume_unwind(e));
    if failed {
        panic!("a contact pass on the second thread panicked");
    }
    if let Some(b) = lock(&cell).take() {
        return (first, b());
    }
    let second = lock(&out).take();
    match second {
        Some(second) => (first, second),
        None => panic!("a contact pass on the second thread returned nothing"),
    }
}

/// A lock whatever a panic left in it (what it guards is taken whole).
fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

impl Team {
    /// The helper's loop: takes posted jobs until told to stop.
    fn serve(&self) {
        let mut idle = Idle::default();
        loop {
            match self.state.load(Ordering::Acquire) {
                STOP => return,
                POSTED if self.state.compare_exchange(POSTED, TAKEN, Ordering::AcqRel, Ordering::Acquire).is_ok() => {
                    // SAFETY: the job was posted before the state (release) and
                    // stays valid until the state leaves TAKEN.
                    let ok = match unsafe { *self.job.get() } {
                        Some(job) => catch_unwind(AssertUnwindSafe(|| unsafe { (*job)() })).is_ok(),
                        None => true,
                    };
                    let end = if ok { DONE } else { FAILED };
                    // A stop while it ran (the caller unwinding) stays a stop.
                    let _ = self.state.compare_exchange(TAKEN, end, Ordering::AcqRel, Ordering::Acquire);
                    idle = Idle::default();
                }
                _ => idle.wait(),
            }
        }
    }
}

/// Spins of a wait after which it yields its core at every turn: a pool
/// larger than the machine's cores (or a busy machine) must not lose a
/// scheduler's time slice to a thread spinning for one that is not running.
const SPINS: u32 = 4096;

/// A wait: spinning, then yielding.
#[derive(Default)]
struct Idle(u32);

impl Idle {
    fn wait(&mut self) {
        if self.0 < SPINS {
            self.0 += 1;
            std::hint::spin_loop();
        } else {
            std::thread::yield_now();
        }
    }
}



#[cfg(test)]
mod tests {
    use super::{both, with_team};
    use std::sync::atomic::{AtomicUsize, Ordering};

    /// On a pool of its own (the shared ones are busy with other tests).
    fn on_two_threads<R: Send>(f: impl FnOnce() -> R + Send) -> R {
        match rayon::ThreadPoolBuilder::new().num_threads(2).build() {
            Ok(pool) => pool.install(f),
            Err(e) => panic!("no pool: {e}"),
        }
    }

    /// Both halves run and return, the second on the helper when it is
    /// free: the first half waits (up to a second) for the second to start,
    /// which only the helper can do meanwhile.
    #[test]
    fn both_halves_run_and_the_second_goes_to_the_helper() {
        let (helped, sum) = (AtomicUsize::new(0), AtomicUsize::new(0));
        on_two_threads(|| {
            with_team(true, || {
                let me = std::thread::current().id();
                for k in 0..200 {
                    let started = std::sync::atomic::AtomicBool::new(false);
                    let wait = || {
                        let t0 = std::time::Instant::now();
                        while !started.load(Ordering::Acquire) && t0.elapsed().as_secs_f64() < 1.0 {
                            std::hint::spin_loop();
                        }
                        k
                    };
                    let second = || {
                        started.store(true, Ordering::Release);
                        sum.fetch_add(k, Ordering::Relaxed);
                        helped.fetch_add((std::thread::current().id() != me) as usize, Ordering::Relaxed);
                        2 * k
                    };
                    assert_eq!(both(wait, second), (k, 2 * k));
                }
            })
        });
        assert_eq!(sum.load(Ordering::Relaxed), 199 * 200 / 2);
        assert!(helped.load(Ordering::Relaxed) >= 190, "the helper took {} halves of 200", helped.load(Ordering::Relaxed));
    }

    /// A panic in either half reaches the caller as a panic (no hang, no
    /// second half left running on borrowed data), and the team still works.
    #[test]
    fn a_panicking_half_panics_the_caller_and_the_team_goes_on() {
        let ok = AtomicUsize::new(0);
        on_two_threads(|| {
            with_team(true, || {
                for k in 0..50 {
                    let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                        both(|| (), || if k % 2 == 0 { panic!("second") });
                    }));
                    assert_eq!(r.is_err(), k % 2 == 0);
                    let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| both(|| if k % 3 == 0 { panic!("first") }, || ())));
                    assert_eq!(r.is_err(), k % 3 == 0);
                    both(|| (), || {
                        ok.fetch_add(1, Ordering::Relaxed);
                    });
                }
            })
        });
        assert_eq!(ok.load(Ordering::Relaxed), 50);
    }

    /// Outside a team (or on one thread) both halves run here, in order.
    #[test]
    fn without_a_team_the_halves_run_here_in_order() {
        let order = std::sync::Mutex::new(Vec::new());
        both(|| order.lock().unwrap().push(1), || order.lock().unwrap().push(2));
        crate::world::threads::install(1, || with_team(true, || both(|| order.lock().unwrap().push(3), || order.lock().unwrap().push(4))));
        assert_eq!(*order.lock().unwrap(), vec![1, 2, 3, 4]);
    }
}
