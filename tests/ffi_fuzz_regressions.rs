//! Replays the fuzz targets' seeds and every kept crashing input (fuzz/regressions/) in the
//! ordinary test pass, plus a few hundred pseudo-random inputs, with the targets' own bodies
//! (fuzz/src/*.rs): the same model, the same oracle checks, no libFuzzer needed.

#[path = "common/oracle.rs"]
mod oracle;

#[path = "../fuzz/src/obj_parse.rs"]
mod obj_parse;
#[path = "../fuzz/src/scene_ops.rs"]
mod scene_ops;

use std::path::Path;

fn inputs(target: &str) -> Vec<(String, Vec<u8>)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz");
    let mut v = Vec::new();
    for dir in ["seeds", "regressions"] {
        let Ok(rd) = std::fs::read_dir(root.join(dir).join(target)) else {
            continue;
        };
        for e in rd {
            let p = e.unwrap().path();
            if p.is_file() && p.file_name().is_some_and(|n| n != ".gitkeep") {
                v.push((p.display().to_string(), std::fs::read(&p).unwrap()));
            }
        }
    }
    v.sort();
    v
}

fn replay(target: &str, run: fn(&[u8])) {
    let all = inputs(target);
    assert!(!all.is_empty(), "no seeds for {target}");
    for (name, data) in all {
        if let Err(e) = std::panic::catch_unwind(|| run(&data)) {
            std::panic::resume_unwind(Box::new(format!(
                "{name}: {:?}",
                e.downcast_ref::<String>()
            )));
        }
    }
}

#[test]
fn scene_ops_seeds_and_regressions() {
    replay("scene_ops", scene_ops::run);
}

#[test]
fn obj_parse_seeds_and_regressions() {
    replay("obj_parse", obj_parse::run);
}

#[test]
fn scene_ops_on_pseudo_random_inputs() {
    let mut x = 0x9E37_79B9_7F4A_7C15u64;
    for i in 0..400 {
        let n = 16 + i % 300;
        let data: Vec<u8> = (0..n)
            .map(|_| {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                (x >> 24) as u8
            })
            .collect();
        scene_ops::run(&data);
    }
}
