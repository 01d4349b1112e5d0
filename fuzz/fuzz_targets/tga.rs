//! `.tga` sources: parse, check and render diagnostics (see `check_tga`).
//! Invalid UTF-8 is read lossily, so that no mutation is wasted.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    plcsynth_fuzz::check_tga(&String::from_utf8_lossy(data));
});
