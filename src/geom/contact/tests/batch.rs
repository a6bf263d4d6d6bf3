//! Tests of many pairs at once: every entry of memory not initialized yet is written, and
//! pairs four at a time answer as one at a time, bit for bit.

use std::mem::MaybeUninit;

use super::support::*;
use super::AVX2_ONLY;
#[cfg(target_arch = "x86_64")]
use crate::geom::contact::four;
use crate::geom::contact::{contact_geometry, contact_geometry_into, ContactGeometry};
#[cfg(target_arch = "x86_64")]
use crate::geom::lanes::TriLanes;
use crate::geom::test_rng::Rng;

/// `contact_geometry_into` writes every entry of memory it is given uninitialized (a
/// vector's spare capacity filled with a poison first): crossing, apart, quad, segment
/// and point pairs mixed, every batch remainder and the 64-pair chunks' sizes, known or
/// not, each kernel; every entry is then `contact_geometry`'s answer bit for bit. (From
/// a review of the lanes' unsafe writes.)
#[test]
fn every_entry_of_spare_capacity_is_written() {
    let mut r = Rng(0xBEEF5);
    let mut pairs: Vec<(Polygon, Polygon)> = Vec::new();
    for i in 0..3000 {
        let (o, sc) = FRAMES[i % FRAMES.len()];
        let c = [o, -0.5 * o, 0.25 * o];
        let (a, b) = crossing_pair(&mut r, &c, sc);
        let (a, b) = match i % 6 {
            0 => (Polygon::tri([a.t[0][0], a.t[0][0], a.t[0][1]]), b),
            1 => (a, Polygon::tri([b.t[0][2], b.t[0][1], b.t[0][1]])),
            2 => (a, b.moved(&[0.0, 0.0, 3.0 * sc])),
            3 => {
                let t = a.t[0];
                (Polygon::quad([t[0], t[1], t[2], plus(&t[0], &r.v(sc))]), b)
            }
            4 => (Polygon::tri([a.t[0][0]; 3]), b),
            _ => (a, b),
        };
        pairs.push((a, b));
    }
    let poison = ContactGeometry {
        point_a: [f64::from_bits(0x7ff8_dead_beef_0001); 3],
        point_b: [f64::NAN; 3],
        normal: [f64::NAN; 3],
        depth: f64::NAN,
        intersecting: true,
        coplanar: true,
    };
    let bits = |g: &ContactGeometry| bits(&plus_zero(g));
    for known in [false, true] {
        for len in [1usize, 2, 3, 4, 5, 7, 9, 63, 64, 65, 257, 3000] {
            for avx2 in [false, true] {
                let mut v = vec![poison; len];
                v.clear();
                AVX2_ONLY.with(|c| c.set(avx2));
                let spare = &mut v.spare_capacity_mut()[..len];
                contact_geometry_into(spare, known, fetch_from(&pairs)).unwrap();
                AVX2_ONLY.with(|c| c.set(false));
                // SAFETY: the call returned Ok, so it wrote the first `len` entries.
                unsafe { v.set_len(len) };
                for (k, g) in v.iter().enumerate() {
                    let want = geometry(&pairs[k].0, &pairs[k].1);
                    // (`known` with a pair apart is a caller's error: not compared.)
                    if known && !want.intersecting {
                        continue;
                    }
                    assert_eq!(bits(g), bits(&want), "known {known} len {len} pair {k}");
                }
            }
        }
    }
}

/// Pairs known to intersect, four at a time (`four.rs`), answer as `contact_geometry`
/// bit for bit: random crossings at every scale and offset, crossings at shallow
/// angles, touching and grid pairs (vertices on planes, edges along planes: lanes left
/// to the scalar path), quads among them; and the lanes do take most crossing pairs.
#[test]
fn intersecting_four_at_a_time_is_contact_geometry() {
    let mut r = Rng(0x4C41_4E45);
    let mut pairs = Vec::new();
    for i in 0..60_000 {
        let (o, sc) = FRAMES[i % FRAMES.len()];
        let c = [o, 0.5 * o, -o];
        let (a, b) = match i % 6 {
            0..=2 => crossing_pair(&mut r, &c, sc),
            3 => {
                // Nearly parallel planes: long thin intersections, shaky cut ends.
                let (a, mut b) = crossing_pair(&mut r, &c, sc);
                let t = a.t[0];
                let x = combo(&t, &r.bary());
                let tilt = 10f64.powi(-((r.next() % 7) as i32));
                for (k, v) in b.t[0].iter_mut().enumerate() {
                    let w = [0, 1, 2].map(|m| t[k][m] - t[0][m]);
                    let h = r.v(sc * tilt);
                    *v = [0, 1, 2].map(|m| f32r(x[m] + (w[m] - 0.3 * (t[1][m] - t[0][m])) + h[m]));
                }
                (a, b)
            }
            4 => {
                let grid = |r: &mut Rng| [0, 1, 2].map(|k| c[k] + sc * (r.next() % 3) as f64 / 2.0);
                let mut t = || [grid(&mut r), grid(&mut r), grid(&mut r)];
                (Polygon::tri(t()), Polygon::tri(t()))
            }
            _ => {
                let (t, u) = crossing_pair(&mut r, &c, sc);
                let q = t.t[0];
                let far = [0, 1, 2].map(|k| q[1][k] + q[2][k] - q[0][k]);
                (Polygon::quad([q[0], q[1], far, q[2]]), u)
            }
        };
        if meet(&a, &b) {
            pairs.push((a, b));
        }
    }
    let mut out = vec![geometry(&pairs[0].0, &pairs[0].1); pairs.len()];
    both_kernels(&mut out, true, fetch_from(&pairs)).unwrap();
    let bits = |g: &ContactGeometry| bits(&plus_zero(g));
    for ((a, b), g) in pairs.iter().zip(&out) {
        assert_eq!(bits(g), bits(&geometry(a, b)), "{a:?} {b:?}");
    }
    // Were a caller wrong about its pairs (pairs apart by more than rounding), the
    // answers are still the exact ones: such lanes go to the scalar path.
    let mut apart = Vec::new();
    while apart.len() < 4000 {
        let (a, b) = crossing_pair(&mut r, &[0.0; 3], 1.0);
        let b = b.moved(&r.v(0.8).map(f32r));
        if !meet(&a, &b) {
            apart.push((a, b));
        }
    }
    let mut out = vec![geometry(&apart[0].0, &apart[0].1); apart.len()];
    both_kernels(&mut out, true, fetch_from(&apart)).unwrap();
    for ((a, b), g) in apart.iter().zip(&out) {
        assert!(!g.intersecting, "{a:?} {b:?}");
        assert_eq!(bits(g), bits(&geometry(a, b)), "{a:?} {b:?}");
    }
    // Not known (a query within a band): intersecting and apart pairs mixed, the
    // lanes' exact test picks the crossing ones.
    let mixed: Vec<_> = pairs
        .iter()
        .zip(apart.iter().cycle())
        .flat_map(|(p, q)| [*p, *q])
        .collect();
    let mut out = vec![geometry(&mixed[0].0, &mixed[0].1); mixed.len()];
    both_kernels(&mut out, false, fetch_from(&mixed)).unwrap();
    for ((a, b), g) in mixed.iter().zip(&out) {
        assert_eq!(bits(g), bits(&geometry(a, b)), "{a:?} {b:?}");
    }
    // The lanes themselves: how many crossing pairs they answer.
    #[cfg(target_arch = "x86_64")]
    {
        if !(std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")) {
            println!("no AVX2: the lanes are not used");
            return;
        }
        let tris: Vec<_> = pairs
            .iter()
            .filter(|(a, b)| a.n == 1 && b.n == 1)
            .map(|(a, b)| (a.t[0], b.t[0]))
            .collect();
        let (mut fast, mut all) = (0, 0);
        for chunk in tris.chunks_exact(four::LANES) {
            let (mut a, mut b): (TriLanes, TriLanes) = (TriLanes::ZERO, TriLanes::ZERO);
            for (l, (t, u)) in chunk.iter().enumerate() {
                a.set(l, t);
                b.set(l, u);
            }
            // (Every field overwritten where answered: none of these survives.)
            let unset = ContactGeometry {
                point_a: [f64::NAN; 3],
                point_b: [f64::NAN; 3],
                normal: [f64::NAN; 3],
                depth: f64::NAN,
                intersecting: false,
                coplanar: true,
            };
            let mut out = [MaybeUninit::new(unset); four::LANES];
            // SAFETY: the CPU has AVX2 and FMA (checked above); `at` is in `out`.
            let ok = unsafe {
                let (ta, tb) = (a.load(), b.load());
                four::crossing(&ta, &tb, 0b1111, &[0, 1, 2, 3], &mut out)
            };
            // SAFETY: every entry was initialized (and the kernel writes whole fields).
            let out = out.map(|g| unsafe { g.assume_init() });
            for (l, (t, u)) in chunk.iter().enumerate() {
                all += 1;
                if ok & (1 << l) != 0 {
                    fast += 1;
                    let want = contact_geometry(&[*t; 2], 1, &[*u; 2], 1);
                    assert_eq!(bits(&out[l]), bits(&want), "{t:?} {u:?}");
                } else {
                    assert!(out[l].depth.is_nan(), "lane {l} not answered but written");
                }
            }
        }
        println!("four lanes answered {fast} of {all} intersecting triangle pairs");
        assert!(
            pairs.len() > 20_000 && fast * 10 > all * 8,
            "{fast} of {all}"
        );
    }
}
