//! A small random L-system through parse → compile → curve refinement → surface refinement.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = lsubdiv_testkit::fuzzing::check_pipeline(data);
});
