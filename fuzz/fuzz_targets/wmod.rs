//! Supremica/Waters `.wmod` modules: read, round trip, `.sct` mapping and SupCon (see
//! `check_wmod`). Invalid UTF-8 is read lossily, so that no mutation is wasted.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    plcsynth_fuzz::check_wmod(&String::from_utf8_lossy(data));
});
