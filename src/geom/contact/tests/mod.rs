//! The contact geometry's tests, a file a stage of `contact/` (on the references and
//! helpers of `support.rs`).
//!
//! Every check here is independent of the code under test: exact predicates
//! (`triangles_intersect`, `orient3d`) and double-double (about 106-bit) references built
//! another way (the Minkowski difference's hull for the depth, edge/face incidences for
//! the intersection, brute force over features for distances).
//!
//! * `support.rs`: double-double arithmetic, the references, the test polygons, their
//!   random families and the checks against the references.
//! * `crossing.rs`: two triangles crossing (the fast path, the segment path, the decision,
//!   the AVX2 build against the baseline and the general path).
//! * `cut.rs`: the intersection's ends where rounding could move them (shallow crossings,
//!   placed meshes' nearly coplanar pairs and folded neighbours).
//! * `depth.rs`: the depth against sampled directions, the pair swapped.
//! * `general.rs`: coplanar pairs, degenerate polygons, quads, grids, extreme values.
//! * `band.rs`: pairs apart (closest points, the shortcut and the lanes of the edge
//!   search, band normals).
//! * `exact.rs`: slivers, whose normals need the accurate crosses.
//! * `batch.rs`: many pairs at once (the four lanes, memory not initialized yet).
//! * `heavy.rs`: the benchmarks' heavy case against the references (needs `../shared`).
//! * `bench.rs`: nanoseconds per pair (ignored: `BENCH_SET=band cargo test --release --lib
//!   geom::contact::tests::bench -- --ignored --nocapture`).

mod band;
mod batch;
mod bench;
mod crossing;
mod cut;
mod depth;
mod exact;
mod general;
mod heavy;
mod support;

thread_local! {
    /// This thread's `contact_geometry_many` uses the AVX2 kernel even where the CPU
    /// has AVX-512 (both are tested where it has).
    pub(super) static AVX2_ONLY: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}
