//! Reading what the caller hands over: structs led by `struct_size` (older, shorter
//! versions accepted), position arrays with a stride, and writing arrays to out-parameters.
//! Every check that can be made on a pointer is made here, before anything is read.

use super::guard::{invalid, non_null, Fail, FfiResult};
use super::types::*;
use crate::{Error, Positions};

/// `Err(INVALID_ARGUMENT)` naming `what` when `p` is not aligned for `T` (C guarantees it
/// for a pointer to a `T`; a misaligned one is refused before anything is read).
pub(super) fn aligned<T>(p: *const T, what: &str) -> FfiResult {
    if p.is_aligned() {
        Ok(())
    } else {
        Err(invalid(format!(
            "{what} is not {}-byte aligned",
            std::mem::align_of::<T>()
        )))
    }
}

/// A caller's struct led by `struct_size` (offset 0), in versions that grow by appended
/// fields: `GlcolSceneDesc` and `GlcolMeshDesc`.
pub(super) trait Desc: Copy {
    /// Its C name, for messages.
    const NAME: &'static str;
    /// The sizes accepted: this version's first, then older versions' (each with a note
    /// saying which), each a prefix of whole fields.
    const SIZES: &'static [(usize, &'static str)];
    /// What the `_init` functions write, `struct_size` aside.
    fn defaults() -> Self;
    /// Sets `struct_size`.
    fn set_size(&mut self, n: u32);
}

impl Desc for GlcolSceneDesc {
    const NAME: &'static str = "GlcolSceneDesc";
    const SIZES: &'static [(usize, &'static str)] = &SCENE_DESC_SIZES;
    fn defaults() -> Self {
        scene_desc_defaults()
    }
    fn set_size(&mut self, n: u32) {
        self.struct_size = n;
    }
}

impl Desc for GlcolMeshDesc {
    const NAME: &'static str = "GlcolMeshDesc";
    const SIZES: &'static [(usize, &'static str)] = &MESH_DESC_SIZES;
    fn defaults() -> Self {
        mesh_desc_defaults()
    }
    fn set_size(&mut self, n: u32) {
        self.struct_size = n;
    }
}

// `read_desc` reads `struct_size` at offset 0.
const _: () = assert!(std::mem::offset_of!(GlcolSceneDesc, struct_size) == 0);
const _: () = assert!(std::mem::offset_of!(GlcolMeshDesc, struct_size) == 0);

/// Reads a caller's struct (non-null, checked by the caller): INVALID_ARGUMENT when it is
/// misaligned; then `struct_size` (its first field) first, since the rest may not be there;
/// then, if it is one of `T::SIZES`, that many bytes over `T`'s defaults: the fields an older
/// struct lacks keep their defaults and nothing past `struct_size` is read.
///
/// # Safety
/// `p` is non-null and points to readable memory of at least 4 bytes, and of as many bytes
/// as its first 4 bytes say when that is one of `T::SIZES`. The bytes of those fields, as C
/// initialised them, are valid values of the fields' types.
pub(super) unsafe fn read_desc<T: Desc>(p: *const T) -> Result<T, Fail> {
    aligned(p, "desc")?;
    // SAFETY: `struct_size` is the first field of `*p` (offset 0, asserted above; so in
    // bounds and aligned as `p` is): an aligned read of the 4 bytes every version has.
    let got = unsafe { p.cast::<u32>().read() };
    let n = check_struct_size(got, T::SIZES, T::NAME)?;
    debug_assert!(n <= std::mem::size_of::<T>());
    let mut out = T::defaults();
    // SAFETY: the caller's struct holds `n` readable bytes (its struct_size says so and `n`
    // is one of `T::SIZES`); `out` is a distinct local `T` of at least `n` bytes; the first
    // `n` bytes are whole fields of `T`, so `out` stays valid.
    unsafe { std::ptr::copy_nonoverlapping(p.cast::<u8>(), std::ptr::addr_of_mut!(out).cast(), n) };
    Ok(out)
}

/// Checks a caller struct's `struct_size` (the first field) against the sizes we know
/// (`sizes[0]` this version's; each with a note saying which version it is); returns it.
fn check_struct_size(got: u32, sizes: &[(usize, &str)], what: &str) -> Result<usize, Fail> {
    if let Some(&(n, _)) = sizes.iter().find(|&&(n, _)| n == got as usize) {
        return Ok(n);
    }
    Err(invalid(format!(
        "{what}.struct_size is {got}, expected {}; call the _init function or set it",
        wanted(sizes)
    )))
}

/// The sizes accepted, for a message: "56 (this) or 48 (0.1's)".
fn wanted(sizes: &[(usize, &str)]) -> String {
    sizes
        .iter()
        .map(|&(n, note)| format!("{n} ({note})"))
        .collect::<Vec<_>>()
        .join(" or ")
}

/// The `_init_sized` functions: `T`'s defaults (with `struct_size` set to `size`) written as
/// a struct of `size` bytes, which must be one of `T::SIZES` (else INVALID_ARGUMENT naming
/// them, nothing written). Nothing past `size` bytes is written.
///
/// # Safety
/// `desc` is NULL or points to writable memory of `size` bytes.
pub(super) unsafe fn init_sized<T: Desc>(desc: *mut T, size: usize) -> FfiResult {
    non_null(desc, "desc")?;
    aligned(desc, "desc")?;
    let Some(&(n, _)) = T::SIZES.iter().find(|&&(n, _)| n == size) else {
        return Err(invalid(format!(
            "size is {size}, expected {}: pass sizeof({})",
            wanted(T::SIZES),
            T::NAME
        )));
    };
    let mut defaults = T::defaults();
    defaults.set_size(n as u32);
    // SAFETY: non-null and aligned (checked); the caller's contract: `size` == `n` writable
    // bytes; `n` is one of `T::SIZES`, a prefix of whole fields of `defaults` (a local).
    unsafe {
        std::ptr::copy_nonoverlapping(std::ptr::addr_of!(defaults).cast::<u8>(), desc.cast(), n)
    };
    Ok(())
}

/// The size of `T` in the oldest version (0.1): what the exported `_init` symbols fill.
pub(super) fn oldest_size<T: Desc>() -> usize {
    T::SIZES[T::SIZES.len() - 1].0
}

/// `GlcolSceneDesc` sizes accepted: this version's, and 0.1's (which ends before `threads`).
const SCENE_DESC_SIZES: [(usize, &str); 2] = [
    (
        std::mem::size_of::<GlcolSceneDesc>(),
        "sizeof(GlcolSceneDesc) of this glcollide",
    ),
    (
        std::mem::offset_of!(GlcolSceneDesc, threads),
        "glcollide 0.1's, without threads",
    ),
];

/// `GlcolMeshDesc` sizes accepted: this version's, and 0.1's (which ends before
/// `positions_f64`).
const MESH_DESC_SIZES: [(usize, &str); 2] = [
    (
        std::mem::size_of::<GlcolMeshDesc>(),
        "sizeof(GlcolMeshDesc) of this glcollide",
    ),
    (
        std::mem::offset_of!(GlcolMeshDesc, positions_f64),
        "glcollide 0.1's, without positions_f64",
    ),
];

/// The defaults `glcol_scene_desc_init` writes.
fn scene_desc_defaults() -> GlcolSceneDesc {
    GlcolSceneDesc {
        struct_size: std::mem::size_of::<GlcolSceneDesc>() as u32,
        backend: GlcolBackend::Auto as u32,
        get_proc_address: None,
        user_data: std::ptr::null_mut(),
        epsilon: 0.0,
        max_polygons_per_box: 0,
        threads: 0,
    }
}

/// The defaults `glcol_mesh_desc_init` writes.
fn mesh_desc_defaults() -> GlcolMeshDesc {
    GlcolMeshDesc {
        struct_size: std::mem::size_of::<GlcolMeshDesc>() as u32,
        positions: std::ptr::null(),
        vertex_count: 0,
        position_stride: 0,
        indices: std::ptr::null(),
        polygon_count: 0,
        vertices_per_polygon: 3,
        positions_f64: std::ptr::null(),
    }
}

/// A coordinate of a caller's position array: `f32` (float meshes) or `f64` (f64 meshes).
pub(super) trait Coordinate: Sized {
    /// Doubles?
    const F64: bool;
    /// `Positions` of `count` vertices of three of these, `stride` bytes apart (0: packed).
    fn over(bytes: &[u8], count: usize, stride: usize) -> crate::Result<Positions<'_>>;
}

impl Coordinate for f32 {
    const F64: bool = false;
    fn over(bytes: &[u8], count: usize, stride: usize) -> crate::Result<Positions<'_>> {
        Positions::new(bytes, count, stride)
    }
}

impl Coordinate for f64 {
    const F64: bool = true;
    fn over(bytes: &[u8], count: usize, stride: usize) -> crate::Result<Positions<'_>> {
        Positions::new_f64(bytes, count, stride)
    }
}

/// `Positions` over the caller's array of floats or doubles after every check that can be
/// made (stride 0: packed, 12 or 24 bytes).
///
/// # Safety
/// `p` is NULL or readable for `count` vertices `stride` bytes apart (0 = packed) for `'a`.
pub(super) unsafe fn positions<'a, T: Coordinate>(
    p: *const T,
    count: usize,
    stride: usize,
) -> Result<Positions<'a>, Fail> {
    non_null(p, "positions")?;
    if count == 0 {
        return Err(invalid("vertex_count is 0"));
    }
    aligned(p, "positions")?;
    let vertex = 3 * std::mem::size_of::<T>();
    let s = if stride == 0 { vertex } else { stride };
    let len = (count - 1)
        .checked_mul(s)
        .and_then(|n| n.checked_add(vertex))
        .filter(|&n| n <= isize::MAX as usize)
        .ok_or_else(|| {
            invalid(format!(
                "vertex_count {count} times position_stride {stride} overflows"
            ))
        })?;
    // The stride itself (at least a vertex, a multiple of a coordinate) is checked by
    // Positions.
    let bytes = if s >= vertex {
        // SAFETY: non-null and aligned (checked), `len` <= isize::MAX (checked), and the
        // caller's contract: `count` vertices `s` apart, `len` bytes, are readable for 'a.
        unsafe { std::slice::from_raw_parts(p.cast::<u8>(), len) }
    } else {
        &[]
    };
    Ok(T::over(bytes, count, stride)?)
}

/// Writes `v`'s first element (NULL when empty) and length to the out-parameters.
///
/// # Safety
/// Both pointers are non-null, writable and aligned.
pub(super) unsafe fn write_array<T>(v: &[T], out: *mut *const T, out_count: *mut usize) {
    let first = if v.is_empty() {
        std::ptr::null()
    } else {
        v.as_ptr()
    };
    // SAFETY: the caller's contract: both non-null, writable and aligned.
    unsafe {
        out.write(first);
        out_count.write(v.len());
    }
}

/// Reserves room for `additional` more items in `v`: a failed allocation is
/// OUT_OF_MEMORY naming `what` (where `Vec`'s own growth would abort the process).
pub(super) fn try_reserve<T>(v: &mut Vec<T>, additional: usize, what: &str) -> FfiResult {
    v.try_reserve(additional)
        .map_err(|e| Error::out_of_memory(what, e).into())
}
