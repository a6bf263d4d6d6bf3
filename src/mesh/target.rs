//! A mesh's target: the end (t = 1) of a continuous step whose start (t = 0) is the mesh's
//! current state. Vertices given a target position move to it, the others keep their start
//! positions, and all take the target transform when one is set (else the current one).
//! Each vertex's world position moves on the straight line between its start and end world
//! positions.
//!
//! A target is not committed: it changes no discrete query's answer and no state those
//! queries read (positions, boxes, generation, pose), and lasts until the mesh's positions
//! are updated, its transform set, or the target cleared. Stored compactly: runs of
//! consecutive vertices given, in the mesh's precision (a mesh without a target holds one
//! null pointer).

use super::{grow_f64, Mesh, Placement, Positions};
use crate::error::{Error, ErrorKind, Result};
use crate::geom::affine::Affine;
use crate::geom::{widen, Aabb, P3};

/// The end of a step (see the module's documentation).
#[derive(Clone, Debug, Default)]
pub(crate) struct Target {
    /// The target positions given, in the mesh's own frame and precision.
    end: End,
    /// The target transform (None: the mesh's current one at t = 1 too).
    transform: Option<Affine>,
}

/// Target positions: runs of consecutive vertices, sorted, disjoint and not adjacent.
#[derive(Clone, Debug)]
enum End {
    F32(Vec<Run<[f32; 3]>>),
    F64(Vec<Run<P3>>),
}

impl Default for End {
    fn default() -> Self {
        End::F32(Vec::new())
    }
}

/// Vertices `first..first + pos.len()` at `pos`.
#[derive(Clone, Debug)]
struct Run<T> {
    first: usize,
    pos: Vec<T>,
}

impl<T> Run<T> {
    fn end(&self) -> usize {
        self.first + self.pos.len()
    }
}

/// Sets vertices `first..first + new.len()` of `runs` to `new`, merging the runs it
/// overlaps or touches into one.
fn set_range<T: Copy>(runs: &mut Vec<Run<T>>, first: usize, new: Vec<T>) {
    let end = first + new.len();
    let lo = runs.partition_point(|r| r.end() < first);
    let hi = runs.partition_point(|r| r.first <= end);
    if lo == hi {
        runs.insert(lo, Run { first, pos: new });
        return;
    }
    // Only runs[lo] can start before `first`, only runs[hi - 1] end after `end`.
    let start = runs[lo].first.min(first);
    let mut pos = Vec::with_capacity(runs[hi - 1].end().max(end) - start);
    pos.extend_from_slice(&runs[lo].pos[..first.saturating_sub(runs[lo].first)]);
    pos.extend_from_slice(&new);
    let last = &runs[hi - 1];
    if last.end() > end {
        pos.extend_from_slice(&last.pos[end - last.first..]);
    }
    runs.splice(lo..hi, [Run { first: start, pos }]);
}

/// The target position of vertex `v` in `runs`, if given.
fn find<T: Copy>(runs: &[Run<T>], v: usize) -> Option<T> {
    let i = runs.partition_point(|r| r.end() <= v);
    runs.get(i)
        .filter(|r| r.first <= v)
        .map(|r| r.pos[v - r.first])
}

impl Target {
    /// A box holding every target position given (doubles rounded outward).
    fn bounds(&self) -> Aabb {
        let mut b = Aabb::EMPTY;
        match &self.end {
            End::F32(runs) => runs.iter().flat_map(|r| &r.pos).for_each(|p| b.grow(p)),
            End::F64(runs) => runs
                .iter()
                .flat_map(|r| &r.pos)
                .for_each(|p| grow_f64(&mut b, p)),
        }
        b
    }

    /// Target positions given, as vertices.
    fn vertices(&self) -> usize {
        match &self.end {
            End::F32(runs) => runs.iter().map(|r| r.pos.len()).sum(),
            End::F64(runs) => runs.iter().map(|r| r.pos.len()).sum(),
        }
    }

    /// Heap bytes the target holds (the runs' positions and headers).
    fn heap_bytes(&self) -> usize {
        let runs = |n: usize, cap: usize, each: usize| n * each + cap * 32;
        std::mem::size_of::<Target>()
            + match &self.end {
                End::F32(r) => runs(self.vertices(), r.capacity(), 12),
                End::F64(r) => runs(self.vertices(), r.capacity(), 24),
            }
    }
}

impl Mesh {
    /// Does the mesh have a target (target positions or a target transform)?
    pub fn has_target(&self) -> bool {
        self.target.is_some()
    }

    /// The target transform, when one was set.
    pub fn target_transform(&self) -> Option<&[f64; 12]> {
        self.target.as_ref()?.transform.as_ref().map(|m| &m.0)
    }

    /// Vertices given a target position (0 without).
    pub fn target_vertex_count(&self) -> usize {
        self.target.as_ref().map_or(0, |t| t.vertices())
    }

    /// Heap bytes the target holds (0 without).
    pub fn target_bytes(&self) -> usize {
        self.target.as_ref().map_or(0, |t| t.heap_bytes())
    }

    /// The caller's vertex `v` at its end world position (t = 1): its target position, or
    /// its start position when it was given none, under the target transform, or the
    /// current transform when none was set (evaluated as [`Affine::apply_f64`]). With no
    /// target, the start world position ([`Mesh::world_position`]). None for a vertex no
    /// polygon uses.
    pub fn end_world_position(&self, v: usize) -> Option<P3> {
        let start = self.vertex_position_f64(v)?;
        let Some(t) = &self.target else {
            return self.world_position(v);
        };
        let local = match &t.end {
            End::F32(runs) => find(runs, v).map(|p| widen(&p)),
            End::F64(runs) => find(runs, v),
        }
        .unwrap_or(start);
        let m = t.transform.as_ref().or(self.place.as_ref().map(|p| &p.m));
        Some(m.map_or(local, |m| m.apply_f64(&local)))
    }

    /// The world positions of every slot at the start (t = 0) and, when the mesh has a
    /// target, at the end (t = 1) into `start` and `end` (`end` left empty when the mesh
    /// stands still). The same values as [`Mesh::world_position`] and
    /// [`Mesh::end_world_position`] give for each slot's vertex.
    pub(crate) fn step_positions(&self, start: &mut Vec<P3>, end: &mut Vec<P3>) {
        let n = self.slots.len();
        start.clear();
        start.extend((0..n).map(|s| self.world(s)));
        end.clear();
        let Some(t) = &self.target else {
            return;
        };
        let m = t.transform.as_ref().or(self.place.as_ref().map(|p| &p.m));
        end.extend((0..n).map(|s| {
            let v = self.slot_vertex[s] as usize;
            let local = match &t.end {
                End::F32(runs) => find(runs, v).map(|p| widen(&p)),
                End::F64(runs) => find(runs, v),
            }
            .unwrap_or_else(|| self.local(s));
            m.map_or(local, |m| m.apply_f64(&local))
        }));
    }

    /// The matrix at t = 1 other than the identity: the target transform if set, else the
    /// current one.
    fn end_matrix(&self) -> Option<&Affine> {
        match self.target.as_ref().and_then(|t| t.transform.as_ref()) {
            Some(m) => Some(m),
            None => self.place.as_ref().map(|p| &p.m),
        }
    }

    /// Vertices `first..first + src.len()` get the target positions `src` (in the mesh's
    /// own frame and precision), replacing any they had; the other vertices keep theirs.
    /// Rejected whole, nothing changed: InvalidArgument for positions of the other
    /// precision or a range past the end; NonFinite for a coordinate that is not finite or
    /// beyond the float range, or end world positions that could leave it (judged from
    /// boxes holding the start and target positions, as [`Mesh::set_transform`] judges).
    /// An empty range changes nothing.
    pub fn set_target_positions(&mut self, first: usize, src: Positions<'_>) -> Result<()> {
        self.check_precision(&src, "set_target_positions")?;
        let end = self.vertex_range(first, src.len())?;
        if let Some(at) = src.first_non_finite() {
            return Err(src.non_finite(first + at, &src.get_f64(at)));
        }
        if first == end {
            return Ok(());
        }
        if let Some(m) = self.end_matrix() {
            let mut b = src.bounds();
            b.merge(&self.leaves.root);
            if let Some(t) = &self.target {
                b.merge(&t.bounds());
            }
            Placement::check_range(m, &b, "target positions")?;
        }
        let t = self.target.get_or_insert_with(Default::default);
        if src.is_f64() {
            if !matches!(t.end, End::F64(_)) {
                t.end = End::F64(Vec::new());
            }
            if let End::F64(runs) = &mut t.end {
                set_range(
                    runs,
                    first,
                    (0..src.len()).map(|i| src.get_f64(i)).collect(),
                );
            }
        } else if let End::F32(runs) = &mut t.end {
            set_range(runs, first, (0..src.len()).map(|i| src.get(i)).collect());
        }
        Ok(())
    }

    /// The mesh takes the placement `m` (row-major 3x4, as [`Mesh::set_transform`]) at the
    /// end of the step; the target positions, if any, stay. Rejected, nothing changed:
    /// NonFinite for an entry that is not finite or end world positions that could leave
    /// the float range.
    pub fn set_target_transform(&mut self, m: &[f64; 12]) -> Result<()> {
        if let Some(i) = Affine::first_non_finite(m) {
            return Err(Error::new(
                ErrorKind::NonFinite,
                format!("m[{i}] is {}; every entry must be finite", m[i]),
            ));
        }
        let a = Affine(*m);
        let mut b = self.leaves.root;
        if let Some(t) = &self.target {
            b.merge(&t.bounds());
        }
        Placement::check_range(&a, &b, "m")?;
        self.target.get_or_insert_with(Default::default).transform = Some(a);
        Ok(())
    }

    /// Drops the target (nothing when there is none): the mesh stands still in a step.
    pub fn clear_target(&mut self) {
        self.target = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn runs(r: &[Run<u32>]) -> Vec<(usize, Vec<u32>)> {
        r.iter().map(|r| (r.first, r.pos.clone())).collect()
    }

    #[test]
    fn ranges_merge_into_sorted_disjoint_runs() {
        let mut r: Vec<Run<u32>> = Vec::new();
        set_range(&mut r, 10, vec![1, 2, 3]);
        set_range(&mut r, 0, vec![7]);
        assert_eq!(runs(&r), [(0, vec![7]), (10, vec![1, 2, 3])]);
        // Adjacent on the right: merged.
        set_range(&mut r, 13, vec![4]);
        assert_eq!(runs(&r), [(0, vec![7]), (10, vec![1, 2, 3, 4])]);
        // Overlapping the inside: replaced there.
        set_range(&mut r, 11, vec![9, 9]);
        assert_eq!(runs(&r), [(0, vec![7]), (10, vec![1, 9, 9, 4])]);
        // Spanning both runs and the gap.
        set_range(&mut r, 1, vec![5; 10]);
        assert_eq!(
            runs(&r),
            [(0, vec![7, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 9, 9, 4])]
        );
        assert_eq!(find(&r, 13), Some(4));
        assert_eq!(find(&r, 14), None);
        set_range(&mut r, 20, vec![1]);
        assert_eq!(find(&r, 19), None);
        assert_eq!(find(&r, 20), Some(1));
        // Against a plain array, at random.
        let mut rng = 12345u64;
        let mut next = |n: u64| {
            rng = rng
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (rng >> 33) % n
        };
        for _ in 0..50 {
            let mut r: Vec<Run<u32>> = Vec::new();
            let mut want = [None; 40];
            for k in 0..20 {
                let first = next(40) as usize;
                let len = (next(8) as usize).min(40 - first);
                let new: Vec<u32> = (0..len as u32).map(|i| k * 100 + i).collect();
                for (i, &x) in new.iter().enumerate() {
                    want[first + i] = Some(x);
                }
                if len > 0 {
                    set_range(&mut r, first, new);
                }
                for (v, w) in want.iter().enumerate() {
                    assert_eq!(find(&r, v), *w);
                }
                for p in r.windows(2) {
                    assert!(p[0].end() < p[1].first, "runs touch: {:?}", runs(&r));
                }
            }
        }
    }
}
