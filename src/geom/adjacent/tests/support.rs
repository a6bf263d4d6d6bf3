//! What the adjacency tests share: a case (two polygons, indices and positions) checked by
//! the predicate through both entry points and both orders, and the tally of a family of
//! cases against the oracle.

use super::oracle;
use crate::geom::adjacent::{
    adjacent_polygons_meet, adjacent_polygons_meet_at, triangles_touch_only_at_joint,
    triangles_touch_only_at_joint_planes,
};
use crate::geom::predicates::P3;
use crate::geom::tritri::Plane;

/// Two polygons: indices and one position per vertex.
#[derive(Clone, Debug)]
pub(super) struct Case {
    a_idx: Vec<u32>,
    a_pos: Vec<P3>,
    b_idx: Vec<u32>,
    b_pos: Vec<P3>,
}

impl Case {
    /// Polygons `a` and `b` over the vertex positions `pos`.
    pub(super) fn new(a: &[u32], b: &[u32], pos: &[P3]) -> Case {
        Case {
            a_idx: a.to_vec(),
            a_pos: a.iter().map(|&i| pos[i as usize]).collect(),
            b_idx: b.to_vec(),
            b_pos: b.iter().map(|&i| pos[i as usize]).collect(),
        }
    }

    pub(super) fn tris(pos: &[P3]) -> ([[P3; 3]; 2], usize) {
        let mut t = [[pos[0], pos[1], pos[2]]; 2];
        if pos.len() == 4 {
            t[1] = [pos[0], pos[2], pos[3]];
        }
        (t, pos.len() - 2)
    }

    /// The predicate, in both orders (which must agree), and through the other entry point
    /// too when asked.
    pub(super) fn predicate(&self, both_entries: bool) -> bool {
        let r = adjacent_polygons_meet_at(&self.a_idx, &self.a_pos, &self.b_idx, &self.b_pos);
        if both_entries {
            let (ta, na) = Case::tris(&self.a_pos);
            let (tb, nb) = Case::tris(&self.b_pos);
            assert_eq!(
                r,
                adjacent_polygons_meet(&self.a_idx, &ta, na, &self.b_idx, &tb, nb),
                "entry points disagree on {self:?}"
            );
        }
        assert_eq!(
            r,
            adjacent_polygons_meet_at(&self.b_idx, &self.b_pos, &self.a_idx, &self.a_pos),
            "asymmetric answer on {self:?}"
        );
        r
    }

    pub(super) fn oracle(&self) -> bool {
        oracle::meets(&self.a_idx, &self.a_pos, &self.b_idx, &self.b_pos)
    }
}

/// Counts of a family of cases.
#[derive(Default)]
pub(super) struct Tally {
    cases: usize,
    meets: usize,
    /// Triangle pairs [`triangles_touch_only_at_joint`] decided (either order).
    quick: usize,
    bad: Vec<String>,
}

impl Tally {
    pub(super) fn check(&mut self, c: &Case) {
        let want = c.oracle();
        let got = c.predicate(self.cases.is_multiple_of(8));
        self.cases += 1;
        self.meets += usize::from(want);
        if got != want && self.bad.len() < 5 {
            self.bad
                .push(format!("predicate {got}, oracle {want}: {c:?}"));
        }
        // The quick test: "no meeting" only where the oracle says so.
        if c.a_idx.len() == 3 && c.b_idx.len() == 3 {
            let tri = |i: &[u32], p: &[P3]| ([i[0], i[1], i[2]], [p[0], p[1], p[2]]);
            let (ai, ap) = tri(&c.a_idx, &c.a_pos);
            let (bi, bp) = tri(&c.b_idx, &c.b_pos);
            let (pa, pb) = (Plane::of(&ap), Plane::of(&bp));
            let planes = triangles_touch_only_at_joint_planes(&ai, &ap, &pa, &bi, &bp, &pb);
            let exact = triangles_touch_only_at_joint(&ai, &ap, &bi, &bp);
            if planes && !exact && self.bad.len() < 5 {
                self.bad
                    .push(format!("quick test: planes {planes}, exact {exact}: {c:?}"));
            }
            for quick in [exact, triangles_touch_only_at_joint(&bi, &bp, &ai, &ap)] {
                self.quick += usize::from(quick);
                if quick && want && self.bad.len() < 5 {
                    self.bad
                        .push(format!("quick test: no meeting, oracle: meets: {c:?}"));
                }
            }
        }
    }

    pub(super) fn finish(self, name: &str, min_cases: usize) {
        println!(
            "{name}: {} cases, {} meeting, {} quick decisions, {} disagreements",
            self.cases,
            self.meets,
            self.quick,
            self.bad.len()
        );
        assert!(
            self.bad.is_empty(),
            "{name}: disagreements:\n{}",
            self.bad.join("\n")
        );
        assert!(self.cases >= min_cases, "{name}: only {} cases", self.cases);
        assert!(
            self.meets > self.cases / 50 && self.meets < self.cases - self.cases / 50,
            "{name}: {} of {} meet: the cases are not adversarial",
            self.meets,
            self.cases
        );
    }
}
