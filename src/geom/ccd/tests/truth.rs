//! The exact public ground truth of three simulation steps (`../shared/meshes/sim/ccd`):
//! every query's answer must agree with its boolean, and every time of impact must pass the
//! reference's checks ([`super::check_toi`]).

use super::super::predicate::Kind;
use super::super::{decide, Points, Stage};
use super::check_toi;
use std::collections::HashMap;

/// The ground truth's folder.
const DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/meshes/sim/ccd");

/// The scenes: folder, step's first frame, whether the edge-edge coordinates are in a CSV
/// (else in the parts file).
pub(super) const SCENES: [(&str, u32, bool); 3] = [
    ("cloth-funnel", 227, true),
    ("rod-twist", 3036, true),
    ("armadillo-rollers", 326, false),
];

/// One query and its truth.
pub(super) struct Query {
    pub(super) pts: Points,
    pub(super) truth: bool,
}

/// Is the ground truth there? If not, says so on stderr (the test then returns).
pub(super) fn has_truth(test: &str) -> bool {
    use std::io::Write;
    let there = std::path::Path::new(DIR).exists();
    if !there {
        let _ = writeln!(
            std::io::stderr(),
            "skipped: needs ../shared/meshes/sim/ccd ({test})"
        );
    }
    there
}

/// `num / den` as the double it is exactly (the files promise it; checked).
fn exact_double(num: &str, den: &str) -> f64 {
    let n: i128 = num.parse().expect("numerator");
    let d: i128 = den.parse().expect("denominator");
    assert!(d > 0 && (d as u128).is_power_of_two(), "{num}/{den}");
    assert!(n.unsigned_abs() < 1 << 53, "{num}/{den}");
    let x = n as f64 / d as f64;
    assert_eq!(x * d as f64, n as f64, "{num}/{den} is not a double");
    x
}

/// The booleans of a `*_mma_bool.json`.
fn booleans(path: &str) -> Vec<bool> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path}: {e}"));
    text.trim()
        .trim_start_matches('[')
        .trim_end_matches(']')
        .split(',')
        .map(|s| match s.trim() {
            "true" => true,
            "false" => false,
            o => panic!("{path}: {o}"),
        })
        .collect()
}

/// The queries of a CSV (8 rows each: the four points at the start, then at the end).
fn from_csv(path: &str) -> Vec<Points> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let rows: Vec<[f64; 3]> = text
        .lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            assert_eq!(f.len(), 6, "{path}: {l}");
            std::array::from_fn(|k| exact_double(f[2 * k], f[2 * k + 1]))
        })
        .collect();
    assert_eq!(rows.len() % 8, 0, "{path}");
    rows.chunks(8)
        .map(|c| std::array::from_fn(|i| [c[i], c[i + 4]]))
        .collect()
}

/// The vertices of a part OBJ, as the doubles it holds.
fn obj_vertices(path: &str) -> Vec<[f64; 3]> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path}: {e}"));
    text.lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| {
            let v: Vec<f64> = l
                .split_whitespace()
                .map(|x| x.parse().expect("coordinate"))
                .collect();
            [v[0], v[1], v[2]]
        })
        .collect()
}

/// The edge-edge queries of a parts file (coordinates from the frames' part OBJs).
fn ee_from_parts(scene: &str, frame: u32) -> Vec<(Points, bool)> {
    let path = format!("{DIR}/{scene}/{frame}ee_parts.tsv");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let mut parts: HashMap<(u32, usize), Vec<[f64; 3]>> = HashMap::new();
    let mut vertex = |f: u32, part: usize, i: usize| -> [f64; 3] {
        parts.entry((f, part)).or_insert_with(|| {
            obj_vertices(&format!("{DIR}/../{scene}/frame{f}_part{part:02}.obj"))
        })[i]
    };
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .map(|l| {
            let f: Vec<usize> = l
                .split_whitespace()
                .map(|x| x.parse().expect("index"))
                .collect();
            let ids = [(f[0], f[1]), (f[0], f[2]), (f[3], f[4]), (f[3], f[5])];
            let pts = ids.map(|(part, i)| [vertex(frame, part, i), vertex(frame + 1, part, i)]);
            (pts, f[6] == 1)
        })
        .collect()
}

/// The queries of a scene of one kind, with their truth.
pub(super) fn load(scene: &str, frame: u32, csv_ee: bool, kind: Kind) -> Vec<Query> {
    let tag = match kind {
        Kind::VertexFace => "vf",
        Kind::EdgeEdge => "ee",
    };
    let truth = booleans(&format!("{DIR}/{scene}/{frame}{tag}_mma_bool.json"));
    let pts = if kind == Kind::VertexFace || csv_ee {
        from_csv(&format!("{DIR}/{scene}/{frame}{tag}.csv"))
    } else {
        let q = ee_from_parts(scene, frame);
        // The parts file's own truth column agrees with the booleans.
        assert!(q.iter().zip(&truth).all(|(q, t)| q.1 == *t));
        q.into_iter().map(|q| q.0).collect()
    };
    assert_eq!(pts.len(), truth.len(), "{scene} {tag}");
    pts.into_iter()
        .zip(truth)
        .map(|(pts, truth)| Query { pts, truth })
        .collect()
}

/// Every query of a scene against its truth; the toi of every true one checked by the
/// reference (of every 8th on the armadillo step: its rational arithmetic takes about 3 ms
/// a pair, and the step has 24k).
fn scene(name: &str, test: &str) {
    if !has_truth(test) {
        return;
    }
    let &(scene, frame, csv_ee) = SCENES.iter().find(|s| s.0 == name).expect("scene");
    for kind in [Kind::VertexFace, Kind::EdgeEdge] {
        let queries = load(scene, frame, csv_ee, kind);
        let (mut agree, mut exact, mut trues, mut checked) = (0, 0, 0, 0);
        let stride = if scene == "armadillo-rollers" { 8 } else { 1 };
        let mut wrong = Vec::new();
        for (i, q) in queries.iter().enumerate() {
            let (got, stage) = decide(kind, &q.pts);
            exact += usize::from(stage == Stage::Exact);
            if got.is_some() == q.truth {
                agree += 1;
            } else {
                wrong.push(i);
            }
            if let Some(toi) = got {
                if trues % stride == 0 {
                    check_toi(kind, &q.pts, toi, None);
                    checked += 1;
                }
                trues += 1;
            }
        }
        eprintln!(
            "{scene} {kind:?}: {agree} of {} agree ({trues} true, {checked} tois checked), \
             {exact} decided exactly",
            queries.len()
        );
        assert!(wrong.is_empty(), "{scene} {kind:?}: wrong at {wrong:?}");
    }
}

#[test]
fn cloth_funnel_agrees_with_the_ground_truth() {
    scene("cloth-funnel", "cloth_funnel_agrees_with_the_ground_truth");
}

#[test]
fn rod_twist_agrees_with_the_ground_truth() {
    scene("rod-twist", "rod_twist_agrees_with_the_ground_truth");
}

#[test]
fn armadillo_rollers_agrees_with_the_ground_truth() {
    scene(
        "armadillo-rollers",
        "armadillo_rollers_agrees_with_the_ground_truth",
    );
}
