//! TLSF specifications: compile with and without a parameter override (see `check_tlsf`).
//! Invalid UTF-8 is read lossily, so that no mutation is wasted.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    plcsynth_fuzz::check_tlsf(&String::from_utf8_lossy(data));
});
