//! Timing one setting on one scene: every timed render runs alone inside a rayon pool of
//! one thread, so methods whose inner loops use rayon are timed sequentially and timings
//! compare. The figure is the median of the runs' thread CPU time (wall clock where the
//! platform has no thread clock), with the wall-clock median beside it.

use std::time::Instant;

use pixelproc_sim::aa::{render_aa, AaError, AaMethod};

use crate::scenes::TestScene;
use crate::TradeoffError;

/// Median times of the timed renders of one setting on one scene, seconds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Timing {
    /// Median CPU time of the rendering thread.
    pub cpu: f64,
    /// Median wall-clock time.
    pub wall: f64,
}

/// A rayon pool of one thread for the timed renders.
pub fn one_thread_pool() -> Result<rayon::ThreadPool, TradeoffError> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .map_err(|e| TradeoffError::Option(format!("thread pool: {e}")))
}

/// The most timed runs a measurement takes (`--runs`): a median of more says nothing new,
/// and each run's figures are kept until the median is taken.
pub const MAX_RUNS: usize = 10_000;

/// Checks `runs` as a count of timed runs, `1 ..= MAX_RUNS`; else the one-line reason.
pub fn check_runs(runs: usize) -> Result<(), String> {
    if (1..=MAX_RUNS).contains(&runs) {
        Ok(())
    } else {
        Err(format!("--runs {runs} is outside 1..={MAX_RUNS}"))
    }
}

/// Renders `sc` with `aa` `runs` times inside `one` and returns the median times.
pub fn time_setting(
    one: &rayon::ThreadPool,
    sc: &TestScene,
    aa: &AaMethod,
    runs: usize,
) -> Result<Timing, AaError> {
    let mut times = Vec::with_capacity(runs);
    let mut walls = Vec::with_capacity(runs);
    for _ in 0..runs {
        let (cpu, wall) = one.install(|| {
            let (c0, t0) = (thread_cpu_seconds(), Instant::now());
            let g = render_aa(&sc.tris, sc.width, sc.height, sc.bg, aa);
            let (c1, dt) = (thread_cpu_seconds(), t0.elapsed().as_secs_f64());
            std::hint::black_box(&g);
            g.map(|_| (c0.zip(c1).map_or(dt, |(a, b)| b - a), dt))
        })?;
        times.push(cpu);
        walls.push(wall);
    }
    Ok(Timing {
        cpu: median(times),
        wall: median(walls),
    })
}

/// CPU time consumed by the calling thread, seconds.
#[cfg(unix)]
pub(crate) fn thread_cpu_seconds() -> Option<f64> {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec; the clock id is a constant.
    let r = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    (r == 0).then_some(ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9)
}

/// No thread clock: the caller falls back to wall-clock time.
#[cfg(not(unix))]
pub(crate) fn thread_cpu_seconds() -> Option<f64> {
    None
}

/// The median (mean of the middle two for an even count; 0 for none).
pub fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n == 0 {
        0.0
    } else if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

#[cfg(test)]
mod tests {
    use super::median;

    #[test]
    fn median_of_odd_even_and_empty() {
        assert_eq!(median(vec![3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(vec![4.0, 1.0, 3.0, 2.0]), 2.5);
        assert_eq!(median(Vec::new()), 0.0);
    }
}
