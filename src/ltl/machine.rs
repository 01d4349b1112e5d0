//! Finite-state strategies: the controller of a realizable specification (a Mealy machine, or a
//! Moore machine under Moore semantics) and the environment's counter-strategy of an
//! unrealizable one. Both are the same shape — a machine that reads the other player's signals
//! and writes its own — so one type serves, and one printer.

use super::spec::{SignalId, Spec};
use serde::Serialize;
use std::collections::BTreeMap;

/// Index of a state in [`Machine::states`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
pub struct StateId(pub u32);

impl StateId {
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// A partial valuation of the signals a machine reads: bit `i` of `care` says whether the
/// `i`-th read signal matters, bit `i` of `value` what it must be.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
pub struct Cube {
    pub care: u64,
    pub value: u64,
}

impl Cube {
    /// The cube every valuation satisfies.
    pub const ANY: Cube = Cube { care: 0, value: 0 };

    pub fn contains(self, valuation: u64) -> bool {
        valuation & self.care == self.value
    }
}

/// One row of a state: when the read signals match `read`, write `write` (bit `i` the `i`-th
/// written signal) and go to `next`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Row {
    pub read: Cube,
    pub write: u64,
    pub next: StateId,
}

/// A complete deterministic strategy. In every state the rows' cubes are disjoint and cover
/// every valuation of `reads`. A machine that [`Machine::moves_first`] writes before it reads
/// (a Moore machine): all rows of a state then write the same value.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Machine {
    pub reads: Vec<SignalId>,
    pub writes: Vec<SignalId>,
    pub moves_first: bool,
    pub init: StateId,
    pub states: Vec<Vec<Row>>,
}

impl Machine {
    /// The row taken in `state` when the read signals have `valuation`.
    pub fn row(&self, state: StateId, valuation: u64) -> &Row {
        self.states[state.index()]
            .iter()
            .find(|r| r.read.contains(valuation))
            .expect("a machine's rows cover every valuation")
    }

    /// What a machine that moves first writes in `state` before reading.
    pub fn first_write(&self, state: StateId) -> u64 {
        self.states[state.index()].first().map_or(0, |r| r.write)
    }

    /// Transitions in all, counting one per row.
    pub fn rows(&self) -> usize {
        self.states.iter().map(Vec::len).sum()
    }

    /// Checks the invariants of the type: rows disjoint and complete, Moore rows uniform, next
    /// states in range. Returns the first violation.
    pub fn validate(&self) -> Result<(), String> {
        let n = self.reads.len();
        if n > 20 {
            return Ok(()); // too many valuations to enumerate; the constructors guarantee it
        }
        for (s, rows) in self.states.iter().enumerate() {
            for v in 0..1u64 << n {
                let hits = rows.iter().filter(|r| r.read.contains(v)).count();
                if hits != 1 {
                    return Err(format!("state {s}: valuation {v:#b} matches {hits} rows"));
                }
            }
            if let Some(r) = rows.iter().find(|r| r.next.index() >= self.states.len()) {
                return Err(format!("state {s}: next state {} out of range", r.next.0));
            }
            if self.moves_first && rows.iter().any(|r| r.write != rows[0].write) {
                return Err(format!("state {s}: a machine that moves first writes one value per state"));
            }
        }
        Ok(())
    }

    /// The JSON form of `plcsynth ltl --json`: `{"init", "states": {ID: [[{read: bool…}, NEXT,
    /// {write: bool…}], …]}}`; a read signal missing from a row's first object is "any".
    pub fn to_json(&self, spec: &Spec) -> serde_json::Value {
        let mut states = serde_json::Map::new();
        for (s, rows) in self.states.iter().enumerate() {
            let rows: Vec<serde_json::Value> = rows
                .iter()
                .map(|r| {
                    let read: BTreeMap<&str, bool> = self
                        .reads
                        .iter()
                        .enumerate()
                        .filter(|(i, _)| r.read.care >> i & 1 == 1)
                        .map(|(i, &sig)| (spec.name(sig), r.read.value >> i & 1 == 1))
                        .collect();
                    let write: BTreeMap<&str, bool> = self
                        .writes
                        .iter()
                        .enumerate()
                        .map(|(i, &sig)| (spec.name(sig), r.write >> i & 1 == 1))
                        .collect();
                    serde_json::json!([read, r.next.0, write])
                })
                .collect();
            states.insert(s.to_string(), serde_json::Value::Array(rows));
        }
        serde_json::json!({ "init": self.init.0, "states": states })
    }
}
