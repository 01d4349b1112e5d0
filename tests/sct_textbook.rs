//! Classic textbook examples whose supervisor sizes are published.

use plcsynth::benchmarks::textbook::{small_factory, transfer_line};
use plcsynth::sct::classic::{is_controllable, minimize, supcon};

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

mod gen_robustness {
    use plcsynth::sct::classic::gen::{read_gen, write_gen};
    use plcsynth::sct::classic::{supcon, Events};
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(crate::common::proptest_config(300))]

        /// Mutated `.gen` files never make the reader (or SupCon on what it reads) panic.
        #[test]
        fn gen_reader_never_panics(ops in proptest::collection::vec((0u8..3, 0usize..4000, 0usize..30, 0usize..8), 1..4)) {
            let (plant, spec, ev) = plcsynth::benchmarks::textbook::small_factory();
            let mut text = write_gen(&plant, &ev, "p");
            let pieces = ["<States>", "</TransRel>", "\"", "+C+", "<Consecutive> 1 9 </Consecutive>", "7", "#", "%"];
            for (op, at, len, p) in ops {
                let at = at % (text.len() + 1);
                let end = (at + len).min(text.len());
                match op {
                    0 => text.replace_range(at..end, ""),
                    1 => text.insert_str(at, pieces[p]),
                    _ => { let s = text[at..end].to_string(); text.insert_str(end, &s); }
                }
            }
            let mut events = Events::new();
            let s2 = write_gen(&spec, &ev, "s");
            if let (Ok(p), Ok(s)) = (read_gen(&text, &mut events), read_gen(&s2, &mut events)) {
                let _ = supcon(&p, &s, &events, true);
            }
        }
    }
}

#[test]
fn agv_supervisor_is_4406_states_11338_transitions() {
    let (plant, spec, ev) = plcsynth::benchmarks::textbook::agv();
    // Five vehicle routes of 4, 8, 4, 6 and 4 states.
    assert_eq!(plant.num_states(), 4 * 8 * 4 * 6 * 4);
    let sup = supcon(&plant, &spec, &ev, true).unwrap();
    assert_eq!((sup.num_states(), sup.num_transitions()), (4406, 11338));
    assert!(sup.is_nonblocking());
    assert!(is_controllable(&plant, &sup, &ev));
}
