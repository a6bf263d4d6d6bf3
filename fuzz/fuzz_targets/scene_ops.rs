#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| glcollide_fuzz::scene_ops::run(data));
