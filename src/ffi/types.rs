//! Types of the C API (`include/glcollide.h` is generated from these).

use std::ffi::c_void;

/// How a call went. Values are ABI: never renumber; new values are appended.
//
// Written out for cbindgen (it does not expand macros). The Rust side derives the rest
// from this enum and the core's error kinds (src/ffi/tables.rs): a variant here needs an
// `ErrorKind` of the same name or a place among the boundary's own statuses there, or the
// crate does not compile.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GlcolStatus {
    /// Success.
    Ok = 0,
    /// A required pointer was NULL.
    NullPointer = 1,
    /// Bad size, stride, count, epsilon, struct_size, enum value ...
    InvalidArgument = 2,
    /// A vertex coordinate is NaN or infinite.
    NonFinite = 3,
    /// A polygon names a vertex that does not exist.
    IndexOutOfRange = 4,
    /// Mesh id not in this scene (destroyed or never made).
    UnknownMesh = 5,
    /// GL backend asked for, but no loader / no current context / missing entry point /
    /// version too low.
    GlUnavailable = 6,
    /// The GL reported an error during our work.
    GlError = 7,
    /// A valid request this build or context cannot do.
    Unsupported = 8,
    /// An allocation failed.
    OutOfMemory = 9,
    /// A bug (a caught panic); the scene is unchanged.
    Internal = 10,
}

/// Which implementation answers a scene's queries. Values are ABI.
//
// Written out for cbindgen. Besides AUTO, each variant is a core `Backend` of the same name
// (src/ffi/tables.rs derives the mapping; a mismatch does not compile).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GlcolBackend {
    /// Best available: GL_COMPUTE on a hardware GL 4.3+ context, CPU when there is no
    /// loader or the renderer is a software one (llvmpipe, softpipe, SwiftShader).
    Auto = 0,
    /// Selection semantics computed on the CPU; needs no GL.
    Cpu = 1,
    /// The paper as published: glRenderMode(GL_SELECT); needs a compatibility-profile (or
    /// <= 3.0) context.
    GlSelect = 2,
    /// The same queries as compute dispatches, the whole query on the GPU with one read-back
    /// of the answer; needs GL 4.3+ core or compatibility.
    GlCompute = 3,
}

/// Loads a GL entry point by name for the context current on the calling thread (like
/// `eglGetProcAddress`, with a user pointer first).
pub type GlcolGetProcAddress = Option<
    unsafe extern "C" fn(user_data: *mut c_void, name: *const std::ffi::c_char) -> *mut c_void,
>;

/// Enum-typed values that come from C are read as plain integers and checked, since a
/// Rust enum holding an unlisted value is undefined behaviour. The header still shows
/// the enum names.
/// cbindgen:ignore
pub mod raw {
    /// A `GlcolStatus` value as C passes it (checked before use).
    pub type GlcolStatus = u32;
    /// A `GlcolBackend` value as C passes it (checked before use).
    pub type GlcolBackend = u32;
}

/// How to make a scene. Fill it with `glcol_scene_desc_init`, then change what you need.
///
/// Growing structs: `struct_size` may be `sizeof(GlcolSceneDesc)` of this header or of an
/// older one (0.1's, which ends before `threads`); the fields an older struct lacks take
/// their defaults and are never read. Any other size: GLCOL_STATUS_INVALID_ARGUMENT.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct GlcolSceneDesc {
    /// `sizeof(GlcolSceneDesc)` (or the size of an older version of it): lets the struct
    /// grow.
    pub struct_size: u32,
    /// Which backend (default GLCOL_BACKEND_AUTO).
    pub backend: raw::GlcolBackend,
    /// NULL: CPU only. Otherwise GL entry points are loaded through it, for the context
    /// current on the calling thread when `glcol_scene_create` runs.
    pub get_proc_address: GlcolGetProcAddress,
    /// Passed back to `get_proc_address`.
    pub user_data: *mut c_void,
    /// Viewing-volume depth in model units (the paper used 0.001). 0 on the CPU backend:
    /// exact intersection of the closed polygons. Default 0. Must be finite and >= 0. The
    /// GL backends raise a smaller epsilon than 2^-20 of the meshes' largest extent (0
    /// included) to that minimum for each query.
    pub epsilon: f32,
    /// Leaf size; 0 (default) = the paper's rule of thumb (100 below 5000 polygons, 450
    /// above).
    pub max_polygons_per_box: u32,
    /// Added in 0.1.1 (0.1.0's struct ends before it). Worker threads for queries: 0
    /// (default) = one per core the process may use, 1 = the calling thread only. `glcol_query_all` shares out its mesh pairs and
    /// self-collision leaf pairs, `glcol_query` its leaf pairs (when the reference and the
    /// meshes near it have 2048 polygons or more). The answer is identical for every count;
    /// workers start once per scene (at its first query that needs them) and sleep between
    /// queries. A 0.1.0 struct (struct_size without this field) gets 0.
    pub threads: u32,
}

/// A mesh to create. Positions and indices are copied; the caller keeps its arrays.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct GlcolMeshDesc {
    /// `sizeof(GlcolMeshDesc)`.
    pub struct_size: u32,
    /// x, y, z per vertex (4-byte aligned). Exactly one of `positions` and `positions_f64`
    /// is non-NULL.
    pub positions: *const f32,
    /// Number of vertices (> 0).
    pub vertex_count: usize,
    /// Bytes from one vertex to the next: 0 (= 12, packed) or a multiple of 4 that is >= 12;
    /// with `positions_f64`, 0 (= 24, packed) or a multiple of 8 that is >= 24.
    pub position_stride: usize,
    /// `vertices_per_polygon` vertex indices per polygon (0-based, < vertex_count).
    pub indices: *const u32,
    /// Number of polygons (> 0).
    pub polygon_count: usize,
    /// 3 (triangles) or 4 (quads: the union of triangles (v0,v1,v2) and (v0,v2,v3)).
    pub vertices_per_polygon: u32,
    /// x, y, z per vertex as doubles (8-byte aligned), instead of `positions`: the mesh is
    /// an f64 mesh, which keeps its positions as doubles and is queried exactly for them.
    /// Added in 0.3: a struct of 0.1's size (without it) makes float meshes.
    pub positions_f64: *const f64,
}

/// Id of a mesh (never 0; unique in the process, so never reused and never valid in
/// another scene).
pub type GlcolMeshId = u32;

/// One colliding polygon pair.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GlcolContact {
    /// Polygon index in the reference mesh.
    pub reference_polygon: u32,
    /// The other mesh.
    pub other_mesh: GlcolMeshId,
    /// Polygon index in `other_mesh`.
    pub other_polygon: u32,
}

/// A triangle mesh read by `glcol_obj_load` (arrays owned by the library until
/// `glcol_obj_free`).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct GlcolObjMesh {
    /// x, y, z per vertex.
    pub positions: *mut f32,
    /// Number of vertices (`positions` holds 3 times as many floats).
    pub vertex_count: usize,
    /// Three 0-based vertex indices per triangle.
    pub indices: *mut u32,
    /// Number of triangles (`indices` holds 3 times as many values).
    pub polygon_count: usize,
    /// Always 3 (larger faces are split into fans).
    pub vertices_per_polygon: u32,
}

/// One colliding polygon pair of `glcol_query_all`: (mesh_a, polygon_a) < (mesh_b,
/// polygon_b), ids comparing first (so mesh_a <= mesh_b, and polygon_a < polygon_b when
/// the two meshes are one: a self-collision pair).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GlcolPair {
    /// The lower mesh id.
    pub mesh_a: GlcolMeshId,
    /// Polygon index in `mesh_a`.
    pub polygon_a: u32,
    /// The higher mesh id, or `mesh_a` for a self-collision pair.
    pub mesh_b: GlcolMeshId,
    /// Polygon index in `mesh_b`.
    pub polygon_b: u32,
}

/// `GlcolContactGeometry::flags`: the closed polygons meet (else they are only within the
/// query's epsilon band).
pub const GLCOL_CONTACT_INTERSECTING: u32 = 1 << 0;

/// `GlcolContactGeometry::flags`: the polygons meet and lie in one plane (then depth is 0
/// and normal is polygon a's normal).
pub const GLCOL_CONTACT_COPLANAR: u32 = 1 << 1;

/// Geometry of one contact or pair (`glcol_query_geometry`). Polygon a is the reference
/// polygon of a `glcol_query` contact, or `polygon_a` of a `glcol_query_all` pair. Computed
/// in double precision, each value then rounded to the nearest float (saturating at
/// +-FLT_MAX, never infinite or NaN).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GlcolContactGeometry {
    /// Intersecting: one end of the intersection of the two polygons (coplanar: of the
    /// overlap's longest extent). Band only: the point of polygon a closest to polygon b.
    pub point_a: [f32; 3],
    /// Intersecting: the other end (equal to point_a when they meet in one point). Band
    /// only: the point of polygon b closest to polygon a.
    pub point_b: [f32; 3],
    /// Unit (within float rounding). Intersecting: moving polygon a by depth * normal
    /// separates the two polygons (the smallest such translation; with a quad, the union
    /// of its triangles, it brings them to touching, and a longer move along normal need
    /// not separate). Band only: from b towards a.
    pub normal: [f32; 3],
    /// Intersecting: >= 0, the length of that smallest separating translation (the
    /// penetration depth). Band only: minus the distance between the polygons.
    pub depth: f32,
    /// GLCOL_CONTACT_* bits.
    pub flags: u32,
}

/// `GlcolImpact::flags`: the pair already meets at t = 0 (its toi is 0). Added in 0.3.
pub const GLCOL_IMPACT_AT_START: u32 = 1 << 0;

/// One pair of `glcol_query_continuous`: two polygons that meet at some time of the step,
/// ordered and sorted as `GlcolPair`s, and when first. Added in 0.3.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GlcolImpact {
    /// The lower mesh id.
    pub mesh_a: GlcolMeshId,
    /// Polygon index in `mesh_a`.
    pub polygon_a: u32,
    /// The higher mesh id, or `mesh_a` for a self-collision pair.
    pub mesh_b: GlcolMeshId,
    /// Polygon index in `mesh_b` (above polygon_a when the meshes are one).
    pub polygon_b: u32,
    /// The earliest time in [0, 1] at which the pair meets, as a certified lower bound:
    /// never later than the exact time, at most 2^-20 earlier; exactly 0 with
    /// GLCOL_IMPACT_AT_START when the pair meets at t = 0.
    pub toi: f64,
    /// GLCOL_IMPACT_* bits.
    pub flags: u32,
}

/// `GlcolImpactGeometry::kind`: the pair meets at t = 0 (GLCOL_IMPACT_AT_START); its
/// crossing geometry is glcol_query_geometry's. Added in 0.3.
pub const GLCOL_FEATURE_NONE: u32 = 0;
/// `GlcolImpactGeometry::kind`: a vertex of polygon a and a triangle of polygon b.
pub const GLCOL_FEATURE_VERTEX_FACE: u32 = 1;
/// `GlcolImpactGeometry::kind`: a triangle of polygon a and a vertex of polygon b.
pub const GLCOL_FEATURE_FACE_VERTEX: u32 = 2;
/// `GlcolImpactGeometry::kind`: an edge of each (a polygon's edges are its triangles').
pub const GLCOL_FEATURE_EDGE_EDGE: u32 = 3;

/// Where a pair of `glcol_query_continuous` meets first (`glcol_query_impact_geometry`).
/// Added in 0.3.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GlcolImpactGeometry {
    /// GLCOL_FEATURE_*: the primitive pair that meets first.
    pub kind: u32,
    /// mesh_a's vertex indices of a's feature: 1 for a vertex, 2 for an edge, 3 for a
    /// triangle; unused entries repeat the last used one.
    pub vertices_a: [u32; 3],
    /// mesh_b's vertex indices of b's feature, likewise.
    pub vertices_b: [u32; 3],
    /// Barycentric weights (each in [0, 1], summing to 1) of the contact point on a's
    /// feature at toi: `point_a = sum of weights_a[k] * p(toi) of vertices_a[k]`; unused
    /// weights 0.
    pub weights_a: [f64; 3],
    /// The same on b's feature.
    pub weights_b: [f64; 3],
    /// Unit, at toi, from b towards a: the triangle's normal turned towards the vertex
    /// (VERTEX_FACE, FACE_VERTEX), the edges' common normal (EDGE_EDGE); 0 for NONE.
    pub normal: [f64; 3],
}
