//! The closed loop of plant models and supervisors stepped event by event, as DESTool's
//! animation and the CIF simulator do: the current state of every plant and supervisor, and for
//! every event whether it can happen now, which supervisor disables it, or which enforces it.
//!
//! A position is a pure function of the events fired from the initial states ([`step`]), so
//! the playground keeps only that trace: stepping back drops its last event.
//!
//! Which events can happen, after the model of 5.8 and the runtime of 6.3:
//! - a plant with the event in its alphabet must have a transition on it from its current
//!   state whose condition holds (the plant contract: otherwise it is physically impossible);
//!   plants without it in their alphabet do not constrain it;
//! - a controllable event is disabled by the first supervisor whose current state prohibits it;
//! - an uncontrollable event cannot be disabled; one that a supervisor prohibits breaks that
//!   supervisor's plant assumptions (*unexpected*), and that supervisor keeps its state when it
//!   happens, as in [`super::Runtime`];
//! - an enforceable event happens only where a supervisor's current state enforces it; the
//!   supervisors that enforce it take it, the others do not track it (6.4.2).

use super::model::{EventId, EventKind, Project, Supervisor, Truth};
use serde::Serialize;

/// What an event can do in the current position.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
#[serde(tag = "status", rename_all = "snake_case")]
pub enum EventStatus {
    /// It can happen; every supervisor allows it.
    Enabled,
    /// A plant model rules it out here.
    Impossible { plant: String },
    /// A controllable event the supervisor prohibits here.
    Disabled { by: String },
    /// An uncontrollable event a supervisor prohibits: possible in the plant models, but it
    /// breaks that supervisor's assumptions.
    Unexpected { by: String },
    /// An enforceable event the supervisor executes in this state.
    Enforced { by: String },
    /// An enforceable event no supervisor enforces here.
    NotEnforced,
}

#[derive(Clone, Debug, Serialize)]
pub struct EventView {
    pub name: String,
    pub kind: EventKind,
    #[serde(flatten)]
    pub status: EventStatus,
}

#[derive(Clone, Debug, Serialize)]
pub struct PlantView {
    pub name: String,
    pub state: String,
}

#[derive(Clone, Debug, Serialize)]
pub struct SupervisorView {
    pub name: String,
    pub state: String,
    pub prohibits: Vec<String>,
    pub enforces: Option<String>,
}

/// The position after a trace.
#[derive(Clone, Debug, Serialize)]
pub struct StepView {
    pub plants: Vec<PlantView>,
    pub supervisors: Vec<SupervisorView>,
    pub events: Vec<EventView>,
    /// The events fired so far.
    pub trace: Vec<String>,
}

/// Where the closed loop is: every plant's state and every supervisor's.
struct Position<'a> {
    project: &'a Project,
    supervisors: &'a [&'a Supervisor],
    plants: Vec<u32>,
    sups: Vec<u32>,
}

impl Position<'_> {
    /// The transition plant `p` takes on `e`, `None` if the plant rules `e` out, or `Some(None)`
    /// if `e` is outside its alphabet.
    fn plant_move(&self, p: usize, e: EventId) -> Option<Option<u32>> {
        let plant = &self.project.plants[p];
        if !plant.alphabet.contains(&e) {
            return Some(None);
        }
        let lookup = |plant: u32| self.plants.get(plant as usize).copied();
        plant
            .trans
            .iter()
            .find(|t| t.src == self.plants[p] && t.event == e && t.cond.eval(&lookup) == Truth::True)
            .map(|t| Some(t.dst))
    }

    fn state(&self, k: usize) -> &super::model::SupState {
        &self.supervisors[k].states[self.sups[k] as usize]
    }

    fn status(&self, e: EventId) -> EventStatus {
        let name = |k: usize| self.supervisors[k].name.clone();
        if let Some(p) = (0..self.plants.len()).find(|&p| self.plant_move(p, e).is_none()) {
            return EventStatus::Impossible { plant: self.project.plants[p].name.clone() };
        }
        let prohibiting = Supervisor::first_prohibiting(self.supervisors, &self.sups, e);
        match self.project.kind(e) {
            EventKind::Controllable => {
                prohibiting.map_or(EventStatus::Enabled, |k| EventStatus::Disabled { by: name(k) })
            }
            EventKind::Uncontrollable => {
                prohibiting.map_or(EventStatus::Enabled, |k| EventStatus::Unexpected { by: name(k) })
            }
            EventKind::Enforceable => (0..self.sups.len())
                .find(|&k| self.state(k).enforced == Some(e))
                .map_or(EventStatus::NotEnforced, |k| EventStatus::Enforced { by: name(k) }),
        }
    }

    /// Fires `e`, or says why it cannot happen.
    fn fire(&mut self, e: EventId) -> Result<(), String> {
        let status = self.status(e);
        let event = self.project.event_name(e);
        match &status {
            EventStatus::Impossible { plant } => {
                return Err(format!("`{event}` cannot happen: plant `{plant}` rules it out"))
            }
            EventStatus::Disabled { by } => return Err(format!("`{event}` is disabled by supervisor `{by}`")),
            EventStatus::NotEnforced => {
                return Err(format!("`{event}` is enforceable and no supervisor enforces it here"))
            }
            _ => {}
        }
        let moves: Vec<Option<u32>> = (0..self.plants.len()).map(|p| self.plant_move(p, e).flatten()).collect();
        for (p, to) in moves.into_iter().enumerate() {
            if let Some(to) = to {
                self.plants[p] = to;
            }
        }
        for k in 0..self.sups.len() {
            let st = self.state(k);
            let tracks = match &status {
                // Only the supervisors that enforce it take an enforced event (6.4.2).
                EventStatus::Enforced { .. } => st.enforced == Some(e),
                // The supervisor whose assumption broke keeps its state (`Runtime`).
                EventStatus::Unexpected { .. } => !st.prohibits(e),
                _ => true,
            };
            if tracks {
                self.sups[k] = self.supervisors[k].successor(self.sups[k], e);
            }
        }
        Ok(())
    }
}

/// The position after firing `trace` (event names) from the initial states. Fails on a void
/// supervisor, an unknown event, or an event that cannot happen where it is fired (the message
/// says which and why).
pub fn step(project: &Project, supervisors: &[&Supervisor], trace: &[String]) -> Result<StepView, String> {
    let mut sups = Vec::with_capacity(supervisors.len());
    for s in supervisors {
        sups.push(s.init.ok_or_else(|| format!("supervisor `{}` is void: its specification is unrealizable", s.name))?);
    }
    let mut at = Position { project, supervisors, plants: project.plants.iter().map(|p| p.init).collect(), sups };
    for (i, name) in trace.iter().enumerate() {
        let e = project.event(name).ok_or_else(|| format!("no event `{name}`"))?;
        at.fire(e).map_err(|why| format!("step {}: {why}", i + 1))?;
    }
    Ok(StepView {
        plants: project
            .plants
            .iter()
            .zip(&at.plants)
            .map(|(p, &q)| PlantView { name: p.name.clone(), state: p.states[q as usize].clone() })
            .collect(),
        supervisors: (0..supervisors.len())
            .map(|k| {
                let st = at.state(k);
                SupervisorView {
                    name: supervisors[k].name.clone(),
                    state: st.label.clone(),
                    prohibits: st.prohibited.iter().map(|&e| project.event_name(e).to_string()).collect(),
                    enforces: st.enforced.map(|e| project.event_name(e).to_string()),
                }
            })
            .collect(),
        events: (0..project.events.len())
            .map(EventId::new)
            .map(|e| EventView { name: project.event_name(e).to_string(), kind: project.kind(e), status: at.status(e) })
            .collect(),
        trace: trace.to_vec(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sct::{compile, model::Config, synthesize, Synthesis};

    fn status_of<'v>(view: &'v StepView, event: &str) -> &'v EventStatus {
        &view.events.iter().find(|e| e.name == event).unwrap().status
    }

    #[test]
    fn the_interlocked_tank_disables_opening_and_the_plant_rules_out_the_alarm() {
        // Figure 5.7: one supervisor state that prohibits opening the inlet.
        let src = include_str!("../../examples/sct/tank_interlock.sct");
        let (loaded, _) = compile(src).unwrap_or_else(|e| panic!("{e:?}"));
        let Synthesis { reports, .. } = synthesize(src, &loaded, &Config::default(), None, &mut |_| true);
        let sups: Vec<&Supervisor> = reports.iter().map(|r| &r.supervisor).collect();
        let p = &loaded.project;
        let view = step(p, &sups, &[]).unwrap();
        assert_eq!(view.plants[0].state, "A");
        assert_eq!(view.supervisors[0].prohibits, ["Tank.openInlet"]);
        assert_eq!(status_of(&view, "Tank.openInlet"), &EventStatus::Disabled { by: "Safety.NoOverflow".into() });
        assert_eq!(status_of(&view, "Tank.closeInlet"), &EventStatus::Enabled);
        assert!(
            matches!(status_of(&view, "Tank.levelAlarm"), EventStatus::Impossible { plant } if plant == "Tank.Inlet")
        );
        let err = step(p, &sups, &["Tank.openInlet".to_string()]).unwrap_err();
        assert!(err.contains("step 1") && err.contains("disabled by supervisor `Safety.NoOverflow`"), "{err}");
        let err = step(p, &sups, &["Tank.closeInlet".into(), "Tank.overflow".into()]).unwrap_err();
        assert!(err.contains("step 2") && err.contains("rules it out"), "{err}");
        assert!(step(p, &sups, &["Nope".to_string()]).unwrap_err().contains("no event"));
    }

    #[test]
    fn preemption_enforces_closing_and_only_the_enforcer_takes_it() {
        let src = include_str!("../../examples/sct/tank_preemption.sct");
        let (loaded, _) = compile(src).unwrap_or_else(|d| panic!("{d:?}"));
        let Synthesis { reports, .. } = synthesize(src, &loaded, &Config::default(), None, &mut |_| true);
        let sups: Vec<&Supervisor> = reports.iter().map(|r| &r.supervisor).collect();
        let p = &loaded.project;
        let trace: Vec<String> = ["Tank.openInlet", "Tank.levelAlarm"].map(String::from).to_vec();
        let view = step(p, &sups, &trace).unwrap();
        assert_eq!(status_of(&view, "Tank.closeInlNow"), &EventStatus::Enforced { by: "Safety.NoOverflow".into() });
        assert_eq!(view.plants[0].state, "C");
        let mut closed = trace.clone();
        closed.push("Tank.closeInlNow".into());
        let view = step(p, &sups, &closed).unwrap();
        assert_eq!(view.plants[0].state, "A", "the enforced event closes the inlet");
        assert!(matches!(status_of(&view, "Tank.closeInlNow"), EventStatus::Impossible { .. }), "only in state C");
        assert_eq!(view.trace, closed);
    }
}
