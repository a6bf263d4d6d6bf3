//! docs/API.md kept in step with include/glcollide.h: every `glcol_*` function, `Glcol*`
//! type and `GLCOL_*` constant the header declares is named in the reference's shipped part
//! (above its "Planned for 0.3" section), and every such name the shipped part gives exists
//! in the header. Names in the 0.3 section are exempt from the second rule (they are not in
//! the library yet); once the header declares one, the first rule asks for it above.

use std::collections::BTreeSet;
use std::path::Path;

/// The heading of the section of docs/API.md whose names are not in the library yet.
const PLANNED: &str = "\n## Planned for 0.3";

fn read(rel: &str) -> String {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join(rel);
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// The API names in `text`: words that start with `glcol_`, `GLCOL_` or `Glcol` and a
/// capital letter. A bare prefix or a word ending in `_` (as in `GLCOL_STATUS_*`) is a
/// pattern, not a name.
fn names(text: &str) -> BTreeSet<String> {
    text.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .filter(|w| {
            let api = w.starts_with("glcol_")
                || w.starts_with("GLCOL_")
                || (w.starts_with("Glcol") && w[5..].starts_with(|c: char| c.is_ascii_uppercase()));
            api && !w.ends_with('_')
        })
        .map(str::to_string)
        .collect()
}

/// C source without its comments (`//` to the end of the line, `/* ... */`).
fn without_comments(c: &str) -> String {
    let mut out = String::new();
    let mut rest = c;
    while !rest.is_empty() {
        let line = rest.find("//");
        let block = rest.find("/*");
        match (line, block) {
            (Some(l), b) if b.is_none_or(|b| l < b) => {
                out.push_str(&rest[..l]);
                rest = rest[l..].find('\n').map_or("", |e| &rest[l + e..]);
            }
            (_, Some(b)) => {
                out.push_str(&rest[..b]);
                rest = rest[b..].find("*/").map_or("", |e| &rest[b + e + 2..]);
            }
            _ => {
                out.push_str(rest);
                rest = "";
            }
        }
    }
    out
}

/// The names the header declares (its code, not its comments).
fn declared() -> BTreeSet<String> {
    let d = names(&without_comments(&read("include/glcollide.h")));
    // A parse that finds nothing would pass every check below.
    for must in [
        "glcol_query",
        "GlcolSceneDesc",
        "GLCOL_STATUS_OK",
        "GLCOL_ABI_VERSION",
    ] {
        assert!(d.contains(must), "the header parse lost {must}: {d:?}");
    }
    d
}

/// Text without its double-quoted strings (a string a function returns, such as
/// "GLCOL_STATUS_UNKNOWN", is not a declared name), line by line.
fn without_strings(text: &str) -> String {
    text.lines()
        .map(|l| {
            l.split('"')
                .enumerate()
                .filter(|(i, _)| i % 2 == 0)
                .map(|(_, s)| s)
                .collect::<Vec<_>>()
                .join(" ")
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// docs/API.md's shipped part and its 0.3 part, double-quoted strings left out.
fn reference() -> (String, String) {
    let doc = without_strings(&read("docs/API.md"));
    let at = doc
        .find(PLANNED)
        .unwrap_or_else(|| panic!("docs/API.md has no heading {:?}", PLANNED.trim()));
    (doc[..at].to_string(), doc[at..].to_string())
}

#[test]
fn every_name_the_header_declares_is_in_the_reference() {
    let (shipped, _) = reference();
    let documented = names(&shipped);
    let missing: Vec<_> = declared().difference(&documented).cloned().collect();
    assert!(
        missing.is_empty(),
        "include/glcollide.h declares names that docs/API.md does not describe (above \
         \"Planned for 0.3\"): {missing:?}"
    );
}

#[test]
fn every_shipped_name_in_the_reference_is_in_the_header() {
    let (shipped, _) = reference();
    let unknown: Vec<_> = names(&shipped).difference(&declared()).cloned().collect();
    assert!(
        unknown.is_empty(),
        "docs/API.md names, as shipped, what include/glcollide.h does not declare (move \
         planned names under \"Planned for 0.3\"): {unknown:?}"
    );
}

#[test]
fn the_reference_plans_what_the_library_does_not_have_yet() {
    let (shipped, planned) = reference();
    let only_planned: BTreeSet<_> = names(&planned)
        .difference(&names(&shipped))
        .cloned()
        .collect();
    assert!(
        only_planned.is_empty() || only_planned.contains("glcol_query_impact_geometry"),
        "{only_planned:?}"
    );
}

#[test]
fn the_name_scanner_skips_comments_and_patterns() {
    let c = "// glcol_commented\n/* GLCOL_BLOCK\n */ int glcol_real(GlcolType *t); // x\n";
    let found = names(&without_comments(c));
    assert_eq!(found, ["GlcolType", "glcol_real"].map(String::from).into());
    let text = "`GLCOL_STATUS_*` and `glcol_` and `Glcol*`, Glcollide, GLCOL_OK \"GLCOL_NO\".";
    assert_eq!(
        names(&without_strings(text)),
        ["GLCOL_OK"].map(String::from).into()
    );
}
