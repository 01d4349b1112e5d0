//! libFAUDES `.gen` files: read, round trip and SupCon (see `check_gen`).
//! Invalid UTF-8 is read lossily, so that no mutation is wasted.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    plcsynth_fuzz::check_gen(&String::from_utf8_lossy(data));
});
