//! A deformable mesh: positions (copied), fixed topology, and its leaf-only AABB structure.

use crate::bvh::{partition, rule_of_thumb, LeafBoxes};
use crate::error::{Error, ErrorKind, Result};
use crate::geom::affine::Affine;
use crate::geom::{f32_down, f32_up, widen, Aabb, P3};

mod positions;
mod target;

pub(crate) use positions::grow_f64;
pub use positions::Positions;
pub(crate) use target::Target;

/// Id of a mesh. Ids start at 1, are never 0 and never reused (unique in the process).
pub type MeshId = u32;

/// Most vertices a mesh can have, 2^32 - 1: vertex numbers are `u32`. The one limit of
/// [`Mesh::check_counts`] (which the C API calls before any array is read),
/// [`Positions::new`] and [`Mesh::new`], all through [`check_vertex_count`].
pub(crate) const MAX_VERTICES: usize = u32::MAX as usize;

/// Most polygon corners (polygons times vertices per polygon) a mesh can have, 2^32 - 2:
/// a mesh keeps a copy of a vertex per leaf that uses it ("slots", numbered by `u32`), and
/// there are at most as many slots as corners. Checked by [`check_polygon_count`].
pub(crate) const MAX_CORNERS: usize = u32::MAX as usize - 1;

/// Refuses a vertex count above [`MAX_VERTICES`], naming `vertex_count`.
pub(crate) fn check_vertex_count(count: usize) -> Result<()> {
    if count > MAX_VERTICES {
        return Err(Error::invalid(format!(
            "vertex_count {count} overflows the 32-bit vertex numbers (at most {MAX_VERTICES} = 2^32 - 1)"
        )));
    }
    Ok(())
}

/// Refuses `polygons` polygons of `k` vertices whose corners are more than [`MAX_CORNERS`],
/// naming `polygon_count`.
pub(crate) fn check_polygon_count(polygons: usize, k: usize) -> Result<()> {
    if polygons.checked_mul(k).is_none_or(|c| c > MAX_CORNERS) {
        return Err(Error::invalid(format!(
            "polygon_count {polygons} times vertices_per_polygon {k} overflows the 32-bit \
             corner numbers (at most {MAX_CORNERS} = 2^32 - 2 corners)"
        )));
    }
    Ok(())
}

impl Mesh {
    /// Refuses, before any array is read, counts no mesh can have: more than 2^32 - 1
    /// vertices, or `polygon_count * vertices_per_polygon` above 2^32 - 2 corners
    /// (InvalidArgument naming the count). [`Mesh::new`] makes the same checks.
    pub fn check_counts(
        vertex_count: usize,
        polygon_count: usize,
        vertices_per_polygon: usize,
    ) -> Result<()> {
        check_vertex_count(vertex_count)?;
        check_polygon_count(polygon_count, vertices_per_polygon)
    }
}

/// A mesh as the scene holds it.
///
/// Vertices are stored leaf by leaf in "slots" (see [`crate::bvh`]): the polygons index
/// slots, and a caller's vertex used by several leaves has one slot in each.
#[derive(Clone, Debug)]
pub struct Mesh {
    /// Positions of the slots, leaf after leaf (an f64 mesh: its doubles rounded to the
    /// nearest float, which only the GL backends' uploads and the float accessors read).
    pub(crate) slots: Vec<[f32; 3]>,
    /// An f64 mesh's positions of the slots, as given (empty for a float mesh): what every
    /// query answers for.
    pub(crate) slots64: Vec<[f64; 3]>,
    /// Slot -> the caller's vertex index.
    pub(crate) slot_vertex: Vec<u32>,
    /// The caller's vertex -> its slots: `vertex_slots[vertex_slot_start[v]..vertex_slot_start[v + 1]]`.
    vertex_slot_start: Vec<u32>,
    vertex_slots: Vec<u32>,
    /// Vertices per polygon: 3 or 4.
    pub(crate) k: usize,
    /// Polygons in leaf order, `k` slot indices each.
    pub(crate) polys: Vec<u32>,
    /// Leaf-order position -> the caller's polygon index.
    pub(crate) poly_ids: Vec<u32>,
    /// The caller's polygon index -> its leaf-order position (the inverse of `poly_ids`).
    pub(crate) poly_leaf: Vec<u32>,
    pub(crate) leaves: LeafBoxes,
    pub(crate) enabled: bool,
    /// Collided with itself by whole-scene queries.
    pub(crate) self_collision: bool,
    /// Filter: two meshes collide only if `a.group & b.mask != 0 && b.group & a.mask != 0`.
    pub(crate) group: u32,
    pub(crate) mask: u32,
    /// Bumped at every position change (lets GPU copies know they are stale).
    pub(crate) generation: u64,
    /// The placement (None: the identity, world positions are the `f32` ones).
    pub(crate) place: Option<Box<Placement>>,
    /// Bumped at every placement change (world polygon boxes cached per mesh are stale).
    pub(crate) pose: u64,
    /// Triangle meshes: each edge's twin by vertex index ([`crate::geom::patch::twins`],
    /// leaf order), made at the first self-collision query that needs it (the topology
    /// never changes); `None` inside where no patch certificate can be tried.
    twins: std::sync::OnceLock<Option<Box<[u32]>>>,
    /// The end of a continuous step, when one is set ([`Target`]); none costs one pointer.
    pub(crate) target: Option<Box<Target>>,
}

/// A mesh's placement: its matrix and its leaf boxes carried into the world
/// ([`Affine::world_box`] of the local boxes, never of the vertices).
#[derive(Clone, Debug)]
pub(crate) struct Placement {
    pub(crate) m: Affine,
    /// World boxes of the leaves, and of the root.
    pub(crate) boxes: Vec<Aabb>,
    pub(crate) root: Aabb,
}

impl Placement {
    /// Refuses a matrix under which some world coordinate of local box `root` could leave
    /// the `f32` range (NonFinite).
    fn check_range(m: &Affine, root: &Aabb, what: &str) -> Result<()> {
        let bound = m.magnitude_bound(root);
        if let Some(r) = (0..3).find(|&r| bound[r] > f64::from(f32::MAX)) {
            return Err(Error::new(
                ErrorKind::NonFinite,
                format!(
                    "{what}: world coordinate {} could reach {:e} (|m| * the largest local \
                     coordinates + |translation|), beyond the float range (3.4e38)",
                    ["x", "y", "z"][r],
                    bound[r]
                ),
            ));
        }
        Ok(())
    }

    /// The placement of local leaf boxes `leaves` by `m` (checked by `check_range`).
    fn of(m: Affine, leaves: &LeafBoxes) -> Placement {
        let mut p = Placement {
            m,
            boxes: Vec::new(),
            root: Aabb::EMPTY,
        };
        p.refit(leaves);
        p
    }

    /// The world boxes of the (refitted) local leaf boxes. No allocation once sized.
    fn refit(&mut self, leaves: &LeafBoxes) {
        self.boxes.clear();
        self.boxes
            .extend(leaves.boxes.iter().map(|b| self.m.world_box(b)));
        self.root = self.m.world_box(&leaves.root);
    }
}

impl Mesh {
    /// Validates and builds a mesh. `indices` holds `k` vertex indices per polygon, in the
    /// caller's polygon order; `max_per_leaf` of 0 applies the paper's rule of thumb.
    pub fn new(
        positions: Positions<'_>,
        indices: &[u32],
        k: usize,
        max_per_leaf: usize,
    ) -> Result<Mesh> {
        if k != 3 && k != 4 {
            return Err(Error::invalid(format!(
                "vertices_per_polygon is {k}; it must be 3 or 4"
            )));
        }
        if positions.is_empty() {
            return Err(Error::invalid("vertex_count is 0"));
        }
        if indices.is_empty() {
            return Err(Error::invalid("polygon_count is 0"));
        }
        if !indices.len().is_multiple_of(k) {
            return Err(Error::invalid(
                "index count is not a multiple of vertices_per_polygon",
            ));
        }
        let n_polys = indices.len() / k;
        let nv = positions.len();
        check_vertex_count(nv)?;
        check_polygon_count(n_polys, k)?;
        if let Some(v) = positions.first_non_finite() {
            return Err(positions.non_finite(v, &positions.get_f64(v)));
        }
        if let Some(i) = indices.iter().position(|&i| i as usize >= nv) {
            return Err(Error::new(
                ErrorKind::IndexOutOfRange,
                format!(
                    "indices: polygon {} names vertex {}, but vertex_count is {nv}",
                    i / k,
                    indices[i]
                ),
            ));
        }
        let pos: Vec<[f32; 3]> = (0..nv).map(|i| positions.get(i)).collect();
        let boxes: Vec<Aabb> = indices
            .chunks_exact(k)
            .map(|p| {
                let mut b = Aabb::EMPTY;
                p.iter().for_each(|&v| b.grow(&pos[v as usize]));
                b
            })
            .collect();
        let max = if max_per_leaf == 0 {
            rule_of_thumb(n_polys)
        } else {
            max_per_leaf
        };
        let (order, leaf_polys) = partition(&boxes, max);

        // Slots: each leaf's distinct vertices, ascending, one run per leaf.
        let leaves = leaf_polys.len() - 1;
        let mut slot_vertex: Vec<u32> = Vec::with_capacity(nv + nv / 4);
        let mut leaf_slots = Vec::with_capacity(leaves + 1);
        leaf_slots.push(0u32);
        let mut polys = Vec::with_capacity(indices.len());
        let mut slot_of = vec![0u32; nv];
        let mut tmp = Vec::new();
        for l in 0..leaves {
            let ps = &order[leaf_polys[l] as usize..leaf_polys[l + 1] as usize];
            tmp.clear();
            for &p in ps {
                tmp.extend_from_slice(&indices[p as usize * k..(p as usize + 1) * k]);
            }
            tmp.sort_unstable();
            tmp.dedup();
            for &v in &tmp {
                slot_of[v as usize] = slot_vertex.len() as u32;
                slot_vertex.push(v);
            }
            for &p in ps {
                polys.extend(
                    indices[p as usize * k..(p as usize + 1) * k]
                        .iter()
                        .map(|&v| slot_of[v as usize]),
                );
            }
            leaf_slots.push(slot_vertex.len() as u32);
        }
        // The inverse: each vertex's slots.
        let mut vertex_slot_start = vec![0u32; nv + 1];
        for &v in &slot_vertex {
            vertex_slot_start[v as usize + 1] += 1;
        }
        for v in 0..nv {
            vertex_slot_start[v + 1] += vertex_slot_start[v];
        }
        let mut fill = vertex_slot_start.clone();
        let mut vertex_slots = vec![0u32; slot_vertex.len()];
        for (s, &v) in slot_vertex.iter().enumerate() {
            vertex_slots[fill[v as usize] as usize] = s as u32;
            fill[v as usize] += 1;
        }
        let slots: Vec<[f32; 3]> = slot_vertex.iter().map(|&v| pos[v as usize]).collect();
        let slots64: Vec<[f64; 3]> = if positions.is_f64() {
            slot_vertex
                .iter()
                .map(|&v| positions.get_f64(v as usize))
                .collect()
        } else {
            Vec::new()
        };
        let mut lb = LeafBoxes {
            leaf_polys,
            leaf_slots,
            boxes: vec![Aabb::EMPTY; leaves],
            root: Aabb::EMPTY,
        };
        if positions.is_f64() {
            lb.refit_f64(&slots64);
        } else {
            lb.refit(&slots);
        }
        let mut poly_leaf = vec![0u32; order.len()];
        for (at, &p) in order.iter().enumerate() {
            poly_leaf[p as usize] = at as u32;
        }
        Ok(Mesh {
            slots,
            slots64,
            slot_vertex,
            vertex_slot_start,
            vertex_slots,
            k,
            polys,
            poly_ids: order,
            poly_leaf,
            leaves: lb,
            enabled: true,
            self_collision: false,
            group: 1,
            mask: u32::MAX,
            generation: 0,
            place: None,
            pose: 0,
            twins: std::sync::OnceLock::new(),
            target: None,
        })
    }

    /// The caller's vertex count.
    pub fn vertex_count(&self) -> usize {
        self.vertex_slot_start.len() - 1
    }

    /// Each edge's twin (see the field), for triangle meshes whose directed edges are
    /// all distinct.
    pub(crate) fn twins(&self) -> Option<&[u32]> {
        if self.k != 3 {
            return None;
        }
        self.twins
            .get_or_init(|| {
                let verts: Vec<[u32; 3]> = (0..self.polygon_count())
                    .map(|p| {
                        let v = self.poly(p);
                        [0, 1, 2].map(|i| self.slot_vertex[v[i] as usize])
                    })
                    .collect();
                crate::geom::patch::twins(&verts).map(Vec::into_boxed_slice)
            })
            .as_deref()
    }

    /// Number of polygons.
    pub fn polygon_count(&self) -> usize {
        self.poly_ids.len()
    }

    /// 3 (triangles) or 4 (quads).
    pub fn vertices_per_polygon(&self) -> usize {
        self.k
    }

    /// Number of leaf boxes.
    pub fn leaf_count(&self) -> usize {
        self.leaves.len()
    }

    /// The leaf structure in the mesh's own frame (the local root box and one local box per
    /// leaf, the polygon and slot ranges of each leaf).
    pub fn leaves(&self) -> &LeafBoxes {
        &self.leaves
    }

    /// The world leaf boxes: the local ones (an f64 mesh's rounded outward to `f32`), or
    /// with a placement boxes holding every world position of their leaves (in `f32`,
    /// rounded outward).
    #[inline]
    pub fn leaf_boxes(&self) -> &[Aabb] {
        match &self.place {
            Some(p) => &p.boxes,
            None => &self.leaves.boxes,
        }
    }

    /// The world root box: every vertex of the mesh at its world position (rounded
    /// outward to `f32` under a placement or for an f64 mesh).
    #[inline]
    pub fn root(&self) -> Aabb {
        match &self.place {
            Some(p) => p.root,
            None => self.leaves.root,
        }
    }

    /// The placement matrix (row-major 3x4), None for the identity.
    pub fn transform(&self) -> Option<&[f64; 12]> {
        self.place.as_ref().map(|p| &p.m.0)
    }

    /// Places the mesh: world position `m * (x, y, z, 1)` of every vertex (None, or a
    /// matrix equal to the identity: the vertices as given). Costs a few operations per
    /// leaf box, never touches a vertex. Refused (nothing changes) when an entry is not
    /// finite or a world coordinate could leave the `f32` range (NonFinite). Drops the
    /// mesh's target (see [`Mesh::has_target`]) when it succeeds.
    pub fn set_transform(&mut self, m: Option<&[f64; 12]>) -> Result<()> {
        let m = match m {
            Some(m) if !Affine(*m).is_identity() => *m,
            _ => {
                if self.place.take().is_some() {
                    self.pose += 1;
                }
                self.target = None;
                return Ok(());
            }
        };
        if let Some(i) = Affine::first_non_finite(&m) {
            return Err(Error::new(
                ErrorKind::NonFinite,
                format!("m[{i}] is {}; every entry must be finite", m[i]),
            ));
        }
        let a = Affine(m);
        Placement::check_range(&a, &self.leaves.root, "m")?;
        match &mut self.place {
            Some(p) => {
                p.m = a;
                p.refit(&self.leaves);
            }
            None => self.place = Some(Box::new(Placement::of(a, &self.leaves))),
        }
        self.pose += 1;
        self.target = None;
        Ok(())
    }

    /// An f64 mesh: made from double positions ([`Positions::is_f64`]), which it keeps and
    /// every query answers for. Updates and targets take double positions only.
    #[inline]
    pub fn is_f64(&self) -> bool {
        !self.slots64.is_empty()
    }

    /// Are the world positions other than the stored floats widened (a placement, or double
    /// positions)? Such a mesh's polygon boxes are its world positions' boxes rounded
    /// outward, and the GL backends, which hold float meshes in their own frames, leave its
    /// pairs to the CPU engine.
    #[inline]
    pub(crate) fn needs_cpu(&self) -> bool {
        self.place.is_some() || !self.slots64.is_empty()
    }

    /// The world position of slot `s`.
    #[inline]
    pub(crate) fn world(&self, s: usize) -> P3 {
        match (&self.place, self.slots64.is_empty()) {
            (None, true) => widen(&self.slots[s]),
            (Some(p), true) => p.m.apply(&self.slots[s]),
            (None, false) => self.slots64[s],
            (Some(p), false) => p.m.apply_f64(&self.slots64[s]),
        }
    }

    /// The caller's vertex `v` at its world position (None for a vertex no polygon uses).
    pub fn world_position(&self, v: usize) -> Option<P3> {
        let s = *self.vertex_slot_start.get(v)? as usize;
        (s < *self.vertex_slot_start.get(v + 1)? as usize)
            .then(|| self.world(self.vertex_slots[s] as usize))
    }

    /// Slot positions, leaf after leaf (what the polygons index); an f64 mesh's rounded to
    /// the nearest floats (its doubles: [`Mesh::vertex_position_f64`]).
    pub fn slot_positions(&self) -> &[[f32; 3]] {
        &self.slots
    }

    /// The slots' positions become `xyz` (three floats a slot, as many slots): a mesh read
    /// from a host GL buffer on the GPU gets the positions its last query used, for contact
    /// geometry. Nothing else changes (its boxes came from the GPU with that query; its
    /// generation stays, the positions being the ones the GPU already holds).
    pub(crate) fn set_slot_positions(&mut self, xyz: &[f32]) {
        debug_assert_eq!(xyz.len(), 3 * self.slots.len());
        for (s, p) in self.slots.iter_mut().zip(xyz.chunks_exact(3)) {
            *s = [p[0], p[1], p[2]];
        }
    }

    /// Slot -> the caller's vertex index.
    pub fn slot_vertices(&self) -> &[u32] {
        &self.slot_vertex
    }

    /// Leaf-ordered polygons, `vertices_per_polygon` slot indices each.
    pub fn polygon_slots(&self) -> &[u32] {
        &self.polys
    }

    /// Leaf-ordered polygon -> the caller's polygon index.
    pub fn polygon_ids(&self) -> &[u32] {
        &self.poly_ids
    }

    /// The caller's vertex `v` as stored (None for a vertex no polygon uses; an f64 mesh's
    /// rounded to the nearest float: see [`Mesh::vertex_position_f64`]).
    pub fn vertex_position(&self, v: usize) -> Option<[f32; 3]> {
        self.slot_of(v).map(|s| self.slots[s])
    }

    /// The caller's vertex `v` in the mesh's own frame, as doubles: an f64 mesh's as
    /// given, a float mesh's widened (None for a vertex no polygon uses).
    pub fn vertex_position_f64(&self, v: usize) -> Option<P3> {
        self.slot_of(v).map(|s| self.local(s))
    }

    /// Slot `s` in the mesh's own frame, as doubles.
    #[inline]
    pub(crate) fn local(&self, s: usize) -> P3 {
        if self.slots64.is_empty() {
            widen(&self.slots[s])
        } else {
            self.slots64[s]
        }
    }

    /// The first slot of the caller's vertex `v` (None for a vertex no polygon uses).
    #[inline]
    fn slot_of(&self, v: usize) -> Option<usize> {
        let s = *self.vertex_slot_start.get(v)? as usize;
        (s < *self.vertex_slot_start.get(v + 1)? as usize).then(|| self.vertex_slots[s] as usize)
    }

    /// Replaces the caller's vertices `first..first + src.len()` and refits. Rejected whole
    /// (nothing changes) when the positions' precision is not the mesh's (float positions
    /// for a float mesh, doubles for an f64 mesh: InvalidArgument), the range runs past the
    /// end, or a coordinate is not finite or, for doubles, beyond the float range
    /// (NonFinite). Drops the mesh's target when it succeeds.
    pub fn update_positions(&mut self, first: usize, src: Positions<'_>) -> Result<()> {
        self.check_precision(&src, "update_positions")?;
        let end = self.vertex_range(first, src.len())?;
        let full = first == 0 && end == self.vertex_count();
        if !src.all_finite() {
            let at = src.first_non_finite().unwrap_or(0);
            let v = if full { at } else { first + at };
            return Err(src.non_finite(v, &src.get_f64(at)));
        }
        // Under a placement the new world positions must stay in range: decided before
        // anything changes from a box holding every vertex after the update (the new ones,
        // and for a partial update the old root too). Only when that box is out of range
        // for a partial update is the exact answer needed: then the update is applied,
        // checked and undone if it fails.
        let mut undo = None;
        if let Some(p) = &self.place {
            let mut b = src.bounds();
            if full {
                Placement::check_range(&p.m, &b, "positions")?;
            } else {
                b.merge(&self.leaves.root);
                if Placement::check_range(&p.m, &b, "positions").is_err() {
                    undo = Some(
                        (first..end)
                            .map(|v| self.vertex_position_f64(v))
                            .collect::<Vec<_>>(),
                    );
                }
            }
        }
        self.write_positions(first, &src);
        self.refit_leaves();
        if let Some(p) = &self.place {
            if let Err(e) = Placement::check_range(&p.m, &self.leaves.root, "positions") {
                // Only reached with `undo` set (a full update was checked exactly above).
                for (i, old) in undo.into_iter().flatten().enumerate() {
                    if let Some(old) = old {
                        self.set_vertex(first + i, old);
                    }
                }
                self.refit_leaves();
                return Err(e);
            }
        }
        if let Some(p) = &mut self.place {
            p.refit(&self.leaves);
        }
        self.generation += 1;
        self.target = None;
        Ok(())
    }

    /// All the mesh's positions from where the host keeps them (a GL buffer read back at a
    /// query): [`Mesh::update_positions`], but not the caller's update, so a target stays.
    pub fn refresh_positions(&mut self, src: Positions<'_>) -> Result<()> {
        let target = self.target.take();
        let r = self.update_positions(0, src);
        self.target = target;
        r
    }

    /// The end of the caller's vertex range `first..first + count`, or InvalidArgument when
    /// it runs past the mesh's vertices.
    pub(crate) fn vertex_range(&self, first: usize, count: usize) -> Result<usize> {
        let n = self.vertex_count();
        first.checked_add(count).filter(|&e| e <= n).ok_or_else(|| {
            Error::invalid(format!(
                "first_vertex {first} + vertex_count {count} runs past the mesh's {n} vertices"
            ))
        })
    }

    /// InvalidArgument unless `src` has the mesh's precision (`what`: the call).
    pub(crate) fn check_precision(&self, src: &Positions<'_>, what: &str) -> Result<()> {
        match (self.is_f64(), src.is_f64()) {
            (true, false) => Err(Error::invalid(format!(
                "{what}: the mesh is an f64 mesh (made from double positions): it takes \
                 double positions only (the _f64 call)"
            ))),
            (false, true) => Err(Error::invalid(format!(
                "{what}: the mesh is a float mesh: it takes float positions only (not the \
                 _f64 call)"
            ))),
            _ => Ok(()),
        }
    }

    /// Copies `src` to the caller's vertices `first..` (checked by the caller).
    fn write_positions(&mut self, first: usize, src: &Positions<'_>) {
        let full = first == 0 && src.len() == self.vertex_count();
        if self.is_f64() && full {
            // Slot by slot, as the float gather.
            for ((d, f), &v) in self
                .slots64
                .iter_mut()
                .zip(&mut self.slots)
                .zip(&self.slot_vertex)
            {
                *d = src.get_f64(v as usize);
                *f = d.map(|x| x as f32);
            }
        } else if self.is_f64() {
            for i in 0..src.len() {
                self.set_vertex(first + i, src.get_f64(i));
            }
        } else if full {
            src.gather(&self.slot_vertex, &mut self.slots);
        } else {
            for i in 0..src.len() {
                self.set_vertex_f32(first + i, src.get(i));
            }
        }
    }

    /// Every slot of the caller's vertex `v` becomes `p` (rounded to floats for a float
    /// mesh, whose positions are then floats already).
    fn set_vertex(&mut self, v: usize, p: P3) {
        if self.slots64.is_empty() {
            self.set_vertex_f32(v, p.map(|x| x as f32));
            return;
        }
        for &s in &self.vertex_slots
            [self.vertex_slot_start[v] as usize..self.vertex_slot_start[v + 1] as usize]
        {
            self.slots64[s as usize] = p;
            self.slots[s as usize] = p.map(|x| x as f32);
        }
    }

    /// Every slot of the caller's vertex `v` becomes `p` (a float mesh).
    #[inline]
    fn set_vertex_f32(&mut self, v: usize, p: [f32; 3]) {
        for &s in &self.vertex_slots
            [self.vertex_slot_start[v] as usize..self.vertex_slot_start[v + 1] as usize]
        {
            self.slots[s as usize] = p;
        }
    }

    /// Refits the local leaf boxes to the positions (doubles rounded outward for an f64
    /// mesh).
    fn refit_leaves(&mut self) {
        if self.slots64.is_empty() {
            self.leaves.refit(&self.slots);
        } else {
            self.leaves.refit_f64(&self.slots64);
        }
    }

    /// Refits the leaf boxes to the current positions (what an update does after copying).
    pub fn refit(&mut self) {
        self.refit_leaves();
        if let Some(p) = &mut self.place {
            p.refit(&self.leaves);
        }
    }

    /// Slot indices of leaf-ordered polygon `p`.
    #[inline]
    pub fn poly(&self, p: usize) -> &[u32] {
        &self.polys[p * self.k..(p + 1) * self.k]
    }

    /// World box of leaf-ordered polygon `p` (under a placement or for an f64 mesh: its
    /// world positions' box rounded outward to `f32`).
    #[inline]
    pub fn poly_box(&self, p: usize) -> Aabb {
        let mut b = Aabb::EMPTY;
        match self.needs_cpu() {
            false => {
                for &v in self.poly(p) {
                    b.grow(&self.slots[v as usize]);
                }
            }
            true => {
                let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
                for &v in self.poly(p) {
                    let w = self.world(v as usize);
                    for ((l, h), x) in lo.iter_mut().zip(&mut hi).zip(w) {
                        *l = l.min(x);
                        *h = h.max(x);
                    }
                }
                b.min = lo.map(f32_down);
                b.max = hi.map(f32_up);
            }
        }
        b
    }

    /// The triangles of the caller's polygon `polygon` (as [`Mesh::triangles`]), or `None`
    /// when the mesh has no such polygon.
    pub fn polygon_triangles(&self, polygon: u32, out: &mut [[P3; 3]; 2]) -> Option<usize> {
        let [first, second] = out;
        self.polygon_triangles_into(polygon, [first, second])
    }

    /// [`Mesh::polygon_triangles`] into two separate places (the first triangle, a quad's
    /// second): the contact geometry writes a polygon's first triangle straight into its
    /// lane of a batch.
    #[inline(always)]
    pub fn polygon_triangles_into(&self, polygon: u32, out: [&mut [P3; 3]; 2]) -> Option<usize> {
        let at = *self.poly_leaf.get(polygon as usize)?;
        Some(self.triangles_into(at as usize, out))
    }

    /// The triangles of leaf-ordered polygon `p` at their world positions: one for a
    /// triangle, (v0,v1,v2) and (v0,v2,v3) for a quad. Returns how many were written.
    #[inline]
    pub fn triangles(&self, p: usize, out: &mut [[P3; 3]; 2]) -> usize {
        let [first, second] = out;
        self.triangles_into(p, [first, second])
    }

    /// [`Mesh::triangles`] into two separate places (the first triangle, a quad's second).
    #[inline(always)]
    pub fn triangles_into(&self, p: usize, out: [&mut [P3; 3]; 2]) -> usize {
        let [first, second] = out;
        // The placement looked at once per polygon, not per vertex (the contact geometry
        // reads two polygons a pair through here).
        match (&self.place, self.slots64.is_empty()) {
            (None, true) => self.corners_into(p, |s| widen(&self.slots[s]), first, second),
            (Some(pl), true) => self.corners_into(p, |s| pl.m.apply(&self.slots[s]), first, second),
            (None, false) => self.corners_into(p, |s| self.slots64[s], first, second),
            (Some(pl), false) => {
                self.corners_into(p, |s| pl.m.apply_f64(&self.slots64[s]), first, second)
            }
        }
    }

    /// [`Mesh::triangles_into`] with `world` making slot `s`'s world position.
    #[inline(always)]
    fn corners_into(
        &self,
        p: usize,
        world: impl Fn(usize) -> P3,
        first: &mut [P3; 3],
        second: &mut [P3; 3],
    ) -> usize {
        let w = |v: u32| world(v as usize);
        if self.k == 4 {
            let v: &[u32; 4] = self.polys[p * 4..p * 4 + 4]
                .try_into()
                .expect("four corners");
            *first = [w(v[0]), w(v[1]), w(v[2])];
            *second = [w(v[0]), w(v[2]), w(v[3])];
            2
        } else {
            let v: &[u32; 3] = self.polys[p * 3..p * 3 + 3]
                .try_into()
                .expect("three corners");
            *first = [w(v[0]), w(v[1]), w(v[2])];
            1
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(n: usize) -> (Vec<[f32; 3]>, Vec<u32>) {
        let mut v = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                v.push([i as f32, j as f32, ((i * 7 + j * 3) % 5) as f32 * 0.1]);
            }
        }
        let mut t = Vec::new();
        let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        for j in 0..n {
            for i in 0..n {
                t.extend([
                    id(i, j),
                    id(i + 1, j),
                    id(i + 1, j + 1),
                    id(i, j),
                    id(i + 1, j + 1),
                    id(i, j + 1),
                ]);
            }
        }
        (v, t)
    }

    #[test]
    fn build_and_refit_keep_boxes_fitted() {
        let (v, t) = grid(40);
        let mut m = Mesh::new(Positions::from_points(&v), &t, 3, 64).unwrap();
        m.leaves.assert_well_formed(&m.polys, 3, &m.slots);
        let mut ids = m.poly_ids.clone();
        for (at, &p) in ids.iter().enumerate() {
            assert_eq!(m.poly_leaf[p as usize] as usize, at);
        }
        ids.sort_unstable();
        assert_eq!(ids, (0..t.len() as u32 / 3).collect::<Vec<_>>());
        let moved: Vec<[f32; 3]> = v
            .iter()
            .map(|p| [p[0] * 1.5, p[1] - 3.0, p[2] + p[0].sin()])
            .collect();
        m.update_positions(0, Positions::from_points(&moved))
            .unwrap();
        m.leaves.assert_well_formed(&m.polys, 3, &m.slots);
        // A range update.
        m.update_positions(10, Positions::from_points(&v[10..100]))
            .unwrap();
        assert_eq!(m.vertex_position(10), Some(v[10]));
        assert_eq!(m.vertex_position(100), Some(moved[100]));
        assert_eq!(m.vertex_position(99), Some(v[99]));
        m.leaves.assert_well_formed(&m.polys, 3, &m.slots);
    }

    #[test]
    fn rejected_updates_change_nothing() {
        let (v, t) = grid(8);
        let mut m = Mesh::new(Positions::from_points(&v), &t, 3, 16).unwrap();
        let before = (m.slots.clone(), m.leaves.boxes.clone());
        let mut bad = v.clone();
        bad[17][1] = f32::NAN;
        let e = m
            .update_positions(0, Positions::from_points(&bad))
            .unwrap_err();
        assert_eq!(e.kind, ErrorKind::NonFinite);
        assert!(e.message.contains("vertex 17"));
        let e = m
            .update_positions(3, Positions::from_points(&bad[..20]))
            .unwrap_err();
        assert_eq!(e.kind, ErrorKind::NonFinite);
        assert!(e.message.contains("vertex 20"), "{}", e.message);
        let e = m
            .update_positions(v.len() - 2, Positions::from_points(&v[..3]))
            .unwrap_err();
        assert_eq!(e.kind, ErrorKind::InvalidArgument);
        assert_eq!(before, (m.slots.clone(), m.leaves.boxes.clone()));
    }

    #[test]
    fn unused_vertices_are_checked_too() {
        let (mut v, t) = grid(4);
        v.push([9.0, 9.0, 9.0]); // no polygon uses it
        let mut m = Mesh::new(Positions::from_points(&v), &t, 3, 8).unwrap();
        assert_eq!(m.vertex_count(), v.len());
        assert_eq!(m.vertex_position(v.len() - 1), None);
        let mut bad = v.clone();
        *bad.last_mut().unwrap() = [f32::INFINITY, 0.0, 0.0];
        let e = m
            .update_positions(0, Positions::from_points(&bad))
            .unwrap_err();
        assert_eq!(e.kind, ErrorKind::NonFinite);
        assert!(
            e.message.contains(&format!("vertex {}", v.len() - 1)),
            "{}",
            e.message
        );
        m.update_positions(0, Positions::from_points(&v)).unwrap();
    }

    #[test]
    fn bad_meshes_are_rejected_with_the_argument_named() {
        let (v, t) = grid(2);
        let p = Positions::from_points(&v);
        assert!(Mesh::new(p, &t, 5, 0)
            .unwrap_err()
            .message
            .contains("vertices_per_polygon"));
        let mut t2 = t.clone();
        t2[4] = 999;
        let e = Mesh::new(p, &t2, 3, 0).unwrap_err();
        assert_eq!(e.kind, ErrorKind::IndexOutOfRange);
        assert!(e.message.contains("polygon 1") && e.message.contains("999"));
        assert!(Positions::new(&[0u8; 24], 2, 8).is_err());
        assert!(Positions::new(&[0u8; 23], 2, 0).is_err());
        assert!(Positions::new(&[0u8; 24], usize::MAX, 16).is_err());
    }
}
