//! OBJ files: arbitrary bytes through the reader and the topology check.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = lsubdiv_testkit::fuzzing::check_obj(data);
});
