//! Scheme files: arbitrary bytes through the parser and, when they parse, the validity analysis.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = lsubdiv_testkit::fuzzing::check_scheme(data);
});
