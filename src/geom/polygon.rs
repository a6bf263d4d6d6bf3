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
        let zero = [[0.0; 3]; 3];
        Prepared {
            poly: Polygon::default(),
            planes: [Plane::of(&zero); 2],
        }
    }
}

impl Prepared {
    /// The polygon made of `tris[..n]` (`n` is 1 or 2).
    #[inline]
    pub fn of(tris: [[P3; 3]; 2], n: usize) -> Prepared {
        Prepared {
            poly: Polygon { tris, n },
            planes: [Plane::of(&tris[0]), Plane::of(&tris[n - 1])],
        }
    }

    /// The viewing volumes of the polygon's triangles (`h > 0`).
    pub fn cells(&self, h: f64) -> [Cell; 2] {
        [
            Cell::of_triangle(&self.poly.tris[0], h),
            Cell::of_triangle(&self.poly.tris[self.poly.n - 1], h),
        ]
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
