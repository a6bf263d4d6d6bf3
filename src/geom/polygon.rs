//! A polygon as one or two `f64` triangles, and the query's narrow test on a polygon pair
//! (step 5): does the candidate meet the volume polygon's viewing volume, or intersect the
//! polygon exactly?

use super::tritri::{separated, triangles_intersect_with, Plane};
use super::volume::Cell;
use super::P3;

/// A polygon as one or two `f64` triangles (`tris[..n]`; a quad is two).
#[derive(Clone, Copy, Default)]
pub struct Polygon {
    /// The triangles; only the first `n` count.
    pub tris: [[P3; 3]; 2],
    /// 1 or 2.
    pub n: usize,
}

/// A polygon with its triangles' planes, made once and tested against many others.
#[derive(Clone, Copy)]
pub struct Prepared {
    /// The polygon.
    pub poly: Polygon,
    /// The planes of `poly.tris[0]` and `poly.tris[n - 1]`.
    pub planes: [Plane; 2],
}

impl Default for Prepared {
    fn default() -> Self {
        Prepared {
            poly: Polygon::default(),
            planes: [Plane::ZERO; 2],
        }
    }
}

impl Prepared {
    /// The polygon made of `tris[..n]` (`n` is 1 or 2).
    #[inline]
    pub fn of(tris: [[P3; 3]; 2], n: usize) -> Prepared {
        let mut p = Prepared {
            poly: Polygon { tris, n },
            planes: [Plane::ZERO; 2],
        };
        p.remake(n);
        p
    }

    /// Made again in place once the caller has written new triangles into
    /// `self.poly.tris[..n]`: the same value as [`Prepared::of`], without building one on
    /// the stack and copying it in (the copy, 300 bytes loaded whole right after being
    /// stored piecewise, was a third of the time of preparing a polygon).
    #[inline]
    pub fn remake(&mut self, n: usize) {
        let first = Plane::of(&self.poly.tris[0]);
        // A triangle's two planes are the same (no second computation).
        self.poly.n = n;
        self.planes[0] = first;
        self.planes[1] = if n == 1 {
            first
        } else {
            Plane::of(&self.poly.tris[1])
        };
    }

    /// This polygon's and `o`'s triangles when both are triangles (what the lane kernels
    /// take); `None` when either is a quad.
    #[inline]
    pub fn triangle_pair<'s>(&'s self, o: &'s Prepared) -> Option<[&'s [P3; 3]; 2]> {
        (self.poly.n == 1 && o.poly.n == 1).then_some([&self.poly.tris[0], &o.poly.tris[0]])
    }

    /// The viewing volumes of the polygon's triangles (`h > 0`).
    pub fn cells(&self, h: f64) -> [Cell; 2] {
        [
            Cell::of_triangle(&self.poly.tris[0], h),
            Cell::of_triangle(&self.poly.tris[self.poly.n - 1], h),
        ]
    }

    /// Is polygon `c` certainly farther than `h` from this one (`cells` this polygon's
    /// viewing volumes of half depth `h`, [`Cell::far_from`] for every triangle pair)? Then
    /// `c` meets neither this polygon nor its volumes, and this polygon meets none of
    /// `c`'s volumes of half depth `h`: [`Prepared::meets`] is false both ways round.
    #[inline]
    pub fn far_apart(&self, cells: &[Cell; 2], c: &Prepared, h: f64) -> bool {
        (0..self.poly.n).all(|a| (0..c.poly.n).all(|b| cells[a].far_from(&c.poly.tris[b], h)))
    }

    /// Step 5's test of a box-overlapping pair: candidate `c` survives clipping against the
    /// viewing volumes `cells` of `self` (`h > 0`), or the closed polygons intersect (exact
    /// predicates, after a conservative plane rejection).
    #[inline]
    pub fn meets(&self, c: &Prepared, cells: Option<&[Cell; 2]>) -> bool {
        (0..self.poly.n).any(|a| {
            (0..c.poly.n).any(|b| {
                let (ta, tb) = (&self.poly.tris[a], &c.poly.tris[b]);
                cells.is_some_and(|cl| cl[a].meets_triangle(tb)) || {
                    // The planes' certain signs spare the exact test those orientations.
                    let su = self.planes[a].sides(tb);
                    !separated(su) && {
                        let st = c.planes[b].sides(ta);
                        !separated(st) && triangles_intersect_with(ta, tb, su, st)
                    }
                }
            })
        })
    }
}

/// Step 5's decision for one polygon pair, each given as its triangles (`v_tris[..nv]`,
/// `c_tris[..nc]`): with `h > 0`, does the candidate meet the viewing volume of `v` or
/// intersect it exactly; with `h = 0`, do the closed polygons intersect? Every backend's
/// final answer comes from this test, so their contacts are the same.
pub fn polygon_meets(
    v_tris: &[[P3; 3]; 2],
    nv: usize,
    c_tris: &[[P3; 3]; 2],
    nc: usize,
    h: f64,
) -> bool {
    let (v, c) = (Prepared::of(*v_tris, nv), Prepared::of(*c_tris, nc));
    let cells = (h > 0.0).then(|| v.cells(h));
    v.meets(&c, cells.as_ref())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `far_apart` only where `meets` is false both ways round (and no corners are within
    /// `h`), on random triangles and quads near each other, degenerate ones included.
    #[test]
    fn far_apart_only_when_neither_meets() {
        let mut s = 0x2545_F491_4F6C_DD1Du64;
        let mut rnd = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut far, mut cases) = (0, 0);
        for i in 0..20_000 {
            let mut poly = |n: usize| {
                let o = [rnd() * 2.0, rnd() * 2.0, rnd() * 0.5];
                let mut t = [[o; 3]; 2];
                for tri in t.iter_mut() {
                    for p in tri.iter_mut().skip(1) {
                        *p = [o[0] + rnd() - 0.5, o[1] + rnd() - 0.5, o[2] + rnd() * 0.2];
                    }
                }
                // Every 16th polygon a segment (degenerate).
                if i % 16 == 0 {
                    t[0][2] = t[0][1];
                }
                t[1][1] = t[0][2];
                Prepared::of(t, n)
            };
            let (a, b) = (poly(1 + i % 2), poly(1 + i / 2 % 2));
            let h = 0.01 + rnd() * 0.3;
            let (ca, cb) = (a.cells(h), b.cells(h));
            cases += 1;
            if a.far_apart(&ca, &b, h) {
                far += 1;
                assert!(
                    !a.meets(&b, Some(&ca)) && !b.meets(&a, Some(&cb)),
                    "case {i}"
                );
                // A consequence that shares nothing with the test: no corner of b within
                // h of a corner of a.
                for tb in &b.poly.tris[..b.poly.n] {
                    for p in tb {
                        for ta in &a.poly.tris[..a.poly.n] {
                            let near = ta.iter().any(|q| {
                                let d = [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
                                (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt() <= h
                            });
                            assert!(!near, "case {i}: a corner within h of a corner");
                        }
                    }
                }
            }
        }
        assert!(
            far > cases / 10 && far < cases - cases / 10,
            "{far} of {cases} far apart"
        );
    }
}
