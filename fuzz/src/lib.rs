//! The fuzz targets' bodies, as plain functions so that `tests/ffi_fuzz_regressions.rs`
//! replays the seeds and every kept crashing input in the ordinary test pass.

#[path = "../../tests/common/oracle.rs"]
pub mod oracle;

pub mod obj_parse;
pub mod scene_ops;
