//! [`Usage`]: the CPU time this process got during a run against the wall time it took,
//! read from `/proc/self/stat` (Linux; elsewhere it is simply unavailable), so that a
//! report says when the machine starved the run.

use std::time::Instant;

use serde::Serialize;

/// Clock ticks per second of `/proc/<pid>/stat`'s times: `USER_HZ`, 100 on every Linux
/// architecture.
const TICKS_PER_S: f64 = 100.0;

/// The CPU time a run got, all of this process's threads together, and its wall time.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Usage {
    /// User plus system CPU time, s.
    pub cpu_s: f64,
    /// Wall time, s.
    pub wall_s: f64,
    /// The cores this process may run on (its affinity and cgroup quota).
    pub cores: usize,
}

impl Usage {
    /// Cores busy on average: CPU time per wall second.
    pub fn busy_cores(&self) -> f64 {
        if self.wall_s > 0.0 {
            self.cpu_s / self.wall_s
        } else {
            0.0
        }
    }

    /// A warning when the process got much less CPU than its work could use: fewer than
    /// half of `min(parallel, cores)` cores busy on average, where `parallel` is how many
    /// of its threads the run can keep simulating at once. The machine was then busy with
    /// other work, and the figures say more about it than about this build.
    pub fn starved(&self, parallel: usize) -> Option<String> {
        let could = parallel.min(self.cores).max(1);
        let busy = self.busy_cores();
        (busy < 0.5 * could as f64).then(|| {
            format!(
                "warning: this process got {:.1} s of CPU in {:.1} s of wall time ({busy:.2} \
                 cores busy on average, where its work could keep {could} of its {} \
                 core(s) busy): the machine was busy with other work, so these figures are \
                 not this build's",
                self.cpu_s, self.wall_s, self.cores
            )
        })
    }
}

/// Measures the CPU time and wall time of `run`; `None` for the usage where
/// `/proc/self/stat` cannot be read.
pub(crate) fn measure<T>(run: impl FnOnce() -> T) -> (T, Option<Usage>) {
    let (cpu0, wall0) = (cpu_seconds(), Instant::now());
    let out = run();
    let usage = match (cpu0, cpu_seconds()) {
        (Some(a), Some(b)) => Some(Usage {
            cpu_s: (b - a).max(0.0),
            wall_s: wall0.elapsed().as_secs_f64(),
            cores: crate::config::threads_or_cores(0),
        }),
        _ => None,
    };
    (out, usage)
}

/// This process's user plus system CPU time so far, s.
fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    parse_stat(&stat)
}

/// `utime + stime` (fields 14 and 15) of a `/proc/<pid>/stat` line, s. The command name
/// (field 2, in parentheses) may hold spaces and parentheses, so fields are counted
/// after its last `)`.
fn parse_stat(stat: &str) -> Option<f64> {
    let rest = &stat[stat.rfind(')')? + 1..];
    let mut fields = rest.split_whitespace();
    // After the name: state (3), ppid (4), …, utime is field 14: the 12th after it.
    let utime: f64 = fields.nth(11)?.parse().ok()?;
    let stime: f64 = fields.next()?.parse().ok()?;
    Some((utime + stime) / TICKS_PER_S)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stat_lines_give_user_plus_system_time() {
        let line = "4242 (gymfleet (load) x) R 1 4242 4242 0 -1 4194304 100 0 0 0 \
                    250 50 0 0 20 0 9 0 123 456 789";
        assert_eq!(parse_stat(line), Some(3.0));
        assert_eq!(parse_stat("garbage"), None);
        assert!(cpu_seconds().is_some(), "this process's own stat reads");
    }

    #[test]
    fn a_starved_run_is_named_and_a_busy_one_is_not() {
        let starved = Usage {
            cpu_s: 1.0,
            wall_s: 19.0,
            cores: 2,
        };
        let warning = starved.starved(2).expect("starved");
        assert!(
            warning.contains("where its work could keep 2 of its 2 core(s) busy"),
            "{warning}"
        );
        assert!(
            warning.starts_with("warning: this process got 1.0 s of CPU in 19.0 s of wall time"),
            "{warning}"
        );
        let busy = Usage {
            cpu_s: 35.0,
            wall_s: 19.0,
            cores: 2,
        };
        assert_eq!(busy.starved(2), None);
        // One thread on two cores needs only one busy core.
        let one = Usage {
            cpu_s: 12.0,
            wall_s: 19.0,
            cores: 2,
        };
        assert_eq!(one.starved(1), None);
    }
}
