//! One query on the GPU: its plan (worked out on the CPU), the query's buffers sized for
//! its room, the kernels of the five steps dispatched, and the whole run again with more
//! room until the answer fits.

use glow::HasContext;

use super::objects::{allocate, bytes, dispatch, set_f32, set_u32, upload};
use super::results::contacts;
use super::{
    Caps, Compute, BINDING, BOXES, GROUP, HEADER, H_ARGS, H_HALF_DEPTH, H_HITS, H_HITS3, H_HITS4,
    H_L1, H_LIST, H_PAIRS, H_TESTS3, H_TESTS4, H_TOTAL5, L1, LEAF_POLYS, LEAF_RANGE, LISTS, OTHERS,
    PAD_REL, PAIRS, POLYS, POS, RESULT, ROOTS,
};
use crate::backend::{Contact, QueryMeshes, QueryStats};
use crate::error::{Error, ErrorKind, Result};
use crate::geom::sortable_key;
use crate::gpu::{gl_bytes, Gl};

fn too_big() -> Error {
    Error::new(
        ErrorKind::Unsupported,
        "the query needs more GPU buffer room than 32-bit counts can address",
    )
}

/// What a query asks of the kernels, worked out on the CPU before any dispatch.
pub(super) struct Plan {
    /// The reference mesh: arena index, first global leaf, leaves.
    ref_mesh: u32,
    ref_base: u32,
    ref_leaves: u32,
    /// Other meshes of the query.
    n_others: u32,
    /// Per other mesh: first global leaf, leaves, first step-1 thread, arena index.
    others: Vec<u32>,
    /// Step-1 threads: every leaf of the other meshes (below 2^31).
    l1_cap: u32,
    /// (first global polygon, position in the query) per mesh, sorted: maps hits back.
    pub(super) bases: Vec<(u32, u32)>,
    /// (first global leaf, leaves) of the meshes refitted on the GPU (host buffers).
    pub(super) refit: Vec<(u32, u32)>,
    /// Root box keys per mesh of the arena (min xyz, max xyz).
    roots: Vec<u32>,
    /// The half depth asked for, before the GPU raises it.
    h_base: f32,
    /// The result header the kernels start from.
    header: [u32; HEADER],
}

impl Compute {
    /// Steps 1 to 5 on the GPU, one read-back (see the module's documentation).
    pub(super) fn query(
        &mut self,
        gl: &Gl,
        q: &QueryMeshes<'_>,
        out: &mut Vec<Contact>,
        stats: &mut QueryStats,
    ) -> Result<()> {
        let t0 = std::time::Instant::now();
        self.gather_bound(gl, q)?;
        for &(id, _) in q.meshes.iter() {
            if self.bound.contains_key(&id) {
                self.gathered.insert(id);
            }
        }
        let plan = self.plan(q)?;
        let raw = self.run_until_room(gl, &plan)?;
        stats.tests = [
            plan.l1_cap as usize,
            raw[H_L1] as usize * plan.ref_leaves as usize,
            raw[H_TESTS3] as usize,
            raw[H_TESTS4] as usize,
            raw[H_TOTAL5] as usize,
        ];
        stats.hits = [
            raw[H_L1],
            raw[H_PAIRS],
            raw[H_HITS3],
            raw[H_HITS4],
            raw[H_HITS],
        ]
        .map(|x| x as usize);
        contacts(q, &plan, &raw[HEADER..], out);
        stats.nanos[0] = t0.elapsed().as_nanos() as u64;
        Ok(())
    }

    /// The query's plan: the other meshes' leaves, the roots, the half depth.
    fn plan(&self, q: &QueryMeshes<'_>) -> Result<Plan> {
        let reference = &self.slots[&q.meshes[0].0];
        let mut others: Vec<u32> = Vec::with_capacity(4 * q.meshes.len());
        let mut l1_cap = 0u32;
        let mut bases: Vec<(u32, u32)> = Vec::with_capacity(q.meshes.len());
        for (mi, (id, _)) in q.meshes.iter().enumerate() {
            let s = &self.slots[id];
            bases.push((s.poly_base, mi as u32));
            if mi > 0 {
                others.extend([s.leaf_base, s.leaves, l1_cap, s.index]);
                l1_cap = l1_cap
                    .checked_add(s.leaves)
                    .filter(|&n| n < 1 << 31)
                    .ok_or_else(too_big)?;
            }
        }
        bases.sort_unstable();
        // Meshes reading a host buffer are refitted on the GPU, their roots reduced there,
        // and the half depth raised there from the roots; the others' boxes and roots are
        // the CPU's, and so is the half depth when every mesh is on the CPU.
        let refit: Vec<(u32, u32)> = q
            .meshes
            .iter()
            .filter(|(id, _)| self.bound.contains_key(id))
            .map(|(id, _)| (self.slots[id].leaf_base, self.slots[id].leaves))
            .collect();
        let mut roots = vec![0u32; 6 * self.slots.len()];
        for (id, s) in &self.slots {
            let r = &mut roots[6 * s.index as usize..][..6];
            match q.meshes.iter().find(|(i, _)| i == id) {
                Some((_, m)) if !self.bound.contains_key(id) => {
                    let b = m.leaves.root;
                    for (k, key) in r.iter_mut().enumerate() {
                        *key = sortable_key(if k < 3 { b.min[k] } else { b.max[k - 3] });
                    }
                }
                _ => r[..3].fill(u32::MAX), // grown down by the refit
            }
        }
        let h_base = (q.half_depth as f32).max(0.0);
        let mut header = [0u32; HEADER];
        header[H_HALF_DEPTH] = if refit.is_empty() {
            ((q.gl_half_depth() * (1.0 + 1e-6)) as f32).to_bits()
        } else {
            h_base.to_bits()
        };
        Ok(Plan {
            ref_mesh: reference.index,
            ref_base: reference.leaf_base,
            ref_leaves: reference.leaves,
            n_others: q.meshes.len() as u32 - 1,
            others,
            l1_cap,
            bases,
            refit,
            roots,
            h_base,
            header,
        })
    }

    /// Runs the kernels and reads the result back until the buffers hold the whole answer
    /// (each run completes at least one more step: at most 4 runs grow them); the header
    /// and the step-5 hits it counts.
    fn run_until_room(&mut self, gl: &Gl, plan: &Plan) -> Result<Vec<u32>> {
        let mut raw = Vec::new();
        for runs in 1.. {
            let caps = self.caps;
            self.size_buffers(gl, plan.l1_cap)?;
            self.upload_plan(gl, plan);
            self.dispatch_steps(gl, plan, caps);
            self.read_back(gl, caps, &mut raw)?;
            self.check_header(&raw)?;
            // Grow what overflowed; the counters after an overflowed one may be short, so
            // run again until nothing overflows.
            let next = grown(&raw, caps);
            if next == caps {
                break;
            }
            if runs >= 8 {
                return Err(Error::new(
                    ErrorKind::Internal,
                    "the query's buffers still overflow after 8 runs (a bug)",
                ));
            }
            self.caps = next;
        }
        Ok(raw)
    }

    /// Sizes the query's buffers for the room `self.caps` and `l1` step-1 hits. A size
    /// the GL cannot take (past `i32::MAX` bytes or the largest storage block) is refused
    /// before any allocation; an allocation the GL reports failing forgets the sizes and
    /// the room.
    fn size_buffers(&mut self, gl: &Gl, l1: u32) -> Result<()> {
        let c = self.caps;
        if self.sized.is_some_and(|(sc, sl)| sc == c && sl >= l1) {
            return Ok(());
        }
        let l1 = l1.max(self.sized.map_or(0, |(_, l)| l));
        let words = [
            (L1, "step-1 hits", u64::from(l1)),
            (PAIRS, "leaf pairs", 8 * u64::from(c.pairs)),
            (LISTS, "step-3/4 lists", u64::from(c.lists)),
            (RESULT, "contacts", HEADER as u64 + 2 * u64::from(c.hits)),
        ];
        let limit = self.max_block.min(i32::MAX as u64);
        if let Some((_, what, w)) = words.iter().find(|(_, _, w)| 4 * w > limit) {
            self.caps = Caps::default(); // the next query starts from the usual room
            return Err(Error::new(
                ErrorKind::OutOfMemory,
                format!(
                    "the query needs a {} MiB buffer for its {what}; this GL's storage blocks \
                     take at most {} MiB",
                    (4 * w) >> 20,
                    limit >> 20
                ),
            ));
        }
        let g = &gl.gl;
        let b = self.objects().buffers;
        self.sized = None;
        for (k, what, w) in words {
            let size = gl_bytes(w, 4, what)?;
            let usage = if k == RESULT {
                glow::DYNAMIC_READ
            } else {
                glow::DYNAMIC_COPY
            };
            // SAFETY: as in `rebuild`; the size is checked against the GL's limits above.
            unsafe { allocate(g, b[k], size, usage) };
        }
        if let Err(e) = gl.check_alloc("allocating the query's buffers") {
            self.caps = Caps::default();
            return Err(e);
        }
        self.sized = Some((c, l1));
        Ok(())
    }

    /// Uploads what the plan computed (other meshes, roots, the header) and binds every
    /// buffer the kernels use (the guard gave the host its bindings back after the last
    /// call).
    fn upload_plan(&self, gl: &Gl, plan: &Plan) {
        let g = &gl.gl;
        let b = &self.objects().buffers;
        // SAFETY: as in `rebuild`; the header fits the result buffer (sized for it and the
        // hits).
        unsafe {
            upload(g, b[OTHERS], bytes(&plan.others));
            upload(g, b[ROOTS], bytes(&plan.roots));
            g.bind_buffer(glow::SHADER_STORAGE_BUFFER, Some(b[RESULT]));
            g.buffer_sub_data_u8_slice(glow::SHADER_STORAGE_BUFFER, 0, bytes(&plan.header));
            for k in [
                POS, POLYS, BOXES, LEAF_RANGE, LEAF_POLYS, OTHERS, L1, PAIRS, LISTS, RESULT, ROOTS,
            ] {
                g.bind_buffer_base(glow::SHADER_STORAGE_BUFFER, BINDING[k], Some(b[k]));
            }
            g.bind_buffer(glow::DISPATCH_INDIRECT_BUFFER, Some(b[RESULT]));
        }
    }

    /// The kernels, in order: refit of the host-buffer meshes (and their half depth),
    /// step 1, then for steps 2, 3-4 and 5: one workgroup sizes the step, the step runs
    /// (dispatched indirectly with those sizes).
    fn dispatch_steps(&self, gl: &Gl, plan: &Plan, caps: Caps) {
        let g = &gl.gl;
        let k = self.objects().query;
        let storage = glow::SHADER_STORAGE_BARRIER_BIT;
        let command = storage | glow::COMMAND_BARRIER_BIT;
        // SAFETY: as in `rebuild`; the programs are ours, their buffers bound by
        // `upload_plan`, the indirect sizes written by the sizes kernel into the bound
        // result buffer (workgroup counts of at most 65535 a side).
        unsafe {
            if !plan.refit.is_empty() {
                use_kernel(g, k.refit, plan, caps);
                for &(first, leaves) in &plan.refit {
                    set_u32(g, k.refit, "u_first_leaf", first);
                    dispatch(g, k.refit, leaves);
                }
                g.memory_barrier(storage);
                use_kernel(g, k.sizes, plan, caps);
                set_u32(g, k.sizes, "u_src", 3); // the half depth from the refitted roots
                dispatch(g, k.sizes, GROUP);
                g.memory_barrier(storage);
            }
            use_kernel(g, k.step1, plan, caps);
            dispatch(g, k.step1, plan.l1_cap);
            g.memory_barrier(storage);
            for (src, (step, args)) in [k.step2, k.step34, k.step5]
                .into_iter()
                .zip(H_ARGS)
                .enumerate()
            {
                use_kernel(g, k.sizes, plan, caps);
                set_u32(g, k.sizes, "u_src", src as u32);
                dispatch(g, k.sizes, GROUP);
                g.memory_barrier(command);
                use_kernel(g, step, plan, caps);
                g.dispatch_compute_indirect(4 * args as i32);
                g.memory_barrier(storage);
            }
            g.memory_barrier(glow::BUFFER_UPDATE_BARRIER_BIT);
        }
    }
}

/// Makes `p` the program in use and sets the uniforms every query kernel shares.
///
/// # Safety
/// `g` was loaded for the context current on this thread; `p` is one of our kernels.
unsafe fn use_kernel(g: &glow::Context, p: glow::NativeProgram, plan: &Plan, caps: Caps) {
    // SAFETY: the caller's contract.
    unsafe {
        g.use_program(Some(p));
        for (name, v) in [
            ("u_ref_mesh", plan.ref_mesh),
            ("u_ref_leaf_base", plan.ref_base),
            ("u_ref_leaves", plan.ref_leaves),
            ("u_others", plan.n_others),
            ("u_l1_cap", plan.l1_cap),
            ("u_pair_cap", caps.pairs),
            ("u_list_cap", caps.lists),
            ("u_hit_cap", caps.hits),
        ] {
            set_u32(g, p, name, v);
        }
        set_f32(g, p, "u_pad_rel", PAD_REL);
        set_f32(g, p, "u_h_base", plan.h_base);
    }
}

/// The room the next run needs: each counter that passed its room grows to fit it.
fn grown(raw: &[u32], caps: Caps) -> Caps {
    let grow = |need: u32, cap: u32| {
        if need > cap {
            need.saturating_add(need / 2).max(cap.saturating_mul(2))
        } else {
            cap
        }
    };
    Caps {
        pairs: grow(raw[H_PAIRS], caps.pairs),
        lists: grow(raw[H_LIST], caps.lists),
        hits: grow(raw[H_HITS], caps.hits),
    }
}
