//! Progress of `sim-host learn`: a bar per running run and one for the whole, on a
//! terminal; otherwise a line per finished run on stderr.

use std::io::IsTerminal as _;
use std::sync::Mutex;

use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};
use sim_host::learn::{RunOutcome, RunSpec};
use sim_host::text::count;

pub struct Progress {
    multi: Option<MultiProgress>,
    total: Option<ProgressBar>,
    lock: Mutex<()>,
}

pub struct RunBar {
    bar: Option<ProgressBar>,
}

impl RunBar {
    pub fn row(&self, row: &gp::GenerationLog) {
        if let Some(b) = &self.bar {
            b.set_position(u64::from(row.generation) + 1);
            b.set_message(format!("{}, best {:.3}", count(row.episodes, "episode"), row.best_fitness));
        }
    }
}

impl Progress {
    pub fn new(specs: &[RunSpec]) -> Self {
        if !std::io::stderr().is_terminal() {
            return Self { multi: None, total: None, lock: Mutex::new(()) };
        }
        let multi = MultiProgress::with_draw_target(ProgressDrawTarget::stderr());
        let total = multi.add(ProgressBar::new(specs.len() as u64));
        total.set_style(
            ProgressStyle::with_template("runs {pos}/{len} {wide_bar} {elapsed}")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        Self { multi: Some(multi), total: Some(total), lock: Mutex::new(()) }
    }

    pub fn start(&self, spec: &RunSpec) -> RunBar {
        let Some(multi) = &self.multi else { return RunBar { bar: None } };
        let bar = multi.add(ProgressBar::new(u64::from(spec.generations)));
        bar.set_style(
            ProgressStyle::with_template("{prefix:<40} gen {pos:>5}/{len} {bar:20} {msg}")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        bar.set_prefix(spec.folder());
        RunBar { bar: Some(bar) }
    }

    /// A line of news, above the bars on a terminal.
    pub fn note(&self, text: &str) {
        match &self.multi {
            Some(m) => {
                let _ = m.println(text);
            }
            None => {
                let _guard = self.lock.lock();
                // Progress only: a closed or full stderr does not stop the runs.
                let _ = super::super::output::stderr(format!("{text}\n").as_bytes());
            }
        }
    }

    pub fn done(&self, bar: &RunBar, o: &RunOutcome) {
        if let Some(b) = &bar.bar {
            b.finish_and_clear();
        }
        match &self.total {
            Some(t) => t.inc(1),
            None => self.note(&format!(
                "done {}: {}, best {:.3} (planner {:.3}), {:.1} s",
                o.spec.folder(),
                count(o.episodes, "episode"),
                o.best.fitness,
                o.planner_fitness,
                o.seconds
            )),
        }
    }

    pub fn finish(&self) {
        if let Some(t) = &self.total {
            t.finish_and_clear();
        }
    }
}
