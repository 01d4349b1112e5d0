//! The runtime framework of supervisory control ([`crate::plc::lower::sct`]) run cycle by cycle in the
//! reference interpreter of the code model ([`crate::plc::model::exec`]), for the playground's cycle
//! simulator: the user sets the plant's inputs and the outputs the existing controller writes,
//! lets time pass, and reads per cycle what the framework did — the events it detected, each
//! supervisor's answer, the outputs it reset, the events it enforced, its timers.
//!
//! It simulates the generated code itself, so what it shows is what the downloaded framework
//! does. A run is a pure function of its inputs ([`run`]): stepping back is running one cycle
//! fewer.

use crate::plc::lower::sct::FrameworkMap;
use crate::plc::model::exec::{Machine, Value};
use crate::plc::model::unit::{SignalKind, Type, Unit};
use crate::sct::model::{Project, Supervisor};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// What happens in one cycle: the time since the previous one, the plant's inputs, and the
/// outputs the existing controller writes when the framework calls it (it writes them in every
/// cycle, as a PLC program does). Signals are named by their symbol; absent ones keep their
/// value (inputs) or are not written (outputs).
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(default)]
pub struct CycleInput {
    pub elapsed_ms: u64,
    pub inputs: BTreeMap<String, i64>,
    pub controller: BTreeMap<String, i64>,
}

/// A signal after a cycle.
#[derive(Clone, Debug, Serialize, PartialEq, Eq)]
pub struct SignalState {
    pub symbol: String,
    /// `input`, `output` or `memory`.
    pub kind: &'static str,
    /// `BOOL` or `INT`.
    pub data_type: &'static str,
    pub value: i64,
    /// For an output the controller wrote this cycle: what it wrote; `value` differs when the
    /// framework reset it (a denied event) or an enforced event's action changed it.
    pub written: Option<i64>,
    /// The events whose triggers or actions use it.
    pub events: String,
}

/// What one event did in a cycle.
#[derive(Clone, Debug, Serialize, PartialEq, Eq)]
pub struct EventState {
    pub event: String,
    /// `accepted`, `denied` (controllable), `occurred` (uncontrollable or a timeout),
    /// `enforced`.
    pub what: &'static str,
    /// For a denied event: the supervisor that denied it (the framework keeps the last denial
    /// of a cycle, so with several denials only the last one's).
    pub by: Option<String>,
}

/// A supervisor after a cycle.
#[derive(Clone, Debug, Serialize, PartialEq, Eq)]
pub struct SupervisorState {
    pub name: String,
    pub state: String,
    /// The events its current state prohibits, and the one it enforces.
    pub prohibits: Vec<String>,
    pub enforces: Option<String>,
}

/// A timer after a cycle.
#[derive(Clone, Debug, Serialize, PartialEq, Eq)]
pub struct TimerState {
    pub name: String,
    pub running: bool,
    pub expired: bool,
}

/// The framework after one cycle.
#[derive(Clone, Debug, Serialize, PartialEq, Eq)]
pub struct CycleView {
    /// From 1.
    pub cycle: usize,
    pub time_ms: u64,
    pub signals: Vec<SignalState>,
    pub events: Vec<EventState>,
    pub supervisors: Vec<SupervisorState>,
    pub timers: Vec<TimerState>,
}

/// The signals and supervisors before the first cycle (a cold start).
pub fn initial(
    unit: &Unit,
    map: &FrameworkMap,
    project: &Project,
    supervisors: &[&Supervisor],
) -> Result<CycleView, String> {
    let machine = Machine::new(unit).map_err(|e| e.0)?;
    Ok(view(&machine, unit, map, project, supervisors, 0, 0, &BTreeMap::new()))
}

/// Runs the framework from a cold start through `cycles`, one view per cycle. An error of the
/// interpreter (a runaway cycle, an unknown signal name) stops the run with its message.
pub fn run(
    unit: &Unit,
    map: &FrameworkMap,
    project: &Project,
    supervisors: &[&Supervisor],
    cycles: &[CycleInput],
) -> Result<Vec<CycleView>, String> {
    let mut index: BTreeMap<&str, usize> = BTreeMap::new();
    index.extend(unit.signals.iter().enumerate().map(|(k, s)| (s.symbol.as_str(), k)));
    let find =
        |symbol: &str| index.get(symbol).copied().ok_or_else(|| format!("the framework has no signal `{symbol}`"));
    let mut machine = Machine::new(unit).map_err(|e| e.0)?;
    let mut out = Vec::with_capacity(cycles.len());
    let mut time_ms = 0;
    for (n, input) in cycles.iter().enumerate() {
        machine.advance(input.elapsed_ms);
        time_ms += input.elapsed_ms;
        for (symbol, &value) in &input.inputs {
            let k = find(symbol)?;
            if unit.signals[k].kind != SignalKind::Input {
                return Err(format!("`{symbol}` is not an input of the framework"));
            }
            machine.set_signal(k, Value::Int(value));
        }
        let mut written = BTreeMap::new();
        for (symbol, &value) in &input.controller {
            written.insert(find(symbol)?, value);
        }
        let mut controller = |m: &mut Machine<'_>| {
            for (&k, &v) in &written {
                m.set_signal(k, Value::Int(v));
            }
            Ok(())
        };
        machine.cycle(&mut controller).map_err(|e| format!("cycle {}: {}", n + 1, e.0))?;
        out.push(view(&machine, unit, map, project, supervisors, n + 1, time_ms, &written));
    }
    Ok(out)
}

#[allow(clippy::too_many_arguments)]
fn view(
    machine: &Machine<'_>,
    unit: &Unit,
    map: &FrameworkMap,
    project: &Project,
    supervisors: &[&Supervisor],
    cycle: usize,
    time_ms: u64,
    written: &BTreeMap<usize, i64>,
) -> CycleView {
    let flag = |name: &str| machine.global(name).is_some_and(Value::as_bool);
    let signals = unit
        .signals
        .iter()
        .enumerate()
        .map(|(k, s)| SignalState {
            symbol: s.symbol.clone(),
            kind: match s.kind {
                SignalKind::Input => "input",
                SignalKind::Output => "output",
                SignalKind::Memory => "memory",
            },
            data_type: if s.ty == Type::Bool { "BOOL" } else { "INT" },
            value: machine.signal(k).as_int(),
            written: written.get(&k).copied(),
            events: s.comment.clone(),
        })
        .collect();
    let int = |name: &str| machine.global(name).map_or(0, Value::as_int);
    let (denied_event, denied_by) = (int(&map.last_denied.0), int(&map.last_denied.1));
    let events = map
        .event_flags
        .iter()
        .filter(|(_, _, g)| flag(g))
        .map(|&(e, what, _)| EventState {
            event: project.event_name(e).to_string(),
            what,
            by: match usize::try_from(denied_by) {
                Ok(k) if k >= 1 && what == "denied" && denied_event == i64::from(e.raw()) + 1 => {
                    supervisors.get(k - 1).map(|s| s.name.clone())
                }
                _ => None,
            },
        })
        .collect();
    let supervisors = supervisors
        .iter()
        .zip(&map.supervisor_states)
        .map(|(s, g)| {
            let q = machine.global(g).map_or(0, Value::as_int);
            let state = s.states.get(q as usize);
            SupervisorState {
                name: s.name.clone(),
                state: state.map_or_else(|| format!("#{q}"), |st| st.label.clone()),
                prohibits: state
                    .map(|st| st.prohibited.iter().map(|&e| project.event_name(e).to_string()).collect())
                    .unwrap_or_default(),
                enforces: state.and_then(|st| st.enforced).map(|e| project.event_name(e).to_string()),
            }
        })
        .collect();
    let timers = map
        .timers
        .iter()
        .map(|(name, run, expired)| TimerState { name: name.clone(), running: flag(run), expired: flag(expired) })
        .collect();
    CycleView { cycle, time_ms, signals, events, supervisors, timers }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plc::lower::sct::{lower_mapped, FrameworkOptions};
    use crate::sct::{compile, model::Config, synthesize, EventOutcome, Runtime, Synthesis};

    const TANK: &str = include_str!("../../../../examples/sct/tank_preemption.sct");

    fn cycle(elapsed_ms: u64, inputs: &[(&str, i64)], controller: &[(&str, i64)]) -> CycleInput {
        CycleInput {
            elapsed_ms,
            inputs: inputs.iter().map(|&(s, v)| (s.to_string(), v)).collect(),
            controller: controller.iter().map(|&(s, v)| (s.to_string(), v)).collect(),
        }
    }

    /// The interlock denies opening the inlet, says which supervisor did, and resets the output.
    #[test]
    fn a_denied_event_names_its_supervisor_and_its_output_is_reset() {
        let src = include_str!("../../../../examples/sct/tank_interlock.sct");
        let (loaded, _) = compile(src).unwrap_or_else(|d| panic!("{d:?}"));
        let Synthesis { reports, .. } = synthesize(src, &loaded, &Config::default(), None, &mut |_| true);
        let sups: Vec<&Supervisor> = reports.iter().map(|r| &r.supervisor).collect();
        let (unit, map) = lower_mapped(src, &loaded, &sups, &FrameworkOptions::default()).unwrap();
        let views = run(&unit, &map, &loaded.project, &sups, &[cycle(10, &[], &[("Q_Inlet", 1)])]).unwrap();
        let denied = &views[0].events[0];
        assert_eq!((denied.what, denied.event.as_str()), ("denied", "Tank.openInlet"));
        assert_eq!(denied.by.as_deref(), Some("Safety.NoOverflow"));
        let q = views[0].signals.iter().find(|s| s.symbol == "Q_Inlet").unwrap();
        assert_eq!((q.written, q.value), (Some(1), 0));
    }

    /// The tank: the controller opens the inlet, the level alarm comes, the supervisor enforces
    /// closing it; a controller that opens again is denied and its output reset. The same events
    /// stepped through `sct::Runtime` give the same answers.
    #[test]
    fn the_tank_framework_denies_resets_and_enforces_as_the_reference_executor() {
        let (loaded, _) = compile(TANK).unwrap_or_else(|e| panic!("{e:?}"));
        let Synthesis { reports, .. } = synthesize(TANK, &loaded, &Config::default(), None, &mut |_| true);
        let sups: Vec<&Supervisor> = reports.iter().map(|r| &r.supervisor).collect();
        let (unit, map) = lower_mapped(TANK, &loaded, &sups, &FrameworkOptions::default()).unwrap();
        let p = &loaded.project;
        let before = initial(&unit, &map, p, &sups).unwrap();
        assert_eq!(before.cycle, 0);
        assert!(before.events.is_empty());
        let cycles = [
            cycle(10, &[], &[("Q_Inlet", 1)]),
            cycle(10, &[("I_LevelHigh", 1)], &[("Q_Inlet", 1)]),
            cycle(10, &[], &[("Q_Inlet", 1)]),
        ];
        let views = run(&unit, &map, p, &sups, &cycles).unwrap();
        let events = |v: &CycleView| v.events.iter().map(|e| format!("{} {}", e.what, e.event)).collect::<Vec<_>>();
        assert_eq!(events(&views[0]), ["accepted Tank.openInlet"]);
        let q_inlet = |v: &CycleView| v.signals.iter().find(|s| s.symbol == "Q_Inlet").unwrap().clone();
        assert_eq!(q_inlet(&views[0]).value, 1);
        // The alarm: the supervisor enforces closing the inlet; its action writes FALSE.
        assert!(events(&views[1]).contains(&"occurred Tank.levelAlarm".to_string()), "{:?}", events(&views[1]));
        assert!(events(&views[1]).contains(&"enforced Tank.closeInlNow".to_string()), "{:?}", events(&views[1]));
        assert_eq!((q_inlet(&views[1]).written, q_inlet(&views[1]).value), (Some(1), 0));

        // The reference executor on the same events.
        let mut rt = Runtime::new(p, &sups, &loaded.timers).unwrap();
        let ev = |name: &str| p.event(name).unwrap();
        rt.begin_cycle(10, &[]);
        assert!(rt.execute(ev("Tank.openInlet")));
        rt.end_cycle();
        rt.begin_cycle(10, &[ev("Tank.levelAlarm")]);
        let report = rt.end_cycle();
        assert!(report
            .steps
            .iter()
            .any(|s| s.event == ev("Tank.closeInlNow") && matches!(s.outcome, EventOutcome::Enforced { .. })));
        assert_eq!(
            views[1].supervisors[0].state,
            sups[0].states[rt.states()[0] as usize].label,
            "the framework's state is the executor's"
        );

        // Stepping back is running fewer cycles: the same views.
        assert_eq!(run(&unit, &map, p, &sups, &cycles[..2]).unwrap(), views[..2]);
        assert!(run(&unit, &map, p, &sups, &[cycle(1, &[("Nope", 1)], &[])]).unwrap_err().contains("Nope"));
        assert!(views.iter().flat_map(|v| &v.events).all(|e| e.by.is_none()), "nothing denied here");
        assert!(run(&unit, &map, p, &sups, &[cycle(1, &[("Q_Inlet", 1)], &[])]).unwrap_err().contains("not an input"));
    }
}
