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

/// Reads a caller's struct: `struct_size` (its first field) first, since the rest may not
/// be there, then, if it is one of `sizes` (this library's `size_of::<T>()` first, then the
/// sizes of older versions, each a prefix of `T`), that many bytes over `defaults`: the
/// fields an older struct lacks keep their defaults and nothing past `struct_size` is read.
///
/// # Safety
/// `p` is non-null and aligned (checked by the caller), and points to readable memory of
/// at least 4 bytes, and of as many bytes as its first 4 bytes say when that is one of
/// `sizes`. Every size in `sizes` ends at a field boundary of `T`, and the bytes of those
/// fields, as C initialised them, are valid values of the fields' types.
pub(super) unsafe fn read_desc<T: Copy>(
    p: *const T,
    struct_size: *const u32,
    what: &str,
    sizes: &[(usize, &str)],
    defaults: T,
) -> Result<T, Fail> {
    // SAFETY: `struct_size` is the first field of `*p` (offset 0, so in bounds and aligned
    // as `p` is): an aligned read of the 4 bytes every version of the struct has.
    let got = unsafe { struct_size.read() };
    let n = check_struct_size(got, sizes, what)?;
    debug_assert!(n <= std::mem::size_of::<T>());
    let mut out = defaults;
    // SAFETY: the caller's struct holds `n` readable bytes (its struct_size says so and `n`
    // is one of `sizes`); `out` is a distinct local `T` of at least `n` bytes; the first
    // `n` bytes are whole fields of `T` (the caller's contract), so `out` stays valid.
    unsafe { std::ptr::copy_nonoverlapping(p.cast::<u8>(), std::ptr::addr_of_mut!(out).cast(), n) };
    Ok(out)
}

/// Checks a caller struct's `struct_size` (the first field) against the sizes we know
/// (`sizes[0]` this version's; each with a note saying which version it is); returns it.
fn check_struct_size(got: u32, sizes: &[(usize, &str)], what: &str) -> Result<usize, Fail> {
    if let Some(&(n, _)) = sizes.iter().find(|&&(n, _)| n == got as usize) {
        return Ok(n);
    }
    let want = sizes
        .iter()
        .map(|&(n, note)| format!("{n} ({note})"))
        .collect::<Vec<_>>()
        .join(" or ");
    Err(invalid(format!(
        "{what}.struct_size is {got}, expected {want}; call the _init function or set it"
    )))
}

/// `GlcolSceneDesc` sizes accepted: this version's, and 0.1's (which ends before `threads`).
pub(super) const SCENE_DESC_SIZES: [(usize, &str); 2] = [
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
pub(super) const MESH_DESC_SIZES: [(usize, &str); 2] = [
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
pub(super) fn scene_desc_defaults() -> GlcolSceneDesc {
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
pub(super) fn mesh_desc_defaults() -> GlcolMeshDesc {
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

/// `Positions` over the caller's array after every check that can be made.
///
/// # Safety
/// `p` is NULL or readable for `count` vertices `stride` bytes apart (0 = 12) for `'a`.
pub(super) unsafe fn positions<'a>(
    p: *const f32,
    count: usize,
    stride: usize,
) -> Result<Positions<'a>, Fail> {
    non_null(p, "positions")?;
    if count == 0 {
        return Err(invalid("vertex_count is 0"));
    }
    if !(p as usize).is_multiple_of(std::mem::align_of::<f32>()) {
        return Err(invalid("positions is not 4-byte aligned"));
    }
    let s = Positions::stride_or_packed(stride);
    let len = Positions::byte_len(count, s)
        .filter(|&n| n <= isize::MAX as usize)
        .ok_or_else(|| {
            invalid(format!(
                "vertex_count {count} times position_stride {stride} overflows"
            ))
        })?;
    // The stride itself (>= 12, multiple of 4) is checked by Positions::new.
    let bytes = if s >= 12 {
        // SAFETY: non-null and aligned (checked), `len` <= isize::MAX (checked), and the
        // caller's contract: `count` vertices `s` apart, `len` bytes, are readable for 'a.
        unsafe { std::slice::from_raw_parts(p.cast::<u8>(), len) }
    } else {
        &[]
    };
    Ok(Positions::new(bytes, count, stride)?)
}

/// `Positions` over the caller's double array after every check that can be made (an f64
/// mesh's positions; stride 0 = 24).
///
/// # Safety
/// `p` is NULL or readable for `count` vertices `stride` bytes apart (0 = 24) for `'a`.
pub(super) unsafe fn positions_f64<'a>(
    p: *const f64,
    count: usize,
    stride: usize,
) -> Result<Positions<'a>, Fail> {
    non_null(p, "positions")?;
    if count == 0 {
        return Err(invalid("vertex_count is 0"));
    }
    aligned(p, "positions")?;
    let s = Positions::stride_or_packed_f64(stride);
    let len = Positions::byte_len_f64(count, s)
        .filter(|&n| n <= isize::MAX as usize)
        .ok_or_else(|| {
            invalid(format!(
                "vertex_count {count} times position_stride {stride} overflows"
            ))
        })?;
    // The stride itself (>= 24, multiple of 8) is checked by Positions::new_f64.
    let bytes = if s >= 24 {
        // SAFETY: non-null and aligned (checked), `len` <= isize::MAX (checked), and the
        // caller's contract: `count` vertices `s` apart, `len` bytes, are readable for 'a.
        unsafe { std::slice::from_raw_parts(p.cast::<u8>(), len) }
    } else {
        &[]
    };
    Ok(Positions::new_f64(bytes, count, stride)?)
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
