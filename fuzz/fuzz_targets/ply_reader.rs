//! PLY files: arbitrary bytes through the reader, the topology check and the writers.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = lsubdiv_testkit::fuzzing::check_ply(data);
});
