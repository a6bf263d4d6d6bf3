//! The fast path of two triangles: crossing transversally (the common case) or apart,
//! without the general path's structures (its separating-axis search over the facets of
//! their Minkowski difference with no data-dependent branches); and a segment (a triangle
//! with two equal corners) crossing a triangle's interior.

use super::cut::{lerp_from_nearer, signed_like, transverse, Cutting, Face};
use super::depth::Axis;
use super::general::exact_sides;
use super::{max, min, pattern, Local, LONELY, NEXT, PREV, V};
use crate::geom::predicates::{orient3d, orient3d_filtered, P3};
use crate::geom::tritri::{separated, triangles_intersect_with};

/// What the triangle-pair fast path found.
pub(super) enum Fast {
    /// Crossing transversally (both non-flat, not coplanar): the geometry.
    Done(Local),
    /// Not intersecting.
    Apart,
    /// Intersecting, coplanar or with a flat triangle: the general path.
    Other,
}

/// Two triangles: the common case (crossing transversally) without the general path's
/// structures, in world coordinates: every quantity is built from differences of the
/// pair's own vertices (exact for `f32` input), so the only rounding at the world's
/// magnitude is the final one of the points. The decision is the same as `meets`
/// (`general.rs`).
#[inline(always)]
pub(super) fn triangles(a: &[P3; 3], b: &[P3; 3]) -> Fast {
    let v = |p: &P3| V::new(p[0], p[1], p[2]);
    let ta = [v(&a[0]), v(&a[1]), v(&a[2])];
    let tb = [v(&b[0]), v(&b[1]), v(&b[2])];
    let fa = Face::of(&ta, a);
    let (db, hb, scale_b) = fa.sides(&tb);
    if separated(hb) {
        return Fast::Apart;
    }
    let fb = Face::of(&tb, b);
    let (da, ha, scale_a) = fb.sides(&ta);
    if separated(ha) {
        return Fast::Apart;
    }
    let su = exact_sides(hb, a, b);
    let st = exact_sides(ha, b, a);
    if separated(su) || separated(st) {
        return Fast::Apart;
    }
    if su.contains(&0) || st.contains(&0) {
        if !triangles_intersect_with(a, b, su, st) {
            return Fast::Apart;
        }
        if su == [0; 3] || st == [0; 3] {
            // Coplanar, or a flat triangle (a non-flat one has a vertex of the other off
            // it).
            return Fast::Other;
        }
    } else if !general_position(a, b, su, st) {
        return Fast::Apart;
    }
    let (da, db) = (signed_like(da, st), signed_like(db, su));
    // The pair's magnitude, to within its extent (enough for the refinement's test).
    let mag = max(ta[0].amax(), tb[0].amax());
    let (cut_a, cut_b) = (
        Cutting::new(&ta, a, &da, &scale_a, &fb, mag),
        Cutting::new(&tb, b, &db, &scale_b, &fa, mag),
    );
    let Some((p, q)) = transverse(&cut_a, &cut_b) else {
        return Fast::Other;
    };
    let Some((normal, depth)) = triangles_sat(&ta, &tb, &fa.n, &fb.n, &da, &db).result() else {
        return Fast::Other;
    };
    Fast::Done(Local {
        p,
        q,
        normal,
        depth,
        intersecting: true,
        coplanar: false,
    })
}

/// Two of the triangle's corners are the same point.
#[inline(always)]
pub(super) fn twin(t: &[P3; 3]) -> bool {
    t[0] == t[1] || t[1] == t[2] || t[2] == t[0]
}

/// A triangle with two equal corners (a segment, as meshes moved in `f32` make of
/// slivers) crossing the other triangle's interior transversally: the common case of a
/// degenerate pair, answered without the general path's structures (which took about
/// 600 ns a pair). `None` for anything else (the general path decides). Exact decision:
/// the segment's ends strictly on opposite sides of the triangle's plane and its line
/// strictly inside the triangle's three edges (`orient3d`). Its intersection is one point,
/// built from the end nearer the plane with the distances evaluated accurately (as a cut
/// is). The depth is the separating-axis minimum over what the Minkowski difference of a
/// segment and a triangle has as facets: the triangle's normal and the segment crossed
/// with each of its edges (the segment's own normal and its other edges are zero), in a
/// frame at the segment's first end. `seg` has two equal corners, `tri` none; `flip` (+-1)
/// turns a translation of `seg` into one of polygon `a` (-1 when `seg` is `b`).
pub(super) fn segment_crossing(seg: &[P3; 3], tri: &[P3; 3], flip: f64) -> Option<Local> {
    let (p, q) = if seg[0] == seg[1] {
        (seg[0], seg[2])
    } else {
        (seg[0], seg[1])
    };
    if p == q {
        return None;
    }
    let (sp, sq) = (
        orient3d(&tri[0], &tri[1], &tri[2], &p),
        orient3d(&tri[0], &tri[1], &tri[2], &q),
    );
    if !((sp > 0.0 && sq < 0.0) || (sp < 0.0 && sq > 0.0)) {
        return None;
    }
    let e = [
        orient3d(&p, &q, &tri[0], &tri[1]),
        orient3d(&p, &q, &tri[1], &tri[2]),
        orient3d(&p, &q, &tri[2], &tri[0]),
    ];
    if !(e.iter().all(|&x| x > 0.0) || e.iter().all(|&x| x < 0.0)) {
        return None;
    }
    let v = |x: &P3| V::new(x[0], x[1], x[2]);
    let (vp, vq, t) = (v(&p), v(&q), [v(&tri[0]), v(&tri[1]), v(&tri[2])]);
    let face = Face::of(&t, tri);
    let (dp, dq) = (face.distance_accurately(&p), face.distance_accurately(&q));
    let x = lerp_from_nearer(&vp, &vq, dp, dq);
    // The separating axes, in a frame at `p` (differences of the input: exact for `f32`).
    let s = vq - vp;
    let w = [t[0] - vp, t[1] - vp, t[2] - vp];
    let mut best = Axis::default();
    // On the triangle's normal: the triangle at 0, the segment's ends at their distances.
    best.offer_intervals(&face.n, min_max2(dp, dq), (0.0, 0.0));
    for j in 0..3 {
        // `c = s x e_j` is normal to the segment (which projects to 0) and to edge j
        // (whose ends project alike): the triangle spans edge j's and the third corner's.
        let c = s.cross(&(w[NEXT[j]] - w[j]));
        best.offer_intervals(&c, (0.0, 0.0), min_max2(c.dot(&w[j]), c.dot(&w[PREV[j]])));
    }
    let (normal, depth) = best.result()?;
    Some(Local {
        p: x,
        q: x,
        normal: normal * flip,
        depth,
        intersecting: true,
        coplanar: false,
    })
}

/// The query's exact test ([`triangles_intersect_with`]) for a pair in general position
/// (no vertex on the other's plane, neither triangle on one side of it): Guigue and
/// Devillers' two orientations, after the same permutation of the vertices as
/// `tritri::general_position`, found here by table from the sign patterns rather than by
/// branches (the patterns are random: branches on them mispredict). `su`, `st`: the signs
/// of `orient3d` of `b`'s vertices against `a`'s plane and of `a`'s against `b`'s.
#[inline(always)]
fn general_position(a: &[P3; 3], b: &[P3; 3], su: [i8; 3], st: [i8; 3]) -> bool {
    // The paper's signs are minus orient3d's: bit k of the pattern is "vertex k positive".
    let neg = |s: &[i8; 3]| {
        usize::from(s[0] < 0) | usize::from(s[1] < 0) << 1 | usize::from(s[2] < 0) << 2
    };
    // a's lone vertex first (p1, q1, r1); when it is negative, b's q and r swap.
    let k1 = LONELY[neg(&st)];
    let (p1, q1, r1) = (&a[k1 % 3], &a[NEXT[k1]], &a[PREV[k1]]);
    let swap_b = st[k1 % 3] > 0;
    let order = if swap_b { [0, 2, 1] } else { [0, 1, 2] };
    let lb = [b[order[0]], b[order[1]], b[order[2]]];
    let sb = [su[order[0]], su[order[1]], su[order[2]]];
    // Then b's lone vertex first (p2, q2, r2); when it is negative, q1 and r1 swap.
    let k2 = LONELY[neg(&sb)];
    if k1 == 3 || k2 == 3 {
        // Not in general position after all (cannot happen: no sign is zero and neither
        // triangle is on one side); the query's test decides.
        return triangles_intersect_with(a, b, su, st);
    }
    let (p2, q2, r2) = (&lb[k2], &lb[NEXT[k2]], &lb[PREV[k2]]);
    let (q1, r1) = if sb[k2] > 0 { (r1, q1) } else { (q1, r1) };
    // The paper's CHECK_MIN_MAX, as tritri::gd_check.
    orient3d_filtered(p2, p1, q2, q1) <= 0.0 && orient3d_filtered(p2, r1, r2, p1) <= 0.0
}

/// [`sat`](super::depth::sat) for two triangles. On a face normal, the face's own vertices project to one
/// value and the other's are the signed distances already computed (`da`: `a`'s vertices
/// against `b`'s plane, `db`: `b`'s against `a`'s). With edges `e_k = v_{k+1} - v_k` (so
/// `e_{k+2} x e_k = n`), `c = ea_i x eb_j` is a facet normal of the Minkowski difference
/// `B - A` only when `a`'s third vertex lies ahead of its edge along `c` and `b`'s behind,
/// or the reverse: `c . (va_{i+2} - va_i) = -eb_j . na` and `c . (vb_{j+2} - vb_j) =
/// ea_i . nb` of opposite signs. Other edge pairs are not facets, and the minimum over the
/// facets is the penetration depth, so they are skipped; on a facet, the translation is
/// the edges' offset `c . (vb_j - va_i)`, signed towards the facet's side. (When a sign is
/// zero, an edge parallel to the other's plane, [`triangles_sat_all`] tries every axis.)
#[inline(always)]
fn triangles_sat(va: &[V; 3], vb: &[V; 3], na: &V, nb: &V, da: &[f64; 3], db: &[f64; 3]) -> Axis {
    let ea = [va[1] - va[0], va[2] - va[1], va[0] - va[2]];
    let eb = [vb[1] - vb[0], vb[2] - vb[1], vb[0] - vb[2]];
    let a3 = [-eb[0].dot(na), -eb[1].dot(na), -eb[2].dot(na)];
    let b3 = [ea[0].dot(nb), ea[1].dot(nb), ea[2].dot(nb)];
    // Which pairs are facets follows the triangles' random orientation: a branch on it
    // would mispredict half the time, so they are listed from the sign patterns instead.
    // The three a3 sum to 0 (the edges of b close), so one has the minority sign, at `ja`
    // (likewise `ib` for b3); a pair (i, j) is a facet when the signs of b3_i and a3_j
    // differ, and a moves along +c when a3_j > 0 (a ahead, b behind).
    let (ja, ib) = (LONELY[pattern(&a3)], LONELY[pattern(&b3)]);
    if ja == 3 || ib == 3 || a3.contains(&0.0) || b3.contains(&0.0) {
        // A zero or rounding-level sign (an edge along the other's plane): every axis,
        // with both projections in full.
        return triangles_sat_all(va, vb, na, nb, da, db, &ea, &eb, &a3, &b3);
    }
    let (j1, j2, i1, i2) = (NEXT[ja], PREV[ja], NEXT[ib], PREV[ib]);
    let five = usize::from((a3[ja] > 0.0) != (b3[ib] > 0.0));
    let pairs = [
        // Four facets (the first one repeated).
        [(ib, j1), (ib, j2), (i1, ja), (i2, ja), (ib, j1)],
        [(ib, ja), (i1, j1), (i1, j2), (i2, j1), (i2, j2)],
    ][five];
    // The two faces first: on na, relative to a's plane, a lies at 0 and b at db; on nb,
    // b at 0 and a at da. Moving a along +n by (bmax - amin), or along -n by (amax - bmin).
    // Each candidate's axis `c`, translation `s`, direction and ranking key `s |s| / |c|^2`
    // (numerator and denominator; the seven divisions are done together below, as
    // independent lanes). Every candidate is kept and the winner taken by index: a `match`
    // on it would mispredict. (No `array::map`: a generic closure is not inlined into the
    // AVX2 build.)
    let mut cs = [V::zeros(); 7];
    let mut ss = [0.0; 7];
    let mut dirs = [0.0; 7];
    let mut num = [0.0; 8];
    let mut den = [1.0; 8];
    let mut face = |slot: usize, n: &V, (amin, amax): (f64, f64), (bmin, bmax): (f64, f64)| {
        let (up, down) = (bmax - amin, amax - bmin);
        let s = min(up, down);
        num[slot] = s * s.abs();
        den[slot] = n.norm_squared();
        (cs[slot], ss[slot]) = (*n, s);
        dirs[slot] = if up <= down { 1.0 } else { -1.0 };
    };
    face(0, na, (0.0, 0.0), min_max(db));
    face(1, nb, min_max(da), (0.0, 0.0));
    // The five facets: `c = ea_i x eb_j`, `s` the edges' offset `c . (vb_j - va_i)` signed
    // by `a3_j` (a moves along `+c` when it is positive; no `a3` is zero here).
    for (m, &(i, j)) in pairs.iter().enumerate() {
        let c = ea[i].cross(&eb[j]);
        // +-1 exactly: `s` is `t` or `-t`, chosen without a branch.
        let dir = 1.0f64.copysign(a3[j]);
        let s = dir * c.dot(&(vb[j] - va[i]));
        num[m + 2] = s * s.abs();
        den[m + 2] = c.norm_squared();
        (cs[m + 2], ss[m + 2], dirs[m + 2]) = (c, s, dir);
    }
    let mut keys = [0.0; 8];
    for m in 0..8 {
        keys[m] = num[m] / den[m];
    }
    let mut key = f64::INFINITY;
    let mut at = usize::MAX;
    for m in 0..7 {
        // NaN (|c|^2 = 0) loses every comparison.
        let k = if den[m] > 0.0 { keys[m] } else { f64::INFINITY };
        take_min(&mut key, &mut at, k, m);
    }
    if at < 7 {
        Axis {
            c: cs[at],
            s: ss[at],
            dir: dirs[at],
            key,
        }
    } else {
        Axis::default()
    }
}

/// [`triangles_sat`] when an edge lies along the other's plane (or its side is not
/// certain): the two normals and the nine edge crosses with both projections in full
/// (relative to `va[i]`: `a`'s edge at 0 and its third vertex at `a3_j`; `b`'s edge at
/// `c . (vb_j - va_i)` and its third vertex `b3_i` further).
#[cold]
#[allow(clippy::too_many_arguments)]
fn triangles_sat_all(
    va: &[V; 3],
    vb: &[V; 3],
    na: &V,
    nb: &V,
    da: &[f64; 3],
    db: &[f64; 3],
    ea: &[V; 3],
    eb: &[V; 3],
    a3: &[f64; 3],
    b3: &[f64; 3],
) -> Axis {
    let mut best = Axis::default();
    best.offer_intervals(na, (0.0, 0.0), min_max(db));
    best.offer_intervals(nb, min_max(da), (0.0, 0.0));
    for i in 0..3 {
        for j in 0..3 {
            let c = ea[i].cross(&eb[j]);
            let b0 = c.dot(&(vb[j] - va[i]));
            best.offer_intervals(&c, min_max2(0.0, a3[j]), min_max2(b0, b0 + b3[i]));
        }
    }
    best
}

/// `best = min(best, key)`, remembering `at`, without a branch.
#[inline(always)]
fn take_min(best: &mut f64, at: &mut usize, key: f64, here: usize) {
    let mask = usize::from(key < *best).wrapping_neg();
    *at = (here & mask) | (*at & !mask);
    *best = best.min(key);
}

#[inline(always)]
fn min_max2(x: f64, y: f64) -> (f64, f64) {
    if x <= y {
        (x, y)
    } else {
        (y, x)
    }
}

#[inline(always)]
fn min_max(d: &[f64; 3]) -> (f64, f64) {
    let (lo, hi) = min_max2(d[0], d[1]);
    (
        if d[2] < lo { d[2] } else { lo },
        if d[2] > hi { d[2] } else { hi },
    )
}
