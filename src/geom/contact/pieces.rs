//! The penetration depth of a pair with a quad, the quad taken as what it is, the union of
//! its two triangles (planar or not; issue 28), not its hull.
//!
//! A translation `t` of polygon `a` leaves it meeting `b` iff `t` lies in the Minkowski
//! difference `B - A`: the union of the pieces `B_j - A_i`, one convex polytope per pair of
//! triangles, each the intersection of the half-spaces `u . t <= h` over the triangles'
//! separating axes (their two normals and the nine crosses of their edges, either way: a
//! superset of the piece's facets, every one a supporting plane). The depth is the distance
//! from the origin to the closure of the union's complement. Its nearest point is the foot
//! of the origin on one facet plane, on the line of two, or at the point of three, of
//! distinct pieces, lies on those pieces, and is not inside the union: some direction leaves
//! every piece holding it (for some choice of one plane through it per such piece, the
//! chosen normals' hull misses the origin, Gordan's theorem; decided by that hull's point
//! nearest the origin, whose direction is then such a direction). So the candidates are
//! tried nearest plane first, and a pair's or triple's only while its planes are nearer
//! than the best found. The constructions are `f64`; "on a plane" is within `TOL` of the
//! pair's extent. Touching (depth 0) is the origin itself passing that test, with the exact
//! decisions of which triangle pairs meet; its normal is the direction that leaves the
//! pieces by the widest margin.

use super::poly::{Poly, Tri};
use super::V;

/// Candidate planes of a piece: both ways along 11 axes.
const PLANES: usize = 22;

/// A point is on a plane within `TOL` times the pair's extent and `eps` (the plane's and
/// the point's rounding), times the candidate's condition (`1 / |u1 x u2|^2` on a line,
/// `1 / |det|` at a point): an overlap thinner than that is taken as touching.
const TOL: f64 = 16.0 * f64::EPSILON;

/// Candidates on planes nearer parallel than this (`1 / |u1 x u2|^2`, `1 / |det|`) are not
/// taken: their point is not known to within the tolerance.
const MAX_COND: f64 = 1e4;

/// The origin is outside the hull of chosen unit normals when the hull's nearest point is
/// farther from it than this.
const GORDAN: f64 = 1e-12;

/// One piece `B_j - A_i`: `u[k] . t <= h[k]`, `u[k]` unit.
struct Piece {
    u: [V; PLANES],
    h: [f64; PLANES],
    n: usize,
    /// Holds the origin (the triangles meet, exactly).
    meets: bool,
}

impl Piece {
    const EMPTY: Piece = Piece {
        u: [V::new(0.0, 0.0, 0.0); PLANES],
        h: [0.0; PLANES],
        n: 0,
        meets: false,
    };

    fn new(t: &Tri, s: &Tri, meets: bool, tol: f64) -> Piece {
        let mut p = Piece {
            u: [V::zeros(); PLANES],
            h: [0.0; PLANES],
            n: 0,
            meets,
        };
        // Axis `c`; `edges`: it crosses edge `k` of `t` and edge `l` of `s`, and is kept
        // either way only where it is a facet (or may be, within `tol`): that edge of `t`
        // at its least projection and that of `s` at its greatest (or the other way
        // round); the planes of the others only touch the piece at an edge or a vertex.
        let mut offer = |c: V, edges: Option<(usize, usize)>| {
            let len = c.norm();
            if !(len > 0.0 && len.is_finite()) {
                return;
            }
            let u = c / len;
            let (pa, pb) = (t.v.map(|v| u.dot(&v)), s.v.map(|v| u.dot(&v)));
            let (amin, amax) = (pa[0].min(pa[1]).min(pa[2]), pa[0].max(pa[1]).max(pa[2]));
            let (bmin, bmax) = (pb[0].min(pb[1]).min(pb[2]), pb[0].max(pb[1]).max(pb[2]));
            let (up, down) = match edges {
                None => (true, true),
                Some((k, l)) => {
                    // The third corners' projections against their edges'.
                    let (ta, tb) = (pa[(k + 2) % 3], pb[(l + 2) % 3]);
                    let (ea, eb) = (pa[k].max(pa[(k + 1) % 3]), pb[l].min(pb[(l + 1) % 3]));
                    let (fa, fb) = (pa[k].min(pa[(k + 1) % 3]), pb[l].max(pb[(l + 1) % 3]));
                    (
                        ta >= ea - tol && tb <= eb + tol,
                        ta <= fa + tol && tb >= fb - tol,
                    )
                }
            };
            // Moving a along +u by more than bmax - amin, or along -u by more than
            // amax - bmin, separates the two triangles.
            if up {
                p.u[p.n] = u;
                p.h[p.n] = bmax - amin;
                p.n += 1;
            }
            if down {
                p.u[p.n] = -u;
                p.h[p.n] = amax - bmin;
                p.n += 1;
            }
        };
        offer(t.n, None);
        offer(s.n, None);
        for k in 0..3 {
            let e = t.v[(k + 1) % 3] - t.v[k];
            for l in 0..3 {
                offer(e.cross(&(s.v[(l + 1) % 3] - s.v[l])), Some((k, l)));
            }
        }
        p
    }

    /// `None` when `x` is outside the piece; else its planes through `x` (none: inside).
    /// `on`: a plane `x` was built on (through it whatever the rounding), or `PLANES`.
    fn through(&self, x: &V, tol: f64, on_plane: usize) -> Option<([u8; PLANES], usize)> {
        let mut on = [0u8; PLANES];
        let mut m = 0;
        for k in 0..self.n {
            let s = if k == on_plane {
                0.0
            } else {
                self.u[k].dot(x) - self.h[k]
            };
            if s > tol {
                return None;
            }
            if s >= -tol {
                on[m] = k as u8;
                m += 1;
            }
        }
        Some((on, m))
    }
}

/// The point of the hull of `p` (one to four points) nearest the origin: the best of the
/// feet on the affine hulls of its subsets whose barycentric weights are all non-negative.
fn nearest_in_hull(p: &[V]) -> V {
    let mut best = p[0];
    for mask in 1u32..(1 << p.len()) {
        let mut s = [V::zeros(); 4];
        let mut n = 0;
        for (i, q) in p.iter().enumerate() {
            if mask & (1 << i) != 0 {
                s[n] = *q;
                n += 1;
            }
        }
        // x = s0 + sum_k w_k (s_k - s0), x . (s_k - s0) = 0 for every k.
        let d = [s[1] - s[0], s[2] - s[0], s[3] - s[0]];
        let mut w = [0.0; 3];
        match n - 1 {
            0 => {}
            1 => {
                let dd = d[0].norm_squared();
                if dd.is_nan() || dd <= 0.0 {
                    continue;
                }
                w[0] = -s[0].dot(&d[0]) / dd;
            }
            2 => {
                let (a, b, c) = (d[0].norm_squared(), d[0].dot(&d[1]), d[1].norm_squared());
                let (r0, r1) = (-s[0].dot(&d[0]), -s[0].dot(&d[1]));
                let det = a * c - b * b;
                if det.is_nan() || det <= 0.0 {
                    continue;
                }
                w[0] = (r0 * c - r1 * b) / det;
                w[1] = (a * r1 - b * r0) / det;
            }
            _ => {
                // The origin in the tetrahedron's frame: s0 + m w = 0.
                let m = nalgebra::Matrix3::from_columns(&d);
                let Some(inv) = m.try_inverse() else { continue };
                let x = inv * (-s[0]);
                w = [x[0], x[1], x[2]];
            }
        }
        if w.iter().any(|&x| x < 0.0) || w.iter().sum::<f64>() > 1.0 {
            continue;
        }
        let x = s[0] + d[0] * w[0] + d[1] * w[1] + d[2] * w[2];
        if x.norm_squared() < best.norm_squared() {
            best = x;
        }
    }
    best
}

/// A direction that leaves every piece holding `x` (within `tol`), if there is one: for
/// some choice of one plane through `x` per such piece, the hull of the chosen normals
/// misses the origin, and its nearest point's direction leaves them all. `widest`: the
/// choice whose direction leaves by the widest margin (else the first found).
fn leaving(
    pieces: &[Piece],
    x: &V,
    tol: f64,
    built_on: &[(usize, usize)],
    origin: bool,
    widest: bool,
) -> Option<V> {
    let mut through = [([0u8; PLANES], 0usize); 4];
    let mut holding = [0usize; 4];
    let mut nh = 0;
    for (k, p) in pieces.iter().enumerate() {
        // At the origin, the exact decision says which pieces hold it.
        if origin && !p.meets {
            continue;
        }
        let on = built_on
            .iter()
            .find(|&&(l, _)| l == k)
            .map_or(PLANES, |&(_, i)| i);
        match p.through(x, tol, on) {
            None => {}
            Some((_, 0)) => return None, // inside
            Some(t) => {
                through[nh] = t;
                holding[nh] = k;
                nh += 1;
            }
        }
    }
    if nh == 0 {
        return Some(V::z()); // on no piece (touching only through flat ones): any way
    }
    let mut best: Option<V> = None;
    let mut choice = [0usize; 4];
    loop {
        let mut u = [V::zeros(); 4];
        for i in 0..nh {
            u[i] = pieces[holding[i]].u[through[i].0[choice[i]] as usize];
        }
        let p = nearest_in_hull(&u[..nh]);
        let m = p.norm();
        if m > GORDAN && best.is_none_or(|b| m > b.norm()) {
            best = Some(p);
            if !widest {
                break;
            }
        }
        // The next choice.
        let mut i = 0;
        while i < nh {
            choice[i] += 1;
            if choice[i] < through[i].1 {
                break;
            }
            choice[i] = 0;
            i += 1;
        }
        if i == nh {
            break;
        }
    }
    best.map(|p| p / p.norm())
}

/// The parameters `[lo, hi]` of the points `x0 + t m` of a line in both pieces `p` and
/// `q` (within `tol`; the planes `i` of `p` and `j` of `q` hold the line), if any.
fn clip(p: &Piece, i: usize, q: &Piece, j: usize, x0: &V, m: &V, tol: f64) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
    for (piece, own) in [(p, i), (q, j)] {
        for k in 0..piece.n {
            if k == own {
                continue;
            }
            // u . (x0 + t m) <= h + tol.
            let (s, c) = (piece.u[k].dot(m), piece.h[k] + tol - piece.u[k].dot(x0));
            if s > 0.0 {
                hi = hi.min(c / s);
            } else if s < 0.0 {
                lo = lo.max(c / s);
            } else if c < 0.0 {
                return None;
            }
            if lo > hi {
                return None;
            }
        }
    }
    Some((lo, hi))
}

/// The smallest translation of `a` that separates the two polygons as unions of their
/// triangles, as (unit normal, depth >= 0); `hit[i][j]`: triangle `i` of `a` meets triangle
/// `j` of `b` (exact). `None` if no candidate passed (a numerical failure: the caller then
/// takes the hulls' depth, an upper bound).
pub(super) fn union_depth<T>(pa: &Poly, pb: &Poly, hit: &[[Option<T>; 2]; 2]) -> Option<(V, f64)> {
    let extent = pa
        .verts()
        .iter()
        .chain(pb.verts())
        .fold(0.0f64, |m, v| m.max(v.amax()));
    let tol = TOL * extent;
    let mut all = [Piece::EMPTY, Piece::EMPTY, Piece::EMPTY, Piece::EMPTY];
    let mut np = 0;
    for (i, t) in pa.tris().iter().enumerate() {
        for (j, s) in pb.tris().iter().enumerate() {
            all[np] = Piece::new(t, s, hit[i][j].is_some(), tol);
            np += 1;
        }
    }
    let pieces = &all[..np];
    // Touching: the origin is on the boundary.
    if let Some(n) = leaving(pieces, &V::zeros(), tol, &[], true, true) {
        return Some((n, 0.0));
    }
    // Every plane (its distance from the origin, piece, index).
    let mut every = [(0.0, 0, 0); 4 * PLANES];
    let mut ne = 0;
    for (k, p) in pieces.iter().enumerate() {
        for i in 0..p.n {
            every[ne] = (p.h[i].abs(), k, i);
            ne += 1;
        }
    }
    let every = &mut every[..ne];
    // No candidate nearer than the depth of a piece holding the origin (the ball of that
    // radius lies inside it) is on the boundary.
    let floor = pieces
        .iter()
        .filter(|p| p.meets)
        .map(|p| p.h[..p.n].iter().fold(f64::INFINITY, |m, &h| m.min(h)))
        .fold(0.0f64, f64::max)
        - tol;
    // A candidate built on planes `on` with condition `cond`: on its pieces, and some
    // direction leaves every piece holding it.
    let accept = |x: &V, on: &[(usize, usize)], cond: f64| {
        if cond.is_nan() || cond > MAX_COND {
            return false;
        }
        let tol = tol * (1.0 + cond);
        on.iter()
            .all(|&(k, i)| pieces[k].through(x, tol, i).is_some())
            && leaving(pieces, x, tol, on, false, false).is_some()
    };
    let mut best: Option<(V, f64)> = None;
    let bound = |best: &Option<(V, f64)>| best.map_or(f64::INFINITY, |b| b.1);
    // One plane: its foot, nearest first (by selection: the first or second usually
    // passes). The planes taken move to the front.
    for f in 0..every.len() {
        let m = (f..every.len())
            .min_by(|&x, &y| every[x].0.total_cmp(&every[y].0))
            .unwrap_or(f);
        every.swap(f, m);
        let (d, k, i) = every[f];
        if d < floor {
            continue;
        }
        let x = pieces[k].u[i] * pieces[k].h[i];
        if accept(&x, &[(k, i)], 0.0) {
            best = Some((x, d));
            break;
        }
    }
    // The planes nearer than that (the only ones a nearer candidate can be on), nearest
    // first.
    let mut near_planes = [(0.0, 0, 0); 4 * PLANES];
    let mut nn = 0;
    for &p in every.iter() {
        if p.0 < bound(&best) {
            near_planes[nn] = p;
            nn += 1;
        }
    }
    let planes = &mut near_planes[..nn];
    planes.sort_unstable_by(|x, y| x.0.total_cmp(&y.0));
    // Two planes of distinct pieces: the foot of the origin on their line; and with a quad
    // against a quad, the points where a third piece's planes cross that line within both
    // pieces (the line clipped to them: its points that can be candidates).
    for a in 0..planes.len() {
        let (da, k, i) = planes[a];
        if da.is_nan() || da >= bound(&best) {
            break;
        }
        let (u1, h1) = (pieces[k].u[i], pieces[k].h[i]);
        for b in a + 1..planes.len() {
            let (db, l, j) = planes[b];
            if db.is_nan() || db >= bound(&best) {
                break;
            }
            if l == k {
                continue;
            }
            let (u2, h2) = (pieces[l].u[j], pieces[l].h[j]);
            // The line x0 + t m, x0 the foot (perpendicular to m).
            let m = u1.cross(&u2);
            let mm = m.norm_squared();
            if mm.is_nan() || mm * MAX_COND < 1.0 {
                continue;
            }
            let x0 = (u2.cross(&m) * h1 + m.cross(&u1) * h2) / mm;
            let d0 = x0.norm_squared();
            if d0.is_nan() || d0 >= bound(&best).powi(2) {
                continue;
            }
            if d0.sqrt() >= floor && accept(&x0, &[(k, i), (l, j)], 1.0 / mm) {
                best = Some((x0, d0.sqrt()));
            }
            if pieces.len() < 4 {
                continue;
            }
            let ltol = tol * (1.0 + 1.0 / mm);
            let Some((lo, hi)) = clip(&pieces[k], i, &pieces[l], j, &x0, &m, ltol) else {
                continue;
            };
            for &(dc, q, r) in &planes[b + 1..] {
                if dc.is_nan() || dc >= bound(&best) {
                    break;
                }
                if q == k || q == l {
                    continue;
                }
                let (u3, h3) = (pieces[q].u[r], pieces[q].h[r]);
                let det = u3.dot(&m);
                if det.is_nan() || det.abs() * MAX_COND < 1.0 {
                    continue;
                }
                let t = (h3 - u3.dot(&x0)) / det;
                let d2 = d0 + t * t * mm;
                if t < lo || t > hi || d2.is_nan() || d2 >= bound(&best).powi(2) {
                    continue;
                }
                let x = x0 + m * t;
                let d = d2.sqrt();
                if d >= floor && accept(&x, &[(k, i), (l, j), (q, r)], 1.0 / det.abs()) {
                    best = Some((x, d));
                }
            }
        }
    }
    best.map(|(x, d)| (x / d, d))
}
