//! The oracle itself against hand-made cases whose answers are known by construction.
//! (Inputs are f32 values, as everything the library sees.)
mod common;
use common::oracle::{triangle_distance, triangles_meet};

fn tri(v: [[f32; 3]; 3]) -> [[f64; 3]; 3] {
    v.map(|p| p.map(f64::from))
}

#[test]
fn oracle_known_cases() {
    let t = tri([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let meet = |u: [[f32; 3]; 3]| triangles_meet(&t, &tri(u));
    assert!(meet([[0.2, 0.2, -1.0], [0.2, 0.2, 1.0], [0.3, 0.3, 1.0]]));
    assert!(!meet([[0.2, 0.2, 0.5], [0.2, 0.2, 1.0], [0.3, 0.3, 1.0]]));
    assert!(meet([[1.0, 0.0, 0.0], [2.0, 0.0, 1.0], [2.0, 1.0, 1.0]])); // shared vertex
    assert!(meet([[0.1, 0.1, 0.0], [0.2, 0.1, 0.0], [0.1, 0.2, 0.0]])); // coplanar, inside
    assert!(!meet([[0.6, 0.6, 0.0], [2.0, 0.6, 0.0], [0.6, 2.0, 0.0]])); // coplanar, apart
    assert!(meet([[0.5, 0.5, 0.0], [2.0, 0.5, 0.0], [0.5, 2.0, 0.0]])); // coplanar, touching at a point
    assert!(meet([[0.25, 0.25, 0.0]; 3])); // a point on the face
    assert!(!meet([[0.25, 0.25, 1e-30]; 3]));
    assert!(meet([[0.5, 0.5, -1.0], [0.5, 0.5, 1.0], [0.5, 0.5, 1.0]])); // a segment through the hypotenuse
    assert!(!meet([
        [0.5, 0.5000001, -1.0],
        [0.5, 0.5000001, 1.0],
        [0.5, 0.5000001, 1.0]
    ]));
    let d = triangle_distance(
        &t,
        &tri([[0.2, 0.2, 0.5], [0.2, 0.2, 1.0], [0.3, 0.3, 1.0]]),
    );
    assert!((d - 0.5).abs() < 1e-12, "{d}");
    let d = triangle_distance(
        &t,
        &tri([[2.0, 0.0, 0.0], [3.0, 0.0, 0.0], [2.0, 1.0, 0.0]]),
    );
    assert!((d - 1.0).abs() < 1e-12, "{d}");
}
