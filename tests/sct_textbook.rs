//! Classic textbook examples whose supervisor sizes are published.

use plcsynth::sct::classic::{is_controllable, minimize, supcon};
use plcsynth::sct::textbook::{small_factory, transfer_line};

#[test]
fn small_factory_supervisor_is_12_states_24_transitions() {
    let (plant, spec, ev) = small_factory();
    assert_eq!((plant.num_states(), plant.num_transitions()), (9, 24));
    let sup = supcon(&plant, &spec, &ev, true).unwrap();
    assert_eq!((sup.num_states(), sup.num_transitions()), (12, 24));
    assert!(sup.is_nonblocking());
    assert!(is_controllable(&plant, &sup, &ev));
}

#[test]
fn transfer_line_3_1_supervisor_is_28_states_65_transitions() {
    let (plant, spec, ev) = transfer_line(3, 1);
    let sup = supcon(&plant, &spec, &ev, true).unwrap();
    assert_eq!((sup.num_states(), sup.num_transitions()), (28, 65));
    assert!(sup.is_nonblocking());
    assert!(is_controllable(&plant, &sup, &ev));
    // The published supervisor is already minimal in states? Minimisation never grows it.
    assert!(minimize(&sup).num_states() <= 28);
}
