//! The figures of a run and how they are shown: [`RunResult`] (one target), [`Report`]
//! (the configuration, one or two runs, the remote / in-process ratio, memory), the
//! stdout table ([`render_table`]) and the JSON document ([`to_json`]).

use std::fmt::Write as _;
use std::time::Instant;

use hdrhistogram::Histogram;
use serde::Serialize;

use crate::config::{Api, LoadConfig};
use crate::cpu::Usage;
use crate::meter::Tally;
use crate::rss::Memory;

/// Per-call latency of measured calls, in µs.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct Latency {
    /// Median.
    pub p50: u64,
    /// 90th percentile.
    pub p90: u64,
    /// 99th percentile.
    pub p99: u64,
    /// Slowest.
    pub max: u64,
    /// Mean.
    pub mean: f64,
}

/// The figures of one target (remote or in process).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RunResult {
    /// What ran, e.g. `remote unary` or `in-process`.
    pub label: String,
    /// Where, e.g. `embedded server 127.0.0.1:40123 (2 threads)`.
    pub target: String,
    /// Measured successful calls, all clients.
    pub calls: u64,
    /// Env-steps in them: `n_envs × calls`.
    pub env_steps: u64,
    /// Wall time of the measurement, s.
    pub elapsed_s: f64,
    /// `env_steps / elapsed_s`.
    pub env_steps_per_s: f64,
    /// `calls / elapsed_s`.
    pub calls_per_s: f64,
    /// Latency of one call.
    pub latency_us: Latency,
    /// Failed calls.
    pub errors: u64,
    /// The first failure's message.
    pub first_error: Option<String>,
    /// Envs that reported `terminated` (e.g. `physics_diverged`) in measured calls.
    pub terminations: u64,
    /// Measured calls per client.
    pub calls_per_client: Vec<u64>,
    /// Resident memory with every env still open, just before they are closed.
    pub memory_loaded: Option<Memory>,
    /// The CPU time this process got during the run (setup and warm-up included) against
    /// its wall time; `None` where it cannot be read.
    pub usage: Option<Usage>,
    /// How many of this process's threads the run can keep simulating at once (in
    /// process, or on the embedded server: its pool threads, at most one per env stepped
    /// at a time); `None` when a server simulates or nothing is simulated (observe, ping).
    pub local_parallel: Option<usize>,
    /// What a healthy run of this workload measured (`apps/load/reference.json`), as a
    /// line; `None` when a server simulates.
    pub reference: Option<String>,
}

impl RunResult {
    /// Merges the clients' tallies. The measurement spans from the earliest client's
    /// start to the latest client's end.
    pub(crate) fn from_tallies(label: String, target: String, tallies: &[Tally]) -> Self {
        let mut latency =
            Histogram::<u64>::new_with_bounds(1, 600_000_000, 3).expect("valid histogram bounds");
        let mut start: Option<Instant> = None;
        let mut end: Option<Instant> = None;
        for t in tallies {
            latency.add(&t.latency).expect("same histogram bounds");
            if let Some(s) = t.measure_start {
                start = Some(start.map_or(s, |x| x.min(s)));
            }
            if let Some(e) = t.measure_end {
                end = Some(end.map_or(e, |x| x.max(e)));
            }
        }
        let elapsed_s = match (start, end) {
            (Some(s), Some(e)) => e.saturating_duration_since(s).as_secs_f64(),
            _ => 0.0,
        };
        let calls: u64 = tallies.iter().map(|t| t.calls).sum();
        let env_steps: u64 = tallies.iter().map(|t| t.env_steps).sum();
        let rate = |n: u64| {
            if elapsed_s > 0.0 {
                n as f64 / elapsed_s
            } else {
                0.0
            }
        };
        let latency_us = if latency.is_empty() {
            Latency::default()
        } else {
            Latency {
                p50: latency.value_at_quantile(0.50),
                p90: latency.value_at_quantile(0.90),
                p99: latency.value_at_quantile(0.99),
                max: latency.max(),
                mean: latency.mean(),
            }
        };
        RunResult {
            label,
            target,
            calls,
            env_steps,
            elapsed_s,
            env_steps_per_s: rate(env_steps),
            calls_per_s: rate(calls),
            latency_us,
            errors: tallies.iter().map(|t| t.errors).sum(),
            first_error: tallies.iter().find_map(|t| t.first_error.clone()),
            terminations: tallies.iter().map(|t| t.terminations).sum(),
            calls_per_client: tallies.iter().map(|t| t.calls).collect(),
            memory_loaded: None,
            usage: None,
            local_parallel: None,
            reference: None,
        }
    }
}

/// Everything a run reports.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Report {
    /// The configuration, as resolved.
    pub config: LoadConfig,
    /// One line describing it.
    pub summary: String,
    /// One result per target; `--compare`: in process, then remote, for each round.
    pub runs: Vec<RunResult>,
    /// `--compare`: remote env-steps/s divided by in-process env-steps/s; the median
    /// of [`Report::round_ratios`] with `--rounds`.
    pub ratio_remote_to_in_process: Option<f64>,
    /// `--compare`: each round's ratio, in order (one with a single round).
    pub round_ratios: Vec<f64>,
    /// `--report-rss`: this process's memory before setup.
    pub memory_baseline: Option<Memory>,
    /// `--report-rss`: this process's memory at the end (VmHWM is the peak).
    pub memory_end: Option<Memory>,
}

/// The report as a pretty-printed JSON document.
pub fn to_json(report: &Report) -> String {
    serde_json::to_string_pretty(report).expect("reports serialise")
}

/// The report as the table printed on stdout: one column per run.
pub fn render_table(report: &Report) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "{}", report.summary);
    for (i, r) in report.runs.iter().enumerate() {
        let _ = writeln!(out, "[{}] {}: {}", i + 1, r.label, r.target);
    }
    out.push_str(&layout(&table_rows(report), report.runs.len()));
    out.push_str(&notes(report));
    out
}

/// The table's rows: a name and one cell per run.
fn table_rows(report: &Report) -> Vec<(String, Vec<String>)> {
    let runs = &report.runs;
    let mut rows: Vec<(String, Vec<String>)> = Vec::new();
    let mut row = |name: &str, f: &dyn Fn(&RunResult) -> String| {
        rows.push((name.to_string(), runs.iter().map(f).collect()));
    };
    // A ping steps no env: its env rows would only say 0 or repeat the calls.
    let envs = report.config.api != Api::Ping;
    row("", &|r| r.label.clone());
    if envs {
        row("env-steps/s", &|r| format!("{:.1}", r.env_steps_per_s));
    }
    row("calls/s", &|r| format!("{:.1}", r.calls_per_s));
    row("latency p50 (µs)", &|r| r.latency_us.p50.to_string());
    row("latency p90 (µs)", &|r| r.latency_us.p90.to_string());
    row("latency p99 (µs)", &|r| r.latency_us.p99.to_string());
    row("latency max (µs)", &|r| r.latency_us.max.to_string());
    row("calls", &|r| r.calls.to_string());
    if envs {
        row("env-steps", &|r| r.env_steps.to_string());
    }
    row("elapsed (s)", &|r| format!("{:.3}", r.elapsed_s));
    if envs {
        row("terminated envs", &|r| r.terminations.to_string());
    }
    row("errors", &|r| r.errors.to_string());
    if runs.iter().any(|r| r.usage.is_some()) {
        row("process CPU / wall (s)", &|r| {
            r.usage
                .map_or("-".into(), |u| format!("{:.1} / {:.1}", u.cpu_s, u.wall_s))
        });
        row("busy cores", &|r| {
            r.usage.map_or("-".into(), |u| {
                format!("{:.2} of {}", u.busy_cores(), u.cores)
            })
        });
    }
    if runs.iter().any(|r| r.memory_loaded.is_some()) {
        row("VmRSS loaded (MiB)", &|r| {
            r.memory_loaded
                .map_or("-".into(), |m| format!("{:.1}", m.rss_mib()))
        });
    }

    rows
}

/// `rows` as aligned text: names left, cells right, two spaces apart.
fn layout(rows: &[(String, Vec<String>)], runs: usize) -> String {
    let name_width = rows
        .iter()
        .map(|(n, _)| n.chars().count())
        .max()
        .unwrap_or(0);
    let widths: Vec<usize> = (0..runs)
        .map(|i| {
            rows.iter()
                .map(|(_, cells)| cells[i].chars().count())
                .max()
                .unwrap_or(0)
        })
        .collect();
    let mut out = String::new();
    for (name, cells) in rows {
        let _ = write!(out, "{name:<name_width$}");
        for (cell, width) in cells.iter().zip(&widths) {
            let _ = write!(out, "  {cell:>width$}");
        }
        out.push('\n');
    }
    out
}

/// The lines under the table: first errors, references, starvation warnings, the
/// remote / in-process ratio and memory.
fn notes(report: &Report) -> String {
    let runs = &report.runs;
    let mut out = String::new();
    for r in runs {
        if let Some(first) = &r.first_error {
            let _ = writeln!(out, "first error ({}): {first}", r.label);
        }
    }
    // Each workload's reference once (a comparison's rounds share them).
    let mut references: Vec<&str> = Vec::new();
    for reference in runs.iter().filter_map(|r| r.reference.as_deref()) {
        if !references.contains(&reference) {
            references.push(reference);
            let _ = writeln!(out, "{reference}");
        }
    }
    for r in runs {
        if let (Some(usage), Some(parallel)) = (r.usage, r.local_parallel) {
            if let Some(warning) = usage.starved(parallel) {
                let _ = writeln!(out, "{} {warning}", r.label);
            }
        }
    }
    match (report.ratio_remote_to_in_process, report.round_ratios.len()) {
        (Some(ratio), 0 | 1) => {
            let _ = writeln!(out, "remote / in-process env-steps/s: {ratio:.3}");
        }
        (Some(ratio), rounds) => {
            let each: Vec<String> = report
                .round_ratios
                .iter()
                .map(|r| format!("{r:.3}"))
                .collect();
            let _ = writeln!(
                out,
                "remote / in-process env-steps/s, each round: {}",
                each.join(" ")
            );
            let _ = writeln!(
                out,
                "remote / in-process env-steps/s, median of {rounds} rounds: {ratio:.3}"
            );
        }
        (None, _) => {}
    }
    for (what, memory) in [
        ("before setup", report.memory_baseline),
        ("at the end", report.memory_end),
    ] {
        if let Some(m) = memory {
            let _ = writeln!(
                out,
                "memory {what}: VmRSS {:.1} MiB, VmHWM {:.1} MiB",
                m.rss_mib(),
                m.hwm_mib()
            );
        }
    }
    out
}
