//! The plane filter's certain signs (`Plane::sides`) against the exact `orient3d`, on
//! adversarial inputs: random f32 bit patterns, big offsets with tiny triangles, slivers
//! down to 2^-80, coordinates near f32::MAX, subnormals next to normal values, and integer
//! grids with many exact zeros. A wrong certain sign would change exact answers (the exact
//! triangle test takes them as given); hinted and unhinted triangle tests must agree.
use glcollide::internals::predicates::orient3d;
use glcollide::internals::tritri::{triangles_intersect, triangles_intersect_with, Plane};

struct R(u64);
impl R {
    fn u(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    fn f(&mut self) -> f64 {
        (self.u() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn any_f32(&mut self) -> f32 {
        // random bits, finite
        loop {
            let x = f32::from_bits(self.u() as u32);
            if x.is_finite() {
                return x;
            }
        }
    }
    fn scaled(&mut self) -> f64 {
        let e = (self.u() % 250) as i32 - 140;
        let s = if self.u() & 1 == 0 { 1.0 } else { -1.0 };
        s * self.f() * 2f64.powi(e)
    }
}

fn f(x: f64) -> f64 {
    x as f32 as f64
}

#[test]
fn plane_sides_are_right_whenever_certain() {
    let mut r = R(0x9e3779b97f4a7c15);
    let mut certain = 0u64;
    let mut bad = 0u64;
    for i in 0..300_000u64 {
        let mode = i % 6;
        let mut t = [[0.0f64; 3]; 3];
        let mut u = [[0.0f64; 3]; 3];
        match mode {
            0 => {
                for v in t.iter_mut().chain(u.iter_mut()) {
                    for c in v.iter_mut() {
                        *c = r.any_f32() as f64;
                    }
                }
            }
            1 => {
                // big offset, tiny triangle, points near plane
                let base = [r.scaled(), r.scaled(), r.scaled()];
                let sc = r.scaled().abs();
                for v in t.iter_mut() {
                    for k in 0..3 {
                        v[k] = f(base[k] + (r.f() - 0.5) * sc);
                    }
                }
                for v in u.iter_mut() {
                    let (a, b) = (r.f() * 2.0 - 0.5, r.f() * 2.0 - 0.5);
                    let off = (r.f() - 0.5) * sc * 2f64.powi(-((r.u() % 60) as i32));
                    for k in 0..3 {
                        v[k] = f(t[0][k]
                            + a * (t[1][k] - t[0][k])
                            + b * (t[2][k] - t[0][k])
                            + if k == 2 { off } else { 0.0 });
                    }
                }
            }
            2 => {
                // sliver: t2 near line t0 t1
                let base = [r.scaled(), r.scaled(), r.scaled()];
                let sc = r.scaled().abs();
                for k in 0..3 {
                    t[0][k] = f(base[k]);
                    t[1][k] = f(base[k] + (r.f() - 0.5) * sc);
                }
                let a = r.f();
                let off = sc * 2f64.powi(-((r.u() % 80) as i32));
                let (t0, t1) = (t[0], t[1]);
                t[2] = [0, 1, 2].map(|k| f(t0[k] + a * (t1[k] - t0[k]) + (r.f() - 0.5) * off));
                for v in u.iter_mut() {
                    let (a, b) = (r.f() * 3.0 - 1.0, r.f() * 3.0 - 1.0);
                    for k in 0..3 {
                        v[k] = f(t[0][k]
                            + a * (t[1][k] - t[0][k])
                            + b * (t[2][k] - t[0][k])
                            + (r.f() - 0.5) * off * r.f());
                    }
                }
            }
            3 => {
                // huge coords near f32::MAX
                for v in t.iter_mut().chain(u.iter_mut()) {
                    for c in v.iter_mut() {
                        *c = f((r.f() * 2.0 - 1.0) * 3.4e38);
                    }
                }
                // put u on the plane approx
                for v in u.iter_mut() {
                    let (a, b) = (r.f(), r.f());
                    for k in 0..3 {
                        let x = t[0][k] + a * (t[1][k] - t[0][k]) + b * (t[2][k] - t[0][k]);
                        v[k] = f(x.clamp(-3.4e38, 3.4e38));
                    }
                }
            }
            4 => {
                // subnormal scale next to normal values
                for v in t.iter_mut().chain(u.iter_mut()) {
                    for c in v.iter_mut() {
                        let small = f32::from_bits((r.u() % 0x0100_0000) as u32) as f64
                            * if r.u() & 1 == 0 { 1.0 } else { -1.0 };
                        *c = if r.u().is_multiple_of(4) {
                            f(r.scaled())
                        } else {
                            small
                        };
                    }
                }
            }
            _ => {
                // integer grid: many exact zeros
                for v in t.iter_mut().chain(u.iter_mut()) {
                    for c in v.iter_mut() {
                        *c = ((r.u() % 5) as f64 - 2.0) * 2f64.powi((r.u() % 40) as i32 - 20);
                    }
                }
            }
        }
        let s = Plane::of(&t).sides(&u);
        for k in 0..3 {
            if s[k] != 0 {
                certain += 1;
                let o = orient3d(&t[0], &t[1], &t[2], &u[k]);
                if f64::from(s[k]) != o.signum() || o == 0.0 {
                    bad += 1;
                    if bad < 10 {
                        eprintln!("BAD mode {mode} {t:?} {u:?} k={k} sides={s:?} o={o}");
                    }
                }
            }
        }
        if i % 7 == 0 {
            let st = Plane::of(&u).sides(&t);
            assert_eq!(
                triangles_intersect_with(&t, &u, s, st),
                triangles_intersect(&t, &u),
                "{t:?} {u:?}"
            );
        }
    }
    assert_eq!(bad, 0, "{bad} wrong signs among {certain} certain ones");
    assert!(certain > 300_000, "{certain}");
}
