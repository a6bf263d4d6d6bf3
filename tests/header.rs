//! The checked-in include/glcollide.h must be exactly what cbindgen makes from the sources
//! now. To refresh it: `cargo test --test header -- --ignored regenerate` (or run
//! `cbindgen --config cbindgen.toml --output include/glcollide.h`).

use std::path::Path;

fn generate() -> String {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = cbindgen::Config::from_file(dir.join("cbindgen.toml")).expect("cbindgen.toml");
    let mut out = Vec::new();
    cbindgen::Builder::new()
        .with_crate(dir)
        .with_config(config)
        .generate()
        .expect("cbindgen failed")
        .write(&mut out);
    String::from_utf8(out).unwrap()
}

#[test]
fn checked_in_header_is_current() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("include/glcollide.h");
    let on_disk = std::fs::read_to_string(&path).expect("include/glcollide.h");
    let fresh = generate();
    if on_disk != fresh {
        let line = on_disk
            .lines()
            .zip(fresh.lines())
            .position(|(a, b)| a != b)
            .unwrap_or(0);
        panic!(
            "include/glcollide.h is stale (first difference at line {}); regenerate it with \
             `cargo test --test header -- --ignored regenerate`",
            line + 1
        );
    }
}

#[test]
fn every_function_is_documented_and_prefixed() {
    let fresh = generate();
    let lines: Vec<&str> = fresh.lines().collect();
    for (i, l) in lines.iter().enumerate() {
        if let Some(name) = l
            .split('(')
            .next()
            .and_then(|s| s.split_whitespace().last())
        {
            if l.contains('(')
                && !l.starts_with("//")
                && !l.starts_with(' ')
                && !l.starts_with('#')
                && !l.starts_with("typedef")
            {
                let name = name.trim_start_matches('*');
                assert!(name.starts_with("glcol_"), "unprefixed function {name}");
                assert!(lines[i - 1].starts_with("//"), "{name} has no doc comment");
            }
        }
    }
}

#[test]
fn every_macro_and_type_is_prefixed() {
    for l in generate().lines() {
        if let Some(rest) = l.strip_prefix("#define ") {
            let name = rest.split_whitespace().next().unwrap_or("");
            assert!(
                name.starts_with("GLCOL_")
                    || name == "GLCOLLIDE_H"
                    || name.starts_with("glcol_scene_desc_init(")
                    || name.starts_with("glcol_mesh_desc_init("),
                "unprefixed macro {name}"
            );
        }
        if let Some(rest) = l
            .strip_prefix("typedef struct ")
            .or_else(|| l.strip_prefix("typedef enum "))
        {
            assert!(rest.starts_with("Glcol"), "unprefixed type in: {l}");
        }
    }
}

/// The `NAME = value` entries of `typedef enum <name> { ... }` in the header.
fn enum_entries(header: &str, name: &str) -> Vec<(String, u32)> {
    let open = format!("typedef enum {name} {{");
    let mut lines = header.lines().skip_while(|l| *l != open).skip(1);
    let mut entries = Vec::new();
    for l in lines.by_ref() {
        if l.starts_with('}') {
            return entries;
        }
        if let Some((n, v)) = l.trim().trim_end_matches(',').split_once(" = ") {
            entries.push((n.to_string(), v.parse().expect("an enum value")));
        }
    }
    panic!("no typedef enum {name} in the header");
}

/// `glcol_status_name` (its names are made from the Rust enum at compile time, by the rule
/// cbindgen.toml sets) answers exactly the header's name for each value of GlcolStatus,
/// and GLCOL_STATUS_UNKNOWN past them.
#[test]
fn status_names_are_the_headers() {
    let entries = enum_entries(&generate(), "GlcolStatus");
    assert_eq!(entries.len(), 11, "{entries:?}");
    let name = |v: u32| {
        // SAFETY: glcol_status_name returns a static NUL-terminated string, never NULL.
        unsafe { std::ffi::CStr::from_ptr(glcollide::ffi::glcol_status_name(v)) }
            .to_str()
            .unwrap()
            .to_owned()
    };
    for (n, v) in &entries {
        assert_eq!(&name(*v), n, "glcol_status_name({v})");
    }
    let past = entries.iter().map(|e| e.1).max().unwrap() + 1;
    assert_eq!(name(past), "GLCOL_STATUS_UNKNOWN");
    let backends = enum_entries(&generate(), "GlcolBackend");
    let values: Vec<u32> = backends.iter().map(|e| e.1).collect();
    assert_eq!(values, [0, 1, 2, 3], "{backends:?}");
}

#[test]
#[ignore]
fn regenerate() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("include/glcollide.h");
    std::fs::write(path, generate()).unwrap();
}
