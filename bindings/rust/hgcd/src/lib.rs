//! Safe Rust bindings to hgcd: exact collision detection between many rigid
//! triangle meshes (a C library with a C ABI; raw bindings in [`sys`]).
//!
//! A [`World`] holds meshes (shared shapes) and bodies (placed instances of a
//! mesh). Each [`World::detect`] (or [`World::step`], which moves the bodies
//! first) finds every pair of bodies whose closed solids share a point,
//! exactly; [`World::pairs`] borrows the result.
//!
//! ```
//! use hgcd::{BodyDesc, MeshDesc, World, WorldDesc};
//!
//! let mut world = World::new(&WorldDesc::default())?;
//! let (vertices, triangles) = hgcd::scene::unit_mesh();
//! let tetra = world.create_mesh(&MeshDesc::new(&vertices, &triangles))?;
//! let a = world.create_body(&BodyDesc::new(tetra))?;
//! let b = world.create_body(&BodyDesc { position: [1.0, 0.0, 0.0], ..BodyDesc::new(tetra) })?;
//! let _far = world.create_body(&BodyDesc { position: [10.0, 0.0, 0.0], ..BodyDesc::new(tetra) })?;
//! world.detect()?;
//! assert_eq!(world.pairs(), &[hgcd::Pair { a, b }]);
//!
//! // Errors carry the library's status and message.
//! let err = world.set_pose(a, [f64::NAN, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]).unwrap_err();
//! assert_eq!(err.kind(), hgcd::ErrorKind::InvalidArgument);
//! # Ok::<(), hgcd::Error>(())
//! ```
//!
//! Threading: [`World`] is `Send` but not `Sync`; see its documentation.

mod error;
mod filter;
pub mod scene;
mod types;
mod world;

pub use hgcd_sys as sys;

pub use error::{Error, ErrorKind, Result};
pub use filter::{BodyType, Filter};
pub use types::{
    BodyDesc, BodyId, Contact, ContactKind, MeshDesc, MeshId, MeshInfo, NarrowPhase, Pair, Pose,
    Stats, ThreadPolicy, WorldDesc,
};
pub use world::{MeshPose, PairEvent, QueryResults, Ray, RayHit, RayMode, World};

/// The run-time library version (major, minor, patch) (`hgcd_version`).
pub fn version() -> (u32, u32, u32) {
    // SAFETY: no arguments.
    let v = unsafe { sys::hgcd_version() };
    (v >> 16, (v >> 8) & 0xff, v & 0xff)
}

/// The run-time library version as a string, "0.1.0" (`hgcd_version_string`).
pub fn version_string() -> &'static str {
    // SAFETY: a static NUL-terminated string (header contract).
    unsafe {
        let p = sys::hgcd_version_string();
        if p.is_null() {
            return "";
        }
        std::ffi::CStr::from_ptr(p).to_str().unwrap_or("")
    }
}

/// libccd compiled into the library (`hgcd_feature_libccd`): 0 none (GJK and
/// MPR are `NotSupported`), 1 single precision, 2 double precision.
pub fn libccd_precision() -> i32 {
    // SAFETY: no arguments.
    unsafe { sys::hgcd_feature_libccd() }
}

/// The version of the header these bindings were generated from.
pub const HEADER_VERSION: (u32, u32, u32) = (
    sys::HGCD_VERSION_MAJOR,
    sys::HGCD_VERSION_MINOR,
    sys::HGCD_VERSION_PATCH,
);
