#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| glcollide_fuzz::obj_parse::run(data));
