//! The collision query of paper section 2.2, steps 1 to 5, asked of a backend: either the
//! backend runs them all itself ([`Engine::Whole`]), or [`run`] sequences them, one batch per
//! step ([`Engine::Steps`], the paper's way).
//!
//! Every polygon lies in exactly one leaf, so a polygon pair is asked about at most once
//! in step 5: through the one (reference leaf, other leaf) pair that holds it.

use crate::backend::{
    Batch, Engine, Group, Hit, Prim, QueryMeshes, Selector, Step, StepQuery, ROOT,
};
use crate::error::Result;

pub mod all;
pub mod continuous;
pub mod impact;
mod neighbours;

pub use crate::backend::{Contact, QueryStats};

/// Buffers reused from query to query.
#[derive(Default)]
pub struct Workspace {
    batch: Batch,
    hits: Vec<Hit>,
    /// Step 1: other meshes' leaves that meet the reference root.
    others: Vec<Prim>,
    /// Step 2: (other leaf, reference leaf) pairs whose boxes meet.
    pairs: Vec<(Prim, u32)>,
    /// Steps 3 and 4: the pair each candidate polygon came through.
    cand_pair: Vec<u32>,
    /// Step 3: (pair, reference polygon); step 4: (pair, other polygon).
    ref_polys: Vec<(u32, u32)>,
    other_polys: Vec<(u32, u32)>,
    by_ref_leaf: Vec<u32>,
    /// Step 3 and 4 hits bucketed by pair (counting sort): offsets and polygons.
    ref_start: Vec<u32>,
    ref_sorted: Vec<u32>,
    other_start: Vec<u32>,
    other_sorted: Vec<u32>,
    pub stats: QueryStats,
}

impl Workspace {
    /// Asks `sel` the current batch as step `step` (0-based); hits in `self.hits`.
    fn ask(&mut self, sel: &mut dyn StepQuery, q: &QueryMeshes<'_>, step: usize) -> Result<()> {
        self.hits.clear();
        self.stats.tests[step] = self.batch.tests();
        if !self.batch.groups.is_empty() {
            let t = std::time::Instant::now();
            sel.select(q, &self.batch, &mut self.hits)?;
            self.stats.nanos[step] = t.elapsed().as_nanos() as u64;
        }
        self.stats.hits[step] = self.hits.len();
        Ok(())
    }
}

/// Runs the five steps for `q.meshes[0]` against the others; `out` gets the contacts
/// (sorted, each pair once) and `ws.stats` the counts. On an error `out` is left cleared.
pub fn run(
    sel: &mut dyn Selector,
    q: &QueryMeshes<'_>,
    ws: &mut Workspace,
    out: &mut Vec<Contact>,
) -> Result<()> {
    out.clear();
    ws.stats = QueryStats::default();
    let r = match sel.engine() {
        Engine::Whole(w) => w.run_query(q, out, &mut ws.stats),
        Engine::Steps(s) => run_steps(s, q, ws, out),
    };
    if r.is_err() {
        out.clear();
    }
    r?;
    out.sort_unstable();
    out.dedup();
    Ok(())
}

/// The five steps, one batch each, answered by `sel`; contacts appended to `out`.
pub fn run_steps(
    sel: &mut dyn StepQuery,
    q: &QueryMeshes<'_>,
    ws: &mut Workspace,
    out: &mut Vec<Contact>,
) -> Result<()> {
    if step1(sel, q, ws)? && step2(sel, q, ws)? {
        step3(sel, q, ws)?;
        step4(sel, q, ws)?;
        step5(sel, q, ws, out)?;
    }
    Ok(())
}

/// Step 1: the other meshes' boxes inside the reference's root box, into `ws.others`.
fn step1(sel: &mut dyn StepQuery, q: &QueryMeshes<'_>, ws: &mut Workspace) -> Result<bool> {
    let reference = q.meshes[0].1;
    ws.batch.reset(Step::BoxesInBoxes);
    ws.batch.volumes.push(Prim {
        mesh: 0,
        index: ROOT,
    });
    for (mi, (_, m)) in q.meshes.iter().enumerate().skip(1) {
        if reference.root().overlaps(&m.root(), q.half_depth) {
            ws.batch
                .candidates
                .extend((0..m.leaf_count() as u32).map(|index| Prim {
                    mesh: mi as u32,
                    index,
                }));
        }
    }
    if ws.batch.candidates.is_empty() {
        return Ok(false);
    }
    ws.batch.groups.push(Group {
        volumes: 0..1,
        candidates: 0..ws.batch.candidates.len() as u32,
    });
    ws.ask(sel, q, 0)?;
    ws.others.clear();
    ws.others.extend(
        ws.hits
            .iter()
            .map(|h| ws.batch.candidates[h.candidate as usize]),
    );
    ws.others.sort_unstable_by_key(|p| (p.mesh, p.index));
    Ok(!ws.others.is_empty())
}

/// Step 2: for each of those boxes, the reference's leaf boxes inside it, into
/// `ws.pairs` (other leaf, reference leaf).
fn step2(sel: &mut dyn StepQuery, q: &QueryMeshes<'_>, ws: &mut Workspace) -> Result<bool> {
    let reference = q.meshes[0].1;
    ws.batch.reset(Step::BoxesInBoxes);
    ws.batch.volumes.extend_from_slice(&ws.others);
    ws.batch
        .candidates
        .extend((0..reference.leaf_count() as u32).map(|index| Prim { mesh: 0, index }));
    ws.batch.groups.push(Group {
        volumes: 0..ws.others.len() as u32,
        candidates: 0..ws.batch.candidates.len() as u32,
    });
    ws.ask(sel, q, 1)?;
    ws.pairs.clear();
    ws.pairs.extend(ws.hits.iter().map(|h| {
        (
            ws.others[h.volume as usize],
            ws.batch.candidates[h.candidate as usize].index,
        )
    }));
    ws.pairs
        .sort_unstable_by_key(|(b, r)| (b.mesh, b.index, *r));
    Ok(!ws.pairs.is_empty())
}

/// Step 3 (combined with step 2, as the paper suggests): for each other box B, the
/// reference polygons of the leaves paired with B that lie inside B, into `ws.ref_polys`
/// (pair, reference polygon).
fn step3(sel: &mut dyn StepQuery, q: &QueryMeshes<'_>, ws: &mut Workspace) -> Result<()> {
    let reference = q.meshes[0].1;
    ws.batch.reset(Step::PolygonsInBoxes);
    ws.cand_pair.clear();
    let mut i = 0;
    while i < ws.pairs.len() {
        let b = ws.pairs[i].0;
        let (v, c0) = (
            ws.batch.volumes.len() as u32,
            ws.batch.candidates.len() as u32,
        );
        ws.batch.volumes.push(b);
        while i < ws.pairs.len() && ws.pairs[i].0 == b {
            for p in reference.leaves().polys(ws.pairs[i].1 as usize) {
                ws.batch.candidates.push(Prim {
                    mesh: 0,
                    index: p as u32,
                });
                ws.cand_pair.push(i as u32);
            }
            i += 1;
        }
        ws.batch.groups.push(Group {
            volumes: v..v + 1,
            candidates: c0..ws.batch.candidates.len() as u32,
        });
    }
    ws.ask(sel, q, 2)?;
    ws.ref_polys.clear();
    ws.ref_polys.extend(ws.hits.iter().map(|h| {
        (
            ws.cand_pair[h.candidate as usize],
            ws.batch.candidates[h.candidate as usize].index,
        )
    }));
    Ok(())
}

/// Step 4: for each reference leaf R, the other meshes' polygons of the boxes paired
/// with R that lie inside R, into `ws.other_polys` (pair, other polygon).
fn step4(sel: &mut dyn StepQuery, q: &QueryMeshes<'_>, ws: &mut Workspace) -> Result<()> {
    ws.by_ref_leaf.clear();
    ws.by_ref_leaf.extend(0..ws.pairs.len() as u32);
    let pairs = &ws.pairs;
    ws.by_ref_leaf
        .sort_unstable_by_key(|&k| (pairs[k as usize].1, k));
    ws.batch.reset(Step::PolygonsInBoxes);
    ws.cand_pair.clear();
    let mut i = 0;
    while i < ws.by_ref_leaf.len() {
        let r = ws.pairs[ws.by_ref_leaf[i] as usize].1;
        let (v, c0) = (
            ws.batch.volumes.len() as u32,
            ws.batch.candidates.len() as u32,
        );
        ws.batch.volumes.push(Prim { mesh: 0, index: r });
        while i < ws.by_ref_leaf.len() && ws.pairs[ws.by_ref_leaf[i] as usize].1 == r {
            let k = ws.by_ref_leaf[i];
            let b = ws.pairs[k as usize].0;
            for p in q.mesh(b).leaves().polys(b.index as usize) {
                ws.batch.candidates.push(Prim {
                    mesh: b.mesh,
                    index: p as u32,
                });
                ws.cand_pair.push(k);
            }
            i += 1;
        }
        ws.batch.groups.push(Group {
            volumes: v..v + 1,
            candidates: c0..ws.batch.candidates.len() as u32,
        });
    }
    ws.ask(sel, q, 3)?;
    ws.other_polys.clear();
    ws.other_polys.extend(ws.hits.iter().map(|h| {
        (
            ws.cand_pair[h.candidate as usize],
            ws.batch.candidates[h.candidate as usize].index,
        )
    }));
    Ok(())
}

/// Step 5: for each leaf pair, every reference polygon found in step 3 becomes a viewing
/// volume (section 2.3) and the other polygons found in step 4 are drawn into it.
fn step5(
    sel: &mut dyn StepQuery,
    q: &QueryMeshes<'_>,
    ws: &mut Workspace,
    out: &mut Vec<Contact>,
) -> Result<()> {
    let reference = q.meshes[0].1;
    let n_pairs = ws.pairs.len();
    bucket(
        &ws.ref_polys,
        n_pairs,
        &mut ws.ref_start,
        &mut ws.ref_sorted,
    );
    bucket(
        &ws.other_polys,
        n_pairs,
        &mut ws.other_start,
        &mut ws.other_sorted,
    );
    ws.batch.reset(Step::PolygonsInPolygons);
    for pair in 0..n_pairs {
        let refs = &ws.ref_sorted[ws.ref_start[pair] as usize..ws.ref_start[pair + 1] as usize];
        let others =
            &ws.other_sorted[ws.other_start[pair] as usize..ws.other_start[pair + 1] as usize];
        if refs.is_empty() || others.is_empty() {
            continue;
        }
        let (v0, c0) = (
            ws.batch.volumes.len() as u32,
            ws.batch.candidates.len() as u32,
        );
        let mesh = ws.pairs[pair].0.mesh;
        ws.batch
            .volumes
            .extend(refs.iter().map(|&index| Prim { mesh: 0, index }));
        ws.batch
            .candidates
            .extend(others.iter().map(|&index| Prim { mesh, index }));
        ws.batch.groups.push(Group {
            volumes: v0..ws.batch.volumes.len() as u32,
            candidates: c0..ws.batch.candidates.len() as u32,
        });
    }
    ws.ask(sel, q, 4)?;
    out.extend(ws.hits.iter().map(|h| {
        let v = ws.batch.volumes[h.volume as usize];
        let c = ws.batch.candidates[h.candidate as usize];
        let (id, m) = q.meshes[c.mesh as usize];
        Contact {
            other_mesh: id,
            reference_polygon: reference.poly_ids[v.index as usize],
            other_polygon: m.poly_ids[c.index as usize],
        }
    }));
    Ok(())
}

/// Counting sort of (key, value) items with keys below `n`: `start` gets `n + 1` offsets
/// and `sorted` the values, key after key, in their original order within a key.
fn bucket(items: &[(u32, u32)], n: usize, start: &mut Vec<u32>, sorted: &mut Vec<u32>) {
    start.clear();
    start.resize(n + 1, 0);
    for &(k, _) in items {
        start[k as usize + 1] += 1;
    }
    for i in 0..n {
        start[i + 1] += start[i];
    }
    sorted.clear();
    sorted.resize(items.len(), 0);
    // Fill through a moving cursor per key (start[k] shifted one place, then restored).
    for &(k, v) in items {
        let at = &mut start[k as usize];
        sorted[*at as usize] = v;
        *at += 1;
    }
    for i in (1..=n).rev() {
        start[i] = start[i - 1];
    }
    start[0] = 0;
}

#[cfg(test)]
mod tests {
    use super::bucket;

    #[test]
    fn bucket_groups_by_key_stably() {
        let items = [(2, 10), (0, 11), (2, 12), (3, 13), (0, 14)];
        let (mut start, mut sorted) = (Vec::new(), Vec::new());
        bucket(&items, 5, &mut start, &mut sorted);
        assert_eq!(start, vec![0, 2, 2, 4, 5, 5]);
        assert_eq!(sorted, vec![11, 14, 10, 12, 13]);
    }
}
