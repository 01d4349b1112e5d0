//! `.sct` projects: load, render and synthesise within a small budget (see `check_sct`).
//! Invalid UTF-8 is read lossily, so that no mutation is wasted.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    plcsynth_fuzz::check_sct(&String::from_utf8_lossy(data));
});
