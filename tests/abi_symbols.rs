//! ABI discipline (docs/INSTALL.md "ABI and soname policy"): the shared library cargo just built
//! (libglcollide.so in target/<profile>/deps/, beside this test's binary) exports exactly the
//! functions include/glcollide.h declares: nothing by accident (no Rust internals, no mangled
//! names, no symbols of dependencies), nothing declared missing. Read with `nm -D
//! --defined-only` (binutils). scripts/test.d/80-install.sh checks the same on the library
//! cargo-c installs.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Function names declared by the header: declarations start in column 0 (comments start
/// with `//` or ` *`), and each names one `glcol_...(`.
fn header_functions() -> BTreeSet<String> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("include/glcollide.h");
    let text = std::fs::read_to_string(&path).expect("include/glcollide.h");
    let mut names = BTreeSet::new();
    for line in text.lines() {
        if !line.starts_with(|c: char| c.is_ascii_alphabetic()) {
            continue;
        }
        let mut rest = line;
        while let Some(i) = rest.find("glcol_") {
            let tail = &rest[i..];
            let end = tail
                .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                .unwrap_or(tail.len());
            let boundary =
                i == 0 || !rest[..i].ends_with(|c: char| c.is_ascii_alphanumeric() || c == '_');
            if boundary && tail[end..].starts_with('(') {
                names.insert(tail[..end].to_string());
            }
            rest = &tail[end..];
        }
    }
    names
}

/// The cdylib cargo built for this test run. The test binary lives in target/<profile>/deps/;
/// cargo writes the library there (and copies it up to target/<profile>/ on `cargo build`).
fn shared_library() -> PathBuf {
    let exe = std::env::current_exe().expect("current_exe");
    let deps = exe.parent().expect("test binary directory");
    let candidates = [
        deps.join("libglcollide.so"),
        deps.parent().unwrap_or(deps).join("libglcollide.so"),
    ];
    candidates
        .iter()
        .find(|p| p.exists())
        .unwrap_or_else(|| {
            panic!("libglcollide.so not built (crate-type cdylib?): looked at {candidates:?}")
        })
        .clone()
}

fn exported_symbols(lib: &Path) -> BTreeSet<String> {
    let out = Command::new("nm")
        .args(["-D", "--defined-only"])
        .arg(lib)
        .output()
        .unwrap_or_else(|e| panic!("running nm (binutils) failed: {e}"));
    assert!(
        out.status.success(),
        "nm -D --defined-only {} failed: {}",
        lib.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout)
        .expect("nm output")
        .lines()
        .filter_map(|l| {
            // "<address> <type> <name>"; name may carry a version suffix "@VER" / "@@VER".
            let mut f = l.split_whitespace();
            let (_addr, kind, name) = (f.next()?, f.next()?, f.next()?);
            // Version-definition entries (type A, absolute) name a version node, not code.
            (kind != "A").then(|| name.split('@').next().unwrap_or(name).to_string())
        })
        .collect()
}

#[test]
fn header_declares_the_c_api() {
    let fns = header_functions();
    for must in [
        "glcol_abi_version",
        "glcol_version",
        "glcol_query",
        "glcol_scene_create",
    ] {
        assert!(fns.contains(must), "header parse found no {must}: {fns:?}");
    }
}

#[cfg(target_os = "linux")]
#[test]
fn shared_library_exports_exactly_the_header_functions() {
    let lib = shared_library();
    let exported = exported_symbols(&lib);
    let declared = header_functions();

    let accidental: Vec<&String> = exported.difference(&declared).collect();
    let mangled: Vec<&&String> = accidental
        .iter()
        .filter(|s| s.starts_with("_ZN") || s.starts_with("_R"))
        .collect();
    let missing: Vec<&String> = declared.difference(&exported).collect();
    assert!(
        accidental.is_empty() && missing.is_empty(),
        "{} exports differ from include/glcollide.h:\n  exported but not declared \
         ({} mangled Rust names among them): {accidental:?}\n  declared but not exported: \
         {missing:?}\n(only `#[no_mangle] pub extern \"C\"` items of src/ffi may be exported, \
         and each must be in the header)",
        lib.display(),
        mangled.len()
    );
    assert!(
        exported.iter().all(|s| s.starts_with("glcol_")),
        "every export carries the glcol_ prefix: {exported:?}"
    );
}
