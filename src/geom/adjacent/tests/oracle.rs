//! The tests' independent oracle, [`meets`].
//!
//! Exact construction of the meeting set, in integers.
//!
//! All coordinates of a case are scaled by one power of two into integers (exact:
//! every `f64` is an integer times a power of two, and a common scale changes nothing
//! about incidence or order). Constructed points are rational, kept as `P / w` with an
//! integer vector `P` and an integer `w > 0`, so every test is an exact integer sign.
//!
//! For closed convex polytopes `t` and `u`, every vertex `v` of `C = t ∩ u` lies in the
//! relative interiors of one face `F` of `t` and one `G` of `u`, and near `v` the set
//! `C` is `aff F ∩ aff G`; `v` being extreme, `aff F ∩ aff G = {v}`. The faces of a
//! triangle given by three points are among: the points, the segments between two of
//! them, the triangle itself (when proper). Pairs whose hulls meet in exactly one point
//! are a point and anything, two coplanar non-parallel lines, or a line and a plane it
//! crosses. So `C` is the convex hull of those candidate points that lie in both closed
//! triangles (all of them are in `C`, and every vertex of `C` is one). Two shortcuts,
//! both exact: a line/plane candidate is needed only when the edge's ends are strictly
//! on either side of the plane (`v` is inside `F`; an end on the plane is a point
//! candidate), and line/line candidates only when a triangle is degenerate or both are
//! in one plane (for proper triangles in different planes, `F` or `G` is not in the
//! other's plane, else both lie on the planes' common line and are parallel, and then
//! `v` is also that edge's line/plane candidate).
//!
//! `C` is then a point, a segment (the extreme candidates along its direction) or has
//! area. It is inside the joint `S` iff: a point lying in `S`; a segment covered by the
//! shared edges collinear with it (an interval sweep of their parameters; the other
//! pieces of `S` meet its line in finitely many points, which cannot fill a gap); never
//! when it has area.
//!
//! Computed in `i128` when no operation overflows there (every one is checked), else
//! in `BigInt`.

use crate::geom::P3;

/// Integer arithmetic for the oracle: `BigInt`, or `i128` that flags an overflow.
pub trait Int: Sized {
    fn one() -> Self;
    fn is_zero(&self) -> bool;
    fn is_neg(&self) -> bool;
    fn is_pos(&self) -> bool;
    /// `±m * 2^shift`.
    fn from_parts(m: u64, shift: u32, neg: bool) -> Self;
}

impl Int for num_bigint::BigInt {
    fn one() -> Self {
        num_traits::One::one()
    }
    fn is_zero(&self) -> bool {
        num_traits::Zero::is_zero(self)
    }
    fn is_neg(&self) -> bool {
        num_traits::Signed::is_negative(self)
    }
    fn is_pos(&self) -> bool {
        num_traits::Signed::is_positive(self)
    }
    fn from_parts(m: u64, shift: u32, neg: bool) -> Self {
        let z = num_bigint::BigInt::from(m) << shift as usize;
        if neg {
            -z
        } else {
            z
        }
    }
}

thread_local! {
    /// Set when a [`Small`] operation overflowed: its results are then meaningless.
    static OVERFLOW: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// An `i128` whose overflowing operations set [`OVERFLOW`] (and yield 0).
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Small(i128);

fn checked(r: Option<i128>) -> Small {
    Small(r.unwrap_or_else(|| {
        OVERFLOW.with(|o| o.set(true));
        0
    }))
}

macro_rules! small_op {
    ($tr:ident, $f:ident, $checked:ident) => {
        impl std::ops::$tr<&Small> for &Small {
            type Output = Small;
            fn $f(self, o: &Small) -> Small {
                checked(self.0.$checked(o.0))
            }
        }
        impl std::ops::$tr<Small> for Small {
            type Output = Small;
            fn $f(self, o: Small) -> Small {
                checked(self.0.$checked(o.0))
            }
        }
    };
}
small_op!(Add, add, checked_add);
small_op!(Sub, sub, checked_sub);
small_op!(Mul, mul, checked_mul);

impl std::ops::Neg for Small {
    type Output = Small;
    fn neg(self) -> Small {
        checked(self.0.checked_neg())
    }
}

impl Int for Small {
    fn one() -> Self {
        Small(1)
    }
    fn is_zero(&self) -> bool {
        self.0 == 0
    }
    fn is_neg(&self) -> bool {
        self.0 < 0
    }
    fn is_pos(&self) -> bool {
        self.0 > 0
    }
    fn from_parts(m: u64, shift: u32, neg: bool) -> Self {
        let z = if shift < 64 {
            checked(i128::from(m).checked_mul(1i128 << shift))
        } else {
            checked(None)
        };
        if neg {
            -z
        } else {
            z
        }
    }
}

macro_rules! exact_oracle {
    ($m:ident, $Z:ty) => {
        mod $m {

            use crate::geom::adjacent::tests::oracle::Int;
            use crate::geom::P3;
            use std::cmp::Ordering;

            type Z = $Z;
            type V = [Z; 3];

            fn sub(a: &V, b: &V) -> V {
                [&a[0] - &b[0], &a[1] - &b[1], &a[2] - &b[2]]
            }
            fn add(a: &V, b: &V) -> V {
                [&a[0] + &b[0], &a[1] + &b[1], &a[2] + &b[2]]
            }
            fn scale(a: &V, s: &Z) -> V {
                [&a[0] * s, &a[1] * s, &a[2] * s]
            }
            fn dot(a: &V, b: &V) -> Z {
                &a[0] * &b[0] + &a[1] * &b[1] + &a[2] * &b[2]
            }
            fn cross(a: &V, b: &V) -> V {
                [
                    &a[1] * &b[2] - &a[2] * &b[1],
                    &a[2] * &b[0] - &a[0] * &b[2],
                    &a[0] * &b[1] - &a[1] * &b[0],
                ]
            }
            fn zero(a: &V) -> bool {
                a.iter().all(Int::is_zero)
            }

            /// The rational point `p / w`, `w > 0`.
            #[derive(Clone, Debug)]
            struct Pt {
                p: V,
                w: Z,
            }

            impl Pt {
                fn int(p: &V) -> Pt {
                    Pt {
                        p: p.clone(),
                        w: <Z as Int>::one(),
                    }
                }
                /// `p / w` with `w != 0`, made positive.
                fn new(p: V, w: Z) -> Pt {
                    if w.is_neg() {
                        Pt {
                            p: p.map(|x| -x),
                            w: -w,
                        }
                    } else {
                        Pt { p, w }
                    }
                }
                fn same(&self, o: &Pt) -> bool {
                    (0..3).all(|k| &self.p[k] * &o.w == &o.p[k] * &self.w)
                }
                /// `w * (self - a)` for an integer point `a`.
                fn from(&self, a: &V) -> V {
                    sub(&self.p, &scale(a, &self.w))
                }
            }

            /// A fraction `n / d`, `d > 0`, ordered by value.
            #[derive(Clone, Debug)]
            struct Frac(Z, Z);

            impl Frac {
                fn cmp(&self, o: &Frac) -> Ordering {
                    (&self.0 * &o.1).cmp(&(&o.0 * &self.1))
                }
            }

            /// Closed segment `a`-`b` (maybe a point) contains `x`.
            fn on_segment(x: &Pt, a: &V, b: &V) -> bool {
                let d = sub(b, a);
                let w = x.from(a);
                if zero(&d) {
                    return zero(&w);
                }
                let s = dot(&w, &d);
                zero(&cross(&w, &d)) && !s.is_neg() && s <= &x.w * &dot(&d, &d)
            }

            /// A closed triangle with what its tests need.
            struct Tri {
                v: [V; 3],
                e1: V,
                e2: V,
                /// Normal `e1 x e2`; zero when degenerate.
                n: V,
                nn: Z,
                /// The farthest two vertices (the segment, when degenerate).
                far: (usize, usize),
            }

            impl Tri {
                fn new(v: [V; 3]) -> Tri {
                    let e1 = sub(&v[1], &v[0]);
                    let e2 = sub(&v[2], &v[0]);
                    let n = cross(&e1, &e2);
                    let nn = dot(&n, &n);
                    let far = [(0, 1), (0, 2), (1, 2)]
                        .into_iter()
                        .max_by_key(|&(i, j)| {
                            let d = sub(&v[j], &v[i]);
                            dot(&d, &d)
                        })
                        .expect("three pairs");
                    Tri {
                        v,
                        e1,
                        e2,
                        n,
                        nn,
                        far,
                    }
                }
                fn proper(&self) -> bool {
                    !self.nn.is_zero()
                }
                fn contains(&self, x: &Pt) -> bool {
                    if !self.proper() {
                        return on_segment(x, &self.v[self.far.0], &self.v[self.far.1]);
                    }
                    // w (x - v0) = b e1 + g e2 with b n = (W x e2), g n = (e1 x W), scaled by w.
                    let w = x.from(&self.v[0]);
                    if !dot(&w, &self.n).is_zero() {
                        return false;
                    }
                    let b = dot(&cross(&w, &self.e2), &self.n);
                    let g = dot(&cross(&self.e1, &w), &self.n);
                    !b.is_neg() && !g.is_neg() && b + g <= &x.w * &self.nn
                }
                /// Signed distances (scaled) of points to the plane, when proper.
                fn sides(&self, p: &[V; 3]) -> Option<[Z; 3]> {
                    self.proper()
                        .then(|| [0, 1, 2].map(|k| dot(&sub(&p[k], &self.v[0]), &self.n)))
                }
            }

            /// The point where the lines `p`-`p2` and `r`-`r2` cross, if exactly one.
            fn line_line(p: &V, p2: &V, r: &V, r2: &V) -> Option<Pt> {
                let d = sub(p2, p);
                let e = sub(r2, r);
                let n = cross(&d, &e);
                if zero(&n) {
                    return None;
                }
                let w = sub(r, p);
                if !dot(&w, &n).is_zero() {
                    return None;
                }
                // p + s d = r + s' e; (w x e) = s (d x e).
                let den = dot(&n, &n);
                let num = dot(&cross(&w, &e), &n);
                Some(Pt::new(add(&scale(p, &den), &scale(&d, &num)), den))
            }

            fn strictly_one_side(d: &Option<[Z; 3]>) -> bool {
                d.as_ref()
                    .is_some_and(|d| d.iter().all(Int::is_pos) || d.iter().all(Int::is_neg))
            }

            /// Candidate points of `t ∩ u` that lie in it (see the module doc).
            fn meeting_points(t: &Tri, u: &Tri) -> Vec<Pt> {
                let du = t.sides(&u.v);
                let dt = u.sides(&t.v);
                if strictly_one_side(&du) || strictly_one_side(&dt) {
                    return Vec::new();
                }
                let mut out: Vec<Pt> = Vec::new();
                let push = |x: Pt, out: &mut Vec<Pt>| {
                    if t.contains(&x) && u.contains(&x) && !out.iter().any(|y| y.same(&x)) {
                        out.push(x);
                    }
                };
                for x in t.v.iter().chain(&u.v) {
                    push(Pt::int(x), &mut out);
                }
                let pairs = [(0, 1), (0, 2), (1, 2)];
                // An edge of `x` crossing the plane of `y` (`d`: sides of `x` against it).
                let crossings = |x: &Tri, d: &Option<[Z; 3]>, out: &mut Vec<Pt>| {
                    if let Some(d) = d {
                        for &(i, j) in &pairs {
                            let (a, b) = (&d[i], &d[j]);
                            if (a.is_pos() && b.is_neg()) || (a.is_neg() && b.is_pos()) {
                                // v_i + a / (a - b) (v_j - v_i) = (a v_j - b v_i) / (a - b).
                                let p = sub(&scale(&x.v[j], a), &scale(&x.v[i], b));
                                push(Pt::new(p, a - b), out);
                            }
                        }
                    }
                };
                crossings(t, &dt, &mut out);
                crossings(u, &du, &mut out);
                let coplanar = du.as_ref().is_some_and(|d| d.iter().all(Int::is_zero));
                if !t.proper() || !u.proper() || coplanar {
                    for &(i, j) in &pairs {
                        for &(k, l) in &pairs {
                            if t.v[i] != t.v[j] && u.v[k] != u.v[l] {
                                if let Some(x) = line_line(&t.v[i], &t.v[j], &u.v[k], &u.v[l]) {
                                    push(x, &mut out);
                                }
                            }
                        }
                    }
                }
                out
            }

            /// Is the convex hull of the points `c` (not empty) inside the joint?
            fn covered(c: &[Pt], pts: &[V], segs: &[[V; 2]]) -> bool {
                let p0 = &c[0];
                let Some(p1) = c.iter().find(|x| !x.same(p0)) else {
                    return pts.iter().any(|s| p0.same(&Pt::int(s)))
                        || segs.iter().any(|[a, b]| on_segment(p0, a, b));
                };
                // rel(x) = w0 wx (x - p0); d ~ p1 - p0.
                let rel = |x: &Pt| sub(&scale(&x.p, &p0.w), &scale(&p0.p, &x.w));
                let d = rel(p1);
                if c.iter().any(|x| !zero(&cross(&rel(x), &d))) {
                    return false; // area
                }
                // (x - p0) . d up to the common factor w0 > 0.
                let param = |x: &Pt| Frac(dot(&rel(x), &d), x.w.clone());
                let mut ps: Vec<Frac> = c.iter().map(param).collect();
                ps.sort_by(Frac::cmp);
                let (lo, hi) = (ps[0].clone(), ps[ps.len() - 1].clone());
                let mut iv: Vec<(Frac, Frac)> = segs
                    .iter()
                    .filter(|[a, b]| {
                        zero(&cross(&rel(&Pt::int(a)), &d)) && zero(&cross(&rel(&Pt::int(b)), &d))
                    })
                    .map(|[a, b]| {
                        let (x, y) = (param(&Pt::int(a)), param(&Pt::int(b)));
                        if x.cmp(&y).is_le() {
                            (x, y)
                        } else {
                            (y, x)
                        }
                    })
                    .collect();
                iv.sort_by(|x, y| x.0.cmp(&y.0));
                let mut reach = lo;
                for (s, e) in iv {
                    if reach.cmp(&hi).is_ge() {
                        break;
                    }
                    if s.cmp(&reach).is_gt() {
                        return false;
                    }
                    if e.cmp(&reach).is_gt() {
                        reach = e;
                    }
                }
                reach.cmp(&hi).is_ge()
            }

            /// All coordinates as integers, scaled by one power of two.
            fn integers(coords: &[f64]) -> Vec<Z> {
                let parts: Vec<(u64, i16, i8)> = coords
                    .iter()
                    .map(|&x| {
                        // Odd mantissas: the smallest integers.
                        let (m, e, s) = num_traits::Float::integer_decode(x);
                        let z = if m == 0 { 0 } else { m.trailing_zeros() };
                        (m >> z, e + z as i16, s)
                    })
                    .collect();
                let e0 = parts
                    .iter()
                    .filter(|p| p.0 != 0)
                    .map(|p| p.1)
                    .min()
                    .unwrap_or(0);
                parts
                    .iter()
                    .map(|&(m, e, s)| {
                        if m == 0 {
                            Z::from_parts(0, 0, false)
                        } else {
                            Z::from_parts(m, (e - e0) as u32, s < 0)
                        }
                    })
                    .collect()
            }

            /// The definition, decided by construction: do the closed polygons meet outside
            /// their shared vertices and shared edges? `a_pos[k]` is the position of vertex
            /// `a_idx[k]`; quads split as `(v0, v1, v2)`, `(v0, v2, v3)`.
            pub fn meets(a_idx: &[u32], a_pos: &[P3], b_idx: &[u32], b_pos: &[P3]) -> bool {
                let flat: Vec<f64> = a_pos.iter().chain(b_pos).flatten().copied().collect();
                let z = integers(&flat);
                let pt = |k: usize| [z[3 * k].clone(), z[3 * k + 1].clone(), z[3 * k + 2].clone()];
                let av: Vec<V> = (0..a_pos.len()).map(pt).collect();
                let bv: Vec<V> = (a_pos.len()..a_pos.len() + b_pos.len()).map(pt).collect();
                let edges = |idx: &[u32]| -> Vec<(u32, u32)> {
                    (0..idx.len())
                        .map(|k| (idx[k], idx[(k + 1) % idx.len()]))
                        .filter(|(i, j)| i != j)
                        .collect()
                };
                let (ea, eb) = (edges(a_idx), edges(b_idx));
                let at =
                    |i: u32| av[a_idx.iter().position(|&x| x == i).expect("a's index")].clone();
                let pts: Vec<V> = a_idx
                    .iter()
                    .filter(|i| b_idx.contains(i))
                    .map(|&i| at(i))
                    .collect();
                let segs: Vec<[V; 2]> = ea
                    .iter()
                    .filter(|&&(i, j)| eb.contains(&(i, j)) || eb.contains(&(j, i)))
                    .map(|&(i, j)| [at(i), at(j)])
                    .collect();
                let tris = |p: &[V]| -> Vec<Tri> {
                    let mut t = vec![Tri::new([p[0].clone(), p[1].clone(), p[2].clone()])];
                    if p.len() == 4 {
                        t.push(Tri::new([p[0].clone(), p[2].clone(), p[3].clone()]));
                    }
                    t
                };
                let (ta, tb) = (tris(&av), tris(&bv));
                for t in &ta {
                    for u in &tb {
                        let c = meeting_points(t, u);
                        if !c.is_empty() && !covered(&c, &pts, &segs) {
                            return true;
                        }
                    }
                }
                false
            }
        }
    };
}

exact_oracle!(big, num_bigint::BigInt);
exact_oracle!(small, crate::geom::adjacent::tests::oracle::Small);

pub fn meets(a_idx: &[u32], a_pos: &[P3], b_idx: &[u32], b_pos: &[P3]) -> bool {
    OVERFLOW.with(|o| o.set(false));
    let r = small::meets(a_idx, a_pos, b_idx, b_pos);
    if !OVERFLOW.with(|o| o.get()) {
        return r;
    }
    big::meets(a_idx, a_pos, b_idx, b_pos)
}
