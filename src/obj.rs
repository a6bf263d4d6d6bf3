//! A small Wavefront OBJ reader (`v` and `f` lines) for the examples, tests and benchmarks.
//! Faces with more than three corners are split into a fan of triangles; `f` corners may be
//! `i`, `i/t`, `i//n` or `i/t/n`, with negative (relative) indices.

use crate::error::{Error, Result};

/// A triangle mesh read from OBJ text.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ObjMesh {
    /// xyz per vertex.
    pub positions: Vec<[f32; 3]>,
    /// Three vertex indices per triangle, 0-based.
    pub triangles: Vec<u32>,
}

impl ObjMesh {
    /// The mesh in the file at `path` ([`load`]).
    pub fn load(path: impl AsRef<std::path::Path>) -> Result<ObjMesh> {
        load(path)
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len() / 3
    }
}

/// Reads the file at `path`.
pub fn load(path: impl AsRef<std::path::Path>) -> Result<ObjMesh> {
    let path = path.as_ref();
    let text =
        std::fs::read(path).map_err(|e| Error::invalid(format!("{}: {e}", path.display())))?;
    parse(&text).map_err(|e| Error::new(e.kind, format!("{}: {}", path.display(), e.message)))
}

/// Parses OBJ text (bytes, so invalid UTF-8 outside `v`/`f` lines is ignored).
///
/// ```
/// // A unit square as one quad face: split into a fan of two triangles.
/// let m = glcollide::obj::parse(b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n")?;
/// assert_eq!(m.positions.len(), 4);
/// assert_eq!(m.triangles, [0, 1, 2, 0, 2, 3]);
/// // A face naming a vertex that does not exist is refused, naming the line.
/// let e = glcollide::obj::parse(b"v 0 0 0\nf 1 2 3\n").unwrap_err();
/// assert!(e.message.starts_with("line 2"), "{}", e.message);
/// # Ok::<(), glcollide::Error>(())
/// ```
pub fn parse(text: &[u8]) -> Result<ObjMesh> {
    let mut m = ObjMesh::default();
    let mut corners: Vec<u32> = Vec::new();
    for (ln, line) in text.split(|&c| c == b'\n').enumerate() {
        let err = |what: &str| Error::invalid(format!("line {}: {what}", ln + 1));
        let line = std::str::from_utf8(line).map_err(|_| err("not UTF-8"))?;
        let mut it = line.split_ascii_whitespace();
        match it.next() {
            Some("v") => {
                let mut p = [0f32; 3];
                for c in &mut p {
                    let s = it
                        .next()
                        .ok_or_else(|| err("a vertex needs three coordinates"))?;
                    *c = s.parse::<f32>().map_err(|_| err("bad coordinate"))?;
                    if !c.is_finite() {
                        return Err(err("coordinate is not finite"));
                    }
                }
                if m.positions.len() >= u32::MAX as usize {
                    return Err(err("too many vertices"));
                }
                m.positions.push(p);
            }
            Some("f") => {
                corners.clear();
                for c in it {
                    let s = c.split('/').next().unwrap_or("");
                    let i: i64 = s.parse().map_err(|_| err("bad face index"))?;
                    let n = m.positions.len() as i64;
                    let idx = if i > 0 { i - 1 } else { n + i };
                    if i == 0 || idx < 0 || idx >= n {
                        return Err(err("face index out of range"));
                    }
                    corners.push(idx as u32);
                }
                if corners.len() < 3 {
                    return Err(err("a face needs at least three corners"));
                }
                for k in 1..corners.len() - 1 {
                    m.triangles.extend([corners[0], corners[k], corners[k + 1]]);
                }
            }
            _ => {}
        }
    }
    if m.triangles.is_empty() {
        return Err(Error::invalid("no faces"));
    }
    Ok(m)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_faces_of_all_forms() {
        let m = parse(
            b"# x\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1/1 3/3/3 -1//4\nf 1 2 3 4\n",
        )
        .unwrap();
        assert_eq!(m.positions.len(), 4);
        assert_eq!(m.triangles, vec![0, 1, 2, 0, 2, 3, 0, 1, 2, 0, 2, 3]);
    }

    #[test]
    fn errors_name_the_line() {
        assert!(parse(b"v 0 0 0\nv 1 0 0\nf 1 2 3\n")
            .unwrap_err()
            .message
            .starts_with("line 3"));
        assert!(parse(b"v 0 0\n").unwrap_err().message.starts_with("line 1"));
        assert!(parse(b"v 0 0 nan\n").is_err());
        assert!(parse(b"v 0 0 0\n").is_err());
    }

    #[test]
    fn reads_the_bundled_meshes() {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/data");
        let m = load(format!("{dir}/scissors_blade.obj")).unwrap();
        assert_eq!((m.positions.len(), m.triangle_count()), (47, 90));
        let m = load(format!("{dir}/gallbladder_glt.obj")).unwrap();
        assert_eq!(m.triangle_count(), 14_700);
    }
}
