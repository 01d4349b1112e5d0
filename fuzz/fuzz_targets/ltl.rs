//! G4LTL `.ltl` specifications: compile, synthesise on a small budget, lower a controller
//! (see `check_g4ltl`). Invalid UTF-8 is read lossily, so that no mutation is wasted.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    plcsynth_fuzz::check_g4ltl(&String::from_utf8_lossy(data));
});
