//! [`lookup`]: what a healthy run of the same workload measured, from the small table in
//! `apps/load/reference.json` (kept with BENCHMARKS.md, O2), so
//! that a report says whether its figure is this machine's or the workload's.

use serde::Deserialize;

use crate::config::{Api, LoadConfig, Mode};

/// The table, compiled in: a report needs it wherever the binary runs.
const TABLE: &str = include_str!("../reference.json");

/// Where a run simulated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub(crate) enum Place {
    /// `gymfleet-batch` on a pool in this process.
    InProcess,
    /// A server started in this process, over loopback gRPC.
    Embedded,
}

impl Place {
    fn words(self) -> &'static str {
        match self {
            Place::InProcess => "in process",
            Place::Embedded => "embedded server",
        }
    }
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Table {
    /// When, at which commit and on what machine the rows were measured.
    measured: String,
    /// The command that measured them.
    command: String,
    rows: Vec<Row>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Row {
    place: Place,
    model: String,
    /// "batch" (unary StepBatch) or "env" (single-env Step).
    api: String,
    n_envs: usize,
    threads: usize,
    env_steps_per_s: f64,
}

fn table() -> Table {
    serde_json::from_str(TABLE).expect("apps/load/reference.json parses (a unit test checks it)")
}

fn api_name(config: &LoadConfig) -> Option<&'static str> {
    match (config.api, config.mode) {
        (Api::Batch, Mode::Unary) => Some("batch"),
        (Api::Env, _) => Some("env"),
        _ => None,
    }
}

/// The reference for `config` run at `place` with `threads` simulation threads: the row
/// of the same model, API and thread count whose env count is nearest, as one line; or a
/// line saying that the table has none, and what it has for the model.
pub(crate) fn lookup(config: &LoadConfig, place: Place, threads: usize) -> String {
    let table = table();
    let model = &config.model.name;
    let Some(api) = api_name(config) else {
        let what = match (config.api, config.mode) {
            (Api::Observe, _) => "single-env Observe",
            (Api::Ping, _) => "GetServerInfo",
            _ => "StreamBatch",
        };
        return format!(
            "reference: none for {what} (apps/load/reference.json covers unary batch steps \
             and single-env steps)"
        );
    };
    let same = |r: &&Row| r.place == place && &r.model == model && r.api == api;
    let best = table
        .rows
        .iter()
        .filter(same)
        .filter(|r| r.threads == threads)
        .min_by_key(|r| r.n_envs.abs_diff(config.n_envs));
    match best {
        Some(r) => format!(
            "reference: {}, {model}, {} env(s), {} thread(s), idle machine: ~{:.0} env-steps/s \
             ({}; `{}`)",
            place.words(),
            r.n_envs,
            r.threads,
            r.env_steps_per_s,
            table.measured,
            table.command
        ),
        None => {
            let mut counts: Vec<usize> =
                table.rows.iter().filter(same).map(|r| r.threads).collect();
            counts.sort_unstable();
            counts.dedup();
            let has = if counts.is_empty() {
                let mut models: Vec<&str> = table.rows.iter().map(|r| r.model.as_str()).collect();
                models.sort_unstable();
                models.dedup();
                format!("it has the models {}", models.join(", "))
            } else {
                let list: Vec<String> = counts.iter().map(usize::to_string).collect();
                format!("it has {} thread(s)", list.join(", "))
            };
            format!(
                "reference: none for {}, {model}, --api {api}, {threads} thread(s) in \
                 apps/load/reference.json ({has})",
                place.words(),
            )
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Model;

    #[test]
    fn the_table_parses_and_covers_the_builtin_arm_at_one_and_two_threads() {
        let table = table();
        assert!(!table.rows.is_empty());
        for place in [Place::InProcess, Place::Embedded] {
            for threads in [1, 2] {
                assert!(
                    table.rows.iter().any(|r| r.place == place
                        && r.model == "arm2"
                        && r.api == "batch"
                        && r.threads == threads
                        && r.env_steps_per_s > 0.0),
                    "{place:?} {threads}"
                );
            }
        }
    }

    #[test]
    fn a_run_gets_the_nearest_row_or_a_line_saying_what_the_table_has() {
        let config = LoadConfig::new(Model::resolve("arm2").unwrap(), 300, 10);
        let line = lookup(&config, Place::InProcess, 2);
        assert!(
            line.starts_with(
                "reference: in process, arm2, 256 env(s), 2 thread(s), idle machine: ~"
            ),
            "{line}"
        );
        let line = lookup(&config, Place::InProcess, 7);
        assert_eq!(
            line,
            "reference: none for in process, arm2, --api batch, 7 thread(s) in \
             apps/load/reference.json (it has 1, 2 thread(s))"
        );
        let mut fourbar = LoadConfig::new(Model::resolve("fourbar").unwrap(), 256, 10);
        fourbar.api = Api::Observe;
        let line = lookup(&fourbar, Place::Embedded, 1);
        assert_eq!(
            line,
            "reference: none for single-env Observe (apps/load/reference.json covers unary \
             batch steps and single-env steps)"
        );
    }
}
