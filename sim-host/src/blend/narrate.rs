//! A blended session told as the demo tells a scenario (the scenario's own
//! [`Teller`]): each tick where something happens, each failure and expansion with the
//! tree it made, each swap, and the facts the controller's reports contradicted.

use std::fmt::Write as _;
use std::sync::Arc;

use bt_core::{NodeId, NodeStatus};
use planner::PddlCatalog;
use planner::ground::Grounding;

use super::{End, Listener, Step};
use crate::scenario::narrate::Teller;
use crate::session::Event;
use crate::text::count;

/// Tells a blended session; [`Narrator::take_text`] hands over what it told so far.
#[derive(Debug)]
pub struct Narrator<'a> {
    teller: Teller<'a, PddlCatalog>,
    g: Arc<Grounding>,
    /// The first tick the old tree ticked on, failing, while a grown tree was on its way.
    waiting_from: Option<u32>,
}

impl<'a> Narrator<'a> {
    /// Tells a session of the problem `g`, naming leaves with `catalog`.
    #[must_use]
    pub fn new(catalog: &'a PddlCatalog, g: Arc<Grounding>) -> Self {
        Self { teller: Teller::new(catalog), g, waiting_from: None }
    }

    /// The text told since the last call.
    pub fn take_text(&mut self) -> String {
        self.teller.take_text()
    }

    /// The old tree's ticks while a grown tree was on its way, in one line.
    fn waited(&mut self, swap: u32) {
        if let Some(from) = self.waiting_from.take() {
            let last = swap.saturating_sub(1);
            let ticks = if last > from { format!("ticks {from:>3}-{last:<3}") } else { format!("tick {from:>3} ") };
            self.teller.flush_quiet(from);
            self.teller
                .add_raw(&format!("{ticks} the old tree ticks on, its root failing, while the grown one is sent"));
        }
    }

    fn facts(&self, facts: &[(planner::ground::AtomId, bool)]) -> String {
        let named: Vec<String> = facts
            .iter()
            .map(|&(a, v)| format!("{} {}", self.g.atom_name(a), if v { "holds" } else { "does not hold" }))
            .collect();
        named.join(", ")
    }
}

impl Listener for Narrator<'_> {
    fn step(&mut self, step: Step<'_>) -> anyhow::Result<()> {
        match step {
            Step::Connected { tick, was_ticking } => {
                if was_ticking {
                    self.teller.say(tick, "the controller was ticking: stopped, what ran halted");
                }
            }
            Step::Tree { tick, nodes, values, image, grown: None } => {
                self.teller.show_tree("the tree at the start", nodes, values);
                self.teller.say(
                    tick,
                    &format!(
                        "the controller swaps it in ({}, image {:08x}) and starts",
                        count(image.len, "byte"),
                        image.crc
                    ),
                );
            }
            Step::Tree { tick, image, grown: Some(n), .. } => {
                self.waited(tick);
                let nodes = count(image.nodes, "node");
                self.teller
                    .say(tick, &format!("the controller swaps in the tree of expansion {n} ({nodes}), as named"));
            }
            Step::Event { event, nodes, before, after, waiting } => match event {
                Event::Tick { tick, root, changes, .. } => {
                    let changes: Vec<(NodeId, NodeStatus, NodeStatus)> = changes
                        .iter()
                        .map(|&(n, s)| (n, before.get(usize::from(n)).copied().unwrap_or(NodeStatus::Idle), s))
                        .collect();
                    self.teller.actions(*tick, nodes, &changes);
                    if NodeStatus::from(*root) == NodeStatus::Failure {
                        if waiting {
                            self.waiting_from.get_or_insert(*tick);
                        } else {
                            self.teller.root_fails(*tick, nodes, after);
                        }
                    }
                }
                Event::Swapped { tick, changes, .. } | Event::Stopped { tick, changes } => {
                    let why = if matches!(event, Event::Swapped { .. }) { "for the swap" } else { "for the stop" };
                    for &(n, s) in changes {
                        let was = before.get(usize::from(n)).copied();
                        if let (Some(NodeStatus::Running), NodeStatus::Idle, Some(node)) =
                            (was, s, nodes.get(usize::from(n)))
                            && let bt_core::NodeKind::Action(leaf) = node.kind()
                        {
                            let name = crate::scenario::driver::leaf_name(self.teller.catalog(), leaf);
                            self.teller.say(*tick, &format!("halts {name} {why}"));
                        }
                    }
                }
                Event::Garbled(fault) => {
                    self.teller.add(&format!("(the controller skipped a frame it could not read: {})", fault.code()));
                }
                Event::Lost { frames, .. } => {
                    self.teller.add(&format!(
                        "(the controller dropped {} its link could not carry: statuses may be stale)",
                        count(*frames, "status frame")
                    ));
                }
            },
            Step::Unexpected { tick, facts } => {
                let text =
                    format!("world: {}, as the controller reports, and no action that ran did it", self.facts(facts));
                self.teller.say(tick, &text);
            }
            Step::Expanded { grown, nodes, values } => {
                let mut note = String::new();
                let _ = write!(
                    note,
                    "planned in {:.2} ms; sent ({}, {} on the wire) and accepted in {:.1} ms; swaps in before tick {}",
                    grown.planning.as_secs_f64() * 1e3,
                    count(grown.image.len, "byte"),
                    count(grown.wire, "byte"),
                    grown.sending.as_secs_f64() * 1e3,
                    grown.swap_at
                );
                self.teller.grown_with(grown.failed_at, &grown.expansion, &note, nodes, values);
            }
            Step::Ending { end, stop_at } => {
                match end {
                    End::Goal(tick) => self.teller.say(*tick, "the root succeeds: the goal holds"),
                    End::Ticks => self.teller.say(stop_at.saturating_sub(1), "the ticks given ran out"),
                    End::Unexpandable { tick, error } => {
                        self.teller.say(*tick, &format!("the planner cannot expand the tree: {error}"));
                    }
                    End::Refused { tick, reason } => self.teller.say(*tick, &format!("the grown tree: {reason}")),
                }
                self.teller.add(&format!("the controller ticks on to its horizon and stops before tick {stop_at}"));
            }
        }
        Ok(())
    }
}
