//! Fuzz target (b): the OBJ reader the examples use (`glcol_obj_load` reads a file and
//! hands it to this parser). Any input either fails with a message naming a line or gives
//! a mesh the library accepts: finite coordinates, indices in range, whole triangles.
//! Small results also go through a scene (two copies, one moved) and a query.

use glcollide::obj::parse;
use glcollide::{Positions, Scene, SceneConfig};

pub fn run(data: &[u8]) {
    let m = match parse(data) {
        Ok(m) => m,
        Err(e) => {
            assert!(!e.message.is_empty());
            return;
        }
    };
    assert!(!m.triangles.is_empty() && m.triangles.len() % 3 == 0);
    assert!(m
        .triangles
        .iter()
        .all(|&i| (i as usize) < m.positions.len()));
    assert!(m.positions.iter().flatten().all(|v| v.is_finite()));
    if m.triangles.len() > 3 * 2000 {
        return;
    }
    let mut s = Scene::new(SceneConfig {
        epsilon: 0.0,
        max_polygons_per_box: 4,
        ..SceneConfig::default()
    })
    .unwrap();
    let a = s
        .create_mesh(Positions::from_points(&m.positions), &m.triangles, 3)
        .expect("a parsed OBJ is a valid mesh");
    let moved: Vec<[f32; 3]> = m
        .positions
        .iter()
        .map(|p| [p[0] + 0.5, p[1], p[2]])
        .collect();
    if moved.iter().flatten().all(|v| v.is_finite()) {
        let b = s
            .create_mesh(Positions::from_points(&moved), &m.triangles, 3)
            .unwrap();
        let n = s.query(a).unwrap().len();
        assert!(
            s.query(b).unwrap().len() == n,
            "swapped query differs in size"
        );
    }
}
