use glcollide::internals::contact::{contact_geometry_many, ContactGeometry};
type T = [[f64; 3]; 3];
fn read(p: &str) -> Vec<(T, T)> {
    let txt = std::fs::read_to_string(p).unwrap();
    let mut pairs = vec![];
    for l in txt.lines() {
        let nums: Vec<f64> = l
            .replace(['[', ']', ','], " ")
            .split_whitespace()
            .skip(1)
            .map(|x| x.parse().unwrap())
            .collect();
        let t = |o: usize| {
            [
                [nums[o], nums[o + 1], nums[o + 2]],
                [nums[o + 3], nums[o + 4], nums[o + 5]],
                [nums[o + 6], nums[o + 7], nums[o + 8]],
            ]
        };
        pairs.push((t(0), t(9)));
    }
    pairs
}
#[test]
fn four() {
    for f in ["/tmp/colon_pairs.txt", "/tmp/blade_pairs.txt"] {
        let pairs = read(f);
        let reps: usize = std::env::var("REPS")
            .map(|x| x.parse().unwrap())
            .unwrap_or(100);
        let mut out = vec![
            ContactGeometry {
                point_a: [0.0; 3],
                point_b: [0.0; 3],
                normal: [0.0; 3],
                depth: 0.0,
                intersecting: false,
                coplanar: false
            };
            pairs.len()
        ];
        let mut best = f64::INFINITY;
        let mut s = 0.0;
        for _ in 0..5 {
            let t = std::time::Instant::now();
            for _ in 0..reps {
                contact_geometry_many::<(), _>(&mut out, true, |i, a, b| {
                    a[0] = pairs[i].0;
                    b[0] = pairs[i].1;
                    Ok((1, 1))
                })
                .unwrap();
                s += out[0].depth;
            }
            best = best.min(t.elapsed().as_nanos() as f64 / (reps * pairs.len()) as f64);
        }
        let h: f64 = out
            .iter()
            .map(|g| g.depth + g.point_a[0] + g.normal[1])
            .sum();
        eprintln!(
            "{f}: {} pairs ns/pair {best:.1} check {h:.17e} {s}",
            pairs.len()
        );
    }
}
