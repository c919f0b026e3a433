//! Fuzz target: the input bytes are a sequence of C API calls on one crowd and one view
//! blender (see `crowdgaze_fuzz::api` for the encoding and the checks). A call returning a
//! status its header documentation does not list, or any output holding a NaN or an
//! infinity, panics.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| crowdgaze_fuzz::api::run(data));
