//! The synthesised supervisor: its states (transitions, prohibitions, the enforced event) and
//! what the runtime, the lowering and the reports ask of it.

use super::EventId;
use serde::Serialize;

/// A synthesised supervisor (definition 7, with the enforcement map of 5.8.5).
#[derive(Clone, Debug, Serialize)]
pub struct Supervisor {
    pub name: String,
    /// `None` if the specification is unrealizable (void supervisor).
    pub init: Option<u32>,
    pub states: Vec<SupState>,
    /// Plants that were applied, in order.
    pub plants_used: Vec<String>,
}

/// One supervisor state: its label, explicit transitions, prohibited and enforced events.
#[derive(Clone, Debug, Serialize)]
pub struct SupState {
    pub label: String,
    pub transitions: Vec<(EventId, u32)>,
    pub prohibited: Vec<EventId>,
    pub enforced: Option<EventId>,
    /// Source locations of the enforced transition (for cycle reports).
    #[serde(skip)]
    pub enforced_origin: Vec<u32>,
}

impl SupState {
    /// The explicit transition on `e`, if any.
    pub fn next(&self, e: EventId) -> Option<u32> {
        self.transitions.iter().find(|(x, _)| *x == e).map(|&(_, t)| t)
    }

    /// Whether this state prohibits `e`.
    pub fn prohibits(&self, e: EventId) -> bool {
        self.prohibited.contains(&e)
    }
}

impl Supervisor {
    /// The successor of `state` on `e`: its transition on `e`, else `state` itself (an event
    /// without a transition loops).
    pub fn successor(&self, state: u32, e: EventId) -> u32 {
        self.states[state as usize].next(e).unwrap_or(state)
    }

    /// Whether `state` prohibits `e`.
    pub fn prohibits(&self, state: u32, e: EventId) -> bool {
        self.states[state as usize].prohibits(e)
    }

    /// The first of `supervisors`, each in its state of `states`, that prohibits `e`.
    pub fn first_prohibiting(supervisors: &[&Supervisor], states: &[u32], e: EventId) -> Option<usize> {
        (0..supervisors.len()).find(|&k| supervisors[k].prohibits(states[k], e))
    }

    pub fn realizable(&self) -> bool {
        self.init.is_some()
    }

    pub fn num_transitions(&self) -> usize {
        self.states.iter().map(|s| s.transitions.len()).sum()
    }

    pub fn num_prohibitions(&self) -> usize {
        self.states.iter().map(|s| s.prohibited.len()).sum()
    }

    /// Events enforced somewhere, sorted and deduplicated.
    pub fn enforced_events(&self) -> Vec<EventId> {
        let mut v: Vec<EventId> = self.states.iter().filter_map(|s| s.enforced).collect();
        crate::sort::sort(&mut v);
        v.dedup();
        v
    }

    /// Events prohibited somewhere, sorted and deduplicated.
    pub fn prohibited_events(&self) -> Vec<EventId> {
        let mut v: Vec<EventId> = self.states.iter().flat_map(|s| s.prohibited.iter().copied()).collect();
        crate::sort::sort(&mut v);
        v.dedup();
        v
    }

    /// The supervisor's state after a word (implicit self-loops for events without a
    /// transition); `None` if a prohibited event occurs or the supervisor is void.
    pub fn run(&self, word: &[EventId]) -> Option<u32> {
        let mut s = self.init?;
        for &e in word {
            if self.prohibits(s, e) {
                return None;
            }
            s = self.successor(s, e);
        }
        Some(s)
    }

    /// A cycle of enforced transitions (5.5.5), as the list of states on it.
    ///
    /// Kept by hand rather than petgraph's `depth_first_search`: every state has at most one
    /// enforced successor, so the search is a walk along it, and the walk is a loop where
    /// petgraph's search recurses once per state on a path (a long enforced chain would exhaust
    /// the stack, in the browser first).
    pub fn enforcement_cycle(&self) -> Option<Vec<u32>> {
        let n = self.states.len();
        let next = |s: usize| -> Option<usize> {
            let f = self.states[s].enforced?;
            self.states[s].next(f).map(|t| t as usize)
        };
        let mut color = vec![0u8; n];
        for start in 0..n {
            let mut path = Vec::new();
            let mut s = start;
            loop {
                if color[s] == 2 {
                    break;
                }
                if color[s] == 1 {
                    let i = path.iter().position(|&x| x == s).unwrap_or(0);
                    return Some(path[i..].iter().map(|&x| x as u32).collect());
                }
                color[s] = 1;
                path.push(s);
                match next(s) {
                    Some(t) => s = t,
                    None => break,
                }
            }
            for p in path {
                color[p] = 2;
            }
        }
        None
    }
}
