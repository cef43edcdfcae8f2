#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| shadowtruth_cli::fuzzing::obj_reader(data));
