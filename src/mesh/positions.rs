//! Vertex positions as a caller hands them over: floats or doubles, strided or packed.

use super::check_vertex_count;
use crate::error::{Error, ErrorKind, Result};
use crate::geom::{f32_down, f32_up, Aabb};

/// The largest magnitude a coordinate may have: the float range (`f32::MAX`, about
/// 3.4e38), for double positions as for float ones (whose finite values are all within it).
pub(crate) const MAX_COORDINATE: f64 = f32::MAX as f64;

/// Vertex positions as the caller lays them out: three `f32` per vertex (native endianness),
/// `stride` bytes apart in a byte slice, or tightly packed points; or the same with three
/// `f64` per vertex ([`Positions::new_f64`], [`Positions::from_points_f64`]), which make an
/// f64 mesh. Reading it is safe; the FFI builds the byte form from the caller's pointer.
#[derive(Clone, Copy, Debug)]
pub struct Positions<'a>(Src<'a>);

#[derive(Clone, Copy, Debug)]
enum Src<'a> {
    Bytes {
        bytes: &'a [u8],
        stride: usize,
        count: usize,
    },
    Points(&'a [[f32; 3]]),
    Bytes64 {
        bytes: &'a [u8],
        stride: usize,
        count: usize,
    },
    Points64(&'a [[f64; 3]]),
}

impl<'a> Positions<'a> {
    /// `count` vertices `stride` bytes apart (0 means tightly packed, 12). Fails when the
    /// stride is below 12 or not a multiple of 4, `count` is more than a mesh can have
    /// (2^32 - 1), or `bytes` is too short.
    pub fn new(bytes: &'a [u8], count: usize, stride: usize) -> Result<Positions<'a>> {
        let stride = Self::stride_or_packed(stride);
        Self::check(bytes, count, stride, 4)?;
        Ok(Positions(Src::Bytes {
            bytes,
            stride,
            count,
        }))
    }

    /// `count` vertices of three `f64` each, `stride` bytes apart (0 means tightly packed,
    /// 24): positions for an f64 mesh. Fails when the stride is below 24 or not a multiple
    /// of 8, `count` is more than a mesh can have (2^32 - 1), or `bytes` is too short.
    pub fn new_f64(bytes: &'a [u8], count: usize, stride: usize) -> Result<Positions<'a>> {
        let stride = Self::stride_or_packed_f64(stride);
        Self::check(bytes, count, stride, 8)?;
        Ok(Positions(Src::Bytes64 {
            bytes,
            stride,
            count,
        }))
    }

    /// Checks a strided array of `count` vertices of three `word`-byte values.
    fn check(bytes: &[u8], count: usize, stride: usize, word: usize) -> Result<()> {
        if stride < 3 * word || !stride.is_multiple_of(word) {
            return Err(Error::invalid(format!(
                "position_stride {stride} must be 0 or a multiple of {word} that is at least {}",
                3 * word
            )));
        }
        check_vertex_count(count)?;
        let need = Self::byte_len_of(count, stride, 3 * word).ok_or_else(|| {
            Error::invalid(format!(
                "vertex_count {count} times position_stride {stride} overflows"
            ))
        })?;
        if bytes.len() < need {
            return Err(Error::invalid(format!(
                "{} bytes of positions, {need} needed",
                bytes.len()
            )));
        }
        Ok(())
    }

    /// From tightly packed points.
    pub fn from_points(points: &'a [[f32; 3]]) -> Positions<'a> {
        Positions(Src::Points(points))
    }

    /// From tightly packed double points: positions for an f64 mesh, which keeps them as
    /// doubles and is queried exactly for them.
    pub fn from_points_f64(points: &'a [[f64; 3]]) -> Positions<'a> {
        Positions(Src::Points64(points))
    }

    /// Doubles (an f64 mesh's positions)?
    pub fn is_f64(&self) -> bool {
        matches!(self.0, Src::Bytes64 { .. } | Src::Points64(_))
    }

    /// Bytes of one tightly packed vertex (three `f32`): the stride a stride of 0 means.
    pub(crate) const PACKED_STRIDE: usize = 12;

    /// Bytes of one tightly packed double vertex (three `f64`).
    pub(crate) const PACKED_STRIDE_F64: usize = 24;

    /// A stride as the APIs take it: 0 means tightly packed ([`Self::PACKED_STRIDE`]).
    pub const fn stride_or_packed(stride: usize) -> usize {
        if stride == 0 {
            Self::PACKED_STRIDE
        } else {
            stride
        }
    }

    /// A stride of double positions: 0 means tightly packed (24).
    pub const fn stride_or_packed_f64(stride: usize) -> usize {
        if stride == 0 {
            Self::PACKED_STRIDE_F64
        } else {
            stride
        }
    }

    /// Bytes a strided array of `count` float vertices spans (`None` on overflow).
    pub fn byte_len(count: usize, stride: usize) -> Option<usize> {
        Self::byte_len_of(count, stride, 12)
    }

    fn byte_len_of(count: usize, stride: usize, vertex: usize) -> Option<usize> {
        if count == 0 {
            return Some(0);
        }
        (count - 1).checked_mul(stride)?.checked_add(vertex)
    }

    /// Number of vertices.
    pub fn len(&self) -> usize {
        match self.0 {
            Src::Bytes { count, .. } | Src::Bytes64 { count, .. } => count,
            Src::Points(p) => p.len(),
            Src::Points64(p) => p.len(),
        }
    }

    /// No vertices?
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Vertex `i` as a float (double positions rounded to the nearest float).
    #[inline]
    pub fn get(&self, i: usize) -> [f32; 3] {
        match self.0 {
            Src::Bytes { bytes, stride, .. } => read3(&bytes[i * stride..i * stride + 12]),
            Src::Points(p) => p[i],
            Src::Bytes64 { .. } | Src::Points64(_) => self.get_f64(i).map(|x| x as f32),
        }
    }

    /// Vertex `i` as doubles (float positions widened, exactly).
    #[inline]
    pub fn get_f64(&self, i: usize) -> [f64; 3] {
        match self.0 {
            Src::Bytes64 { bytes, stride, .. } => read3_f64(&bytes[i * stride..i * stride + 24]),
            Src::Points64(p) => p[i],
            Src::Bytes { .. } | Src::Points(_) => self.get(i).map(f64::from),
        }
    }

    /// True when every coordinate is finite and, for doubles, within the float range
    /// ([`MAX_COORDINATE`]) (one streaming pass).
    pub fn all_finite(&self) -> bool {
        let ok = |c: f32| (c.to_bits() & 0x7f80_0000) != 0x7f80_0000;
        match self.0 {
            Src::Bytes {
                bytes,
                stride,
                count,
            } => {
                if stride == 12 {
                    bytes[..count * 12].chunks_exact(4).fold(true, |a, b| {
                        a & ok(f32::from_ne_bytes([b[0], b[1], b[2], b[3]]))
                    })
                } else {
                    (0..count).fold(true, |a, i| {
                        let p = read3(&bytes[i * stride..i * stride + 12]);
                        a & ok(p[0]) & ok(p[1]) & ok(p[2])
                    })
                }
            }
            Src::Points(p) => p.as_flattened().iter().fold(true, |a, &c| a & ok(c)),
            Src::Bytes64 { .. } | Src::Points64(_) => {
                (0..self.len()).fold(true, |a, i| a & in_range(&self.get_f64(i)))
            }
        }
    }

    /// `dst[j] = vertex ids[j]` for every j.
    pub fn gather(&self, ids: &[u32], dst: &mut [[f32; 3]]) {
        match self.0 {
            Src::Bytes { bytes, stride, .. } => {
                for (d, &v) in dst.iter_mut().zip(ids) {
                    let o = v as usize * stride;
                    *d = read3(&bytes[o..o + 12]);
                }
            }
            Src::Points(p) => {
                for (d, &v) in dst.iter_mut().zip(ids) {
                    *d = p[v as usize];
                }
            }
            Src::Bytes64 { .. } | Src::Points64(_) => {
                for (d, &v) in dst.iter_mut().zip(ids) {
                    *d = self.get(v as usize);
                }
            }
        }
    }

    /// Index of the first vertex with a NaN or infinite coordinate (or, for doubles, one
    /// beyond the float range).
    pub fn first_non_finite(&self) -> Option<usize> {
        (0..self.len()).find(|&i| !in_range(&self.get_f64(i)))
    }

    /// The NonFinite error for vertex `v` (numbered as the caller numbers it) of these
    /// positions, holding the bad coordinate `p`.
    pub(crate) fn non_finite(&self, v: usize, p: &[f64; 3]) -> Error {
        let what = if p.iter().all(|c| c.is_finite()) {
            "a coordinate beyond the float range (|x| > 3.4e38)"
        } else {
            "a NaN or infinite coordinate"
        };
        Error::new(
            ErrorKind::NonFinite,
            format!("positions: vertex {v} has {what}"),
        )
    }

    /// A box holding every vertex (rounded outward to floats for doubles).
    pub(crate) fn bounds(&self) -> Aabb {
        let mut b = Aabb::EMPTY;
        if self.is_f64() {
            for i in 0..self.len() {
                grow_f64(&mut b, &self.get_f64(i));
            }
        } else {
            (0..self.len()).for_each(|i| b.grow(&self.get(i)));
        }
        b
    }
}

/// Finite and within the float range?
#[inline]
pub(crate) fn in_range(p: &[f64; 3]) -> bool {
    p.iter().all(|c| c.abs() <= MAX_COORDINATE)
}

/// Grows `b` to hold the double point `p` (rounded outward to floats).
#[inline]
pub(crate) fn grow_f64(b: &mut Aabb, p: &[f64; 3]) {
    for ((lo, hi), &x) in b.min.iter_mut().zip(&mut b.max).zip(p) {
        *lo = lo.min(f32_down(x));
        *hi = hi.max(f32_up(x));
    }
}

#[inline]
fn read3(b: &[u8]) -> [f32; 3] {
    let f = |o: usize| f32::from_ne_bytes([b[o], b[o + 1], b[o + 2], b[o + 3]]);
    [f(0), f(4), f(8)]
}

#[inline]
fn read3_f64(b: &[u8]) -> [f64; 3] {
    let f = |o: usize| f64::from_ne_bytes(b[o..o + 8].try_into().expect("eight bytes"));
    [f(0), f(8), f(16)]
}
