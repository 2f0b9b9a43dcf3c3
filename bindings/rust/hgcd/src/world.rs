//! `World`: the owned `hgcd_world*` (its batch calls in world/batch.rs).

mod batch;
mod events;
mod filter;
mod query;

pub use events::PairEvent;
pub use query::{MeshPose, QueryResults, Ray, RayHit, RayMode};

use std::ffi::CStr;
use std::fmt;
use std::mem::size_of;
use std::ptr::{self, NonNull};

use hgcd_sys as sys;

use crate::error::{Error, ErrorKind, Result};
use crate::types::{
    BodyDesc, BodyId, Contact, MeshDesc, MeshId, MeshInfo, NarrowPhase, Pair, Pose, Stats,
    ThreadPolicy, WorldDesc,
};

/// A collision world: meshes, bodies placed from them, and the pairs of the
/// last tick. Owns its `hgcd_world*` and frees it on drop.
///
/// # Threading
///
/// The C contract (hgcd.h, "Threading"): one world is used by one thread at a
/// time; separate worlds are fully independent; calls taking a
/// `const hgcd_world*` may overlap with each other but not with a call that
/// changes the world. The library keeps no per-thread state for a world
/// (inside step/detect it runs its own OpenMP regions and changes no global
/// OpenMP setting), so a world may be handed from one thread to another:
///
/// * `World` is [`Send`]: moving it moves the only handle, so afterwards just
///   one thread uses it, which is exactly "one thread at a time".
/// * `World` is **not** [`Sync`]. Sharing `&World` across threads would let
///   read-only calls overlap, which C allows, but the gain is small and the
///   argument would rest on every `&self` method mapping to a `const` C call
///   forever; keeping `World` `!Sync` makes soundness follow from the borrow
///   checker alone: `&mut self` methods (every C call that changes the world)
///   are exclusive, and `&self` methods never run concurrently with anything.
///   (`NonNull` is already `!Sync`; no `impl Sync` is written.) Wrap it in a
///   `Mutex` to share it.
///
/// ```compile_fail,E0277
/// fn needs_sync<T: Sync>() {}
/// needs_sync::<hgcd::World>(); // error: `World` is not `Sync`
/// ```
///
/// ```
/// fn needs_send<T: Send>() {}
/// needs_send::<hgcd::World>();
/// ```
///
/// # Pairs borrow the world
///
/// [`World::pairs`] returns the library's own array, valid until the next call
/// that changes the world. Those calls take `&mut self`, so the borrow checker
/// refuses any use of the slice after them:
///
/// ```compile_fail,E0502
/// let mut world = hgcd::World::new(&hgcd::WorldDesc::default()).unwrap();
/// world.detect().unwrap();
/// let pairs = world.pairs();
/// world.step().unwrap(); // error: `world` is borrowed by `pairs`
/// println!("{}", pairs.len());
/// ```
///
/// ```compile_fail,E0502
/// # let mut world = hgcd::World::new(&hgcd::WorldDesc::default()).unwrap();
/// let pairs = world.pairs();
/// world.destroy_body(pairs[0].a).unwrap(); // error: still borrowed
/// println!("{:?}", pairs[0]);
/// ```
///
/// ```compile_fail,E0505
/// # let mut world = hgcd::World::new(&hgcd::WorldDesc::default()).unwrap();
/// let pairs = world.pairs();
/// drop(world); // error: cannot move out of `world` while borrowed
/// println!("{}", pairs.len());
/// ```
///
/// Copy what must outlive the next change: `world.pairs().to_vec()`.
///
/// ```
/// # let mut world = hgcd::World::new(&hgcd::WorldDesc::default()).unwrap();
/// world.detect().unwrap();
/// let before = world.pairs().to_vec();
/// world.step().unwrap();
/// println!("{} then {}", before.len(), world.pairs().len());
/// ```
pub struct World {
    raw: NonNull<sys::hgcd_world>,
}

// SAFETY: see "Threading" above: hgcd worlds have no thread affinity and the
// C contract allows one thread at a time, which ownership transfer preserves.
unsafe impl Send for World {}

impl World {
    /// Creates a world (`hgcd_world_create`).
    pub fn new(desc: &WorldDesc) -> Result<World> {
        let raw_desc = desc.to_raw();
        let mut raw: *mut sys::hgcd_world = ptr::null_mut();
        // SAFETY: both pointers are valid for the call.
        let status = unsafe { sys::hgcd_world_create(&raw_desc, &mut raw) };
        if status != sys::HGCD_OK {
            // There is no world to hold a message: say what can be said.
            let message = if status == sys::HGCD_ERROR_INVALID_ARGUMENT {
                "world_create: a descriptor value is out of range (non-finite or negative \
                 time_step, bounds_min >= bounds_max, bad cell sizes, too many threads, \
                 unknown narrow_phase)"
            } else if status == sys::HGCD_ERROR_NOT_SUPPORTED {
                "world_create: narrow_phase GJK or MPR, but not built with libccd"
            } else {
                "world_create"
            };
            return Err(Error::from_status(status, message));
        }
        match NonNull::new(raw) {
            Some(raw) => Ok(World { raw }),
            None => Err(Error::new(
                ErrorKind::Internal,
                "world_create returned OK and a NULL world",
            )),
        }
    }

    /// Takes ownership of a world made by `hgcd_world_create`.
    ///
    /// # Safety
    /// `raw` must be a live world from `hgcd_world_create` that nothing else
    /// uses or frees afterwards.
    pub unsafe fn from_raw(raw: NonNull<sys::hgcd_world>) -> World {
        World { raw }
    }

    /// Gives up ownership: the caller must free it with `hgcd_world_destroy`.
    pub fn into_raw(self) -> NonNull<sys::hgcd_world> {
        let raw = self.raw;
        std::mem::forget(self);
        raw
    }

    /// The handle, for read-only (`const hgcd_world*`) C calls.
    pub fn as_ptr(&self) -> *const sys::hgcd_world {
        self.raw.as_ptr()
    }

    /// The handle, for any C call (the pairs borrowed from this world must be
    /// considered invalidated by a changing call).
    pub fn as_mut_ptr(&mut self) -> *mut sys::hgcd_world {
        self.raw.as_ptr()
    }

    /// Turns the status of a call that takes a non-const world into a
    /// `Result`, with the library's message for a failure.
    fn check(&mut self, status: sys::hgcd_status) -> Result<()> {
        if status == sys::HGCD_OK {
            Ok(())
        } else {
            Err(Error::from_status(status, self.last_error()))
        }
    }

    /// The same for calls taking a const world: they record no message.
    fn check_const(status: sys::hgcd_status, what: impl FnOnce() -> String) -> Result<()> {
        if status == sys::HGCD_OK {
            Ok(())
        } else {
            Err(Error::from_status(status, what()))
        }
    }

    /// The message of the last failed changing call on this world
    /// (`hgcd_world_last_error`), or "" if none failed yet. Errors returned by
    /// this crate already carry it.
    pub fn last_error(&self) -> String {
        // SAFETY: the world is live; the string is owned by it and valid
        // until the next changing call, which cannot happen while `&self`
        // is borrowed. It is copied out at once.
        unsafe {
            let p = sys::hgcd_world_last_error(self.raw.as_ptr());
            if p.is_null() {
                return String::new();
            }
            CStr::from_ptr(p).to_string_lossy().into_owned()
        }
    }

    /// Number of live bodies.
    pub fn body_count(&self) -> u32 {
        // SAFETY: live world.
        unsafe { sys::hgcd_world_body_count(self.raw.as_ptr()) }
    }

    /// Number of live meshes.
    pub fn mesh_count(&self) -> u32 {
        // SAFETY: live world.
        unsafe { sys::hgcd_world_mesh_count(self.raw.as_ptr()) }
    }

    /// OpenMP threads per parallel region (0 = all cores).
    pub fn set_thread_count(&mut self, thread_count: u32) -> Result<()> {
        // SAFETY: live world, exclusively borrowed.
        let s = unsafe { sys::hgcd_world_set_thread_count(self.raw.as_ptr(), thread_count) };
        self.check(s)
    }

    /// The thread policy of the following calls
    /// (`hgcd_world_set_thread_policy`): `Adaptive` or `Fixed`; another
    /// value is refused as `InvalidArgument`.
    pub fn set_thread_policy(&mut self, policy: ThreadPolicy) -> Result<()> {
        // SAFETY: live world, exclusively borrowed.
        let s = unsafe { sys::hgcd_world_set_thread_policy(self.raw.as_ptr(), policy.to_raw()) };
        self.check(s)
    }

    /// The world's narrow phase, from the next step/detect
    /// (`hgcd_world_set_narrow_phase`): `Exact`, `Gjk` or `Mpr`.
    pub fn set_narrow_phase(&mut self, narrow_phase: NarrowPhase) -> Result<()> {
        // SAFETY: live world, exclusively borrowed.
        let s =
            unsafe { sys::hgcd_world_set_narrow_phase(self.raw.as_ptr(), narrow_phase.to_raw()) };
        self.check(s)
    }

    /// A mesh's narrow phase (`hgcd_mesh_set_narrow_phase`): `World` (follow
    /// the world), `Exact`, `Gjk` or `Mpr`; `Gjk`/`Mpr` on a non-convex mesh
    /// is refused as `InvalidArgument`.
    pub fn set_mesh_narrow_phase(&mut self, mesh: MeshId, narrow_phase: NarrowPhase) -> Result<()> {
        // SAFETY: live world, exclusively borrowed; ids are checked by the library.
        let s = unsafe {
            sys::hgcd_mesh_set_narrow_phase(self.raw.as_ptr(), mesh.to_raw(), narrow_phase.to_raw())
        };
        self.check(s)
    }

    /// Records contacts from the next step/detect on (`hgcd_world_set_contacts`).
    pub fn set_contacts(&mut self, on: bool) -> Result<()> {
        // SAFETY: live world, exclusively borrowed.
        let s = unsafe { sys::hgcd_world_set_contacts(self.raw.as_ptr(), u32::from(on)) };
        self.check(s)
    }

    /// What each pair of the last step/detect is made of, in the order of
    /// [`World::pairs`] (`hgcd_world_contacts`, copied). `InvalidArgument`
    /// if contacts were off during that step/detect.
    pub fn contacts(&self) -> Result<Vec<Contact>> {
        let mut p: *const sys::hgcd_contact = ptr::null();
        let mut n: usize = 0;
        // SAFETY: live world and valid out pointers.
        let s = unsafe { sys::hgcd_world_contacts(self.raw.as_ptr(), &mut p, &mut n) };
        Self::check_const(s, || {
            "world_contacts: the last step/detect ran with contacts off".to_string()
        })?;
        if p.is_null() || n == 0 {
            return Ok(Vec::new());
        }
        // SAFETY: `n` initialised contacts at `p`, valid while `self` is
        // borrowed (no changing call can run); copied out at once.
        let raw = unsafe { std::slice::from_raw_parts(p, n) };
        Ok(raw.iter().map(Contact::from).collect())
    }

    /// Moves every body by velocity * time_step, then detects
    /// (`hgcd_world_step`).
    pub fn step(&mut self) -> Result<()> {
        // SAFETY: live world, exclusively borrowed.
        let s = unsafe { sys::hgcd_world_step(self.raw.as_ptr()) };
        self.check(s)
    }

    /// Detects the colliding pairs at the current poses (`hgcd_world_detect`).
    pub fn detect(&mut self) -> Result<()> {
        // SAFETY: live world, exclusively borrowed.
        let s = unsafe { sys::hgcd_world_detect(self.raw.as_ptr()) };
        self.check(s)
    }

    /// The pairs of the last step/detect, sorted by (a.index, b.index),
    /// a.index < b.index, no duplicates: the library's own array, not a copy
    /// (`hgcd_world_pairs`). Empty before the first detect.
    pub fn pairs(&self) -> &[Pair] {
        let mut p: *const sys::hgcd_pair = ptr::null();
        let mut n: usize = 0;
        // SAFETY: live world and valid out pointers.
        let s = unsafe { sys::hgcd_world_pairs(self.raw.as_ptr(), &mut p, &mut n) };
        if s != sys::HGCD_OK || p.is_null() || n == 0 {
            return &[];
        }
        // SAFETY: the library guarantees `n` initialised pairs at `p`, valid
        // until the next call that changes the world; every such call takes
        // `&mut self`, so it cannot happen while the returned slice (borrowing
        // `self`) lives, and dropping the world needs it unborrowed too.
        // `Pair` is layout-identical to `hgcd_pair` (compile-time asserts in
        // types.rs), and every bit pattern is a valid `Pair`.
        unsafe { std::slice::from_raw_parts(p.cast::<Pair>(), n) }
    }

    /// Statistics of the last step/detect (`hgcd_world_stats`); all zero
    /// before the first.
    pub fn stats(&self) -> Stats {
        // SAFETY: hgcd_stats is plain data; zero is a valid value.
        let mut raw: sys::hgcd_stats = unsafe { std::mem::zeroed() };
        raw.struct_size = size_of::<sys::hgcd_stats>() as u32;
        // SAFETY: live world, valid out pointer with its size set.
        let s = unsafe { sys::hgcd_world_stats(self.raw.as_ptr(), &mut raw) };
        if s != sys::HGCD_OK {
            // Cannot happen (non-NULL arguments, right struct_size).
            return Stats::default();
        }
        Stats::from(&raw)
    }

    /// Registers a mesh (`hgcd_mesh_create`); its data are copied in.
    pub fn create_mesh(&mut self, desc: &MeshDesc<'_>) -> Result<MeshId> {
        let too_large = |what: &str, n: usize| {
            Error::new(
                ErrorKind::InvalidMesh,
                format!("mesh_create: {what} count {n} does not fit in 32 bits"),
            )
        };
        let vertex_count = u32::try_from(desc.vertices.len())
            .map_err(|_| too_large("vertex", desc.vertices.len()))?;
        let triangle_count = u32::try_from(desc.triangles.len())
            .map_err(|_| too_large("triangle", desc.triangles.len()))?;
        // SAFETY: returns a plain struct.
        let mut d = unsafe { sys::hgcd_mesh_desc_default() };
        // [[f64; 3]] and [[u32; 3]] are contiguous arrays of f64 / u32.
        d.vertices = desc.vertices.as_ptr().cast::<f64>();
        d.triangles = desc.triangles.as_ptr().cast::<u32>();
        d.vertex_count = vertex_count;
        d.triangle_count = triangle_count;
        let mut out = MeshId::NULL.to_raw();
        // SAFETY: the pointers are valid for the stated counts for the whole
        // call (the library copies the data in); `out` is valid.
        let s = unsafe { sys::hgcd_mesh_create(self.raw.as_ptr(), &d, &mut out) };
        self.check(s)?;
        Ok(MeshId::from_raw(out))
    }

    /// Removes a mesh no live body uses (`hgcd_mesh_destroy`); else
    /// `MeshInUse`.
    pub fn destroy_mesh(&mut self, mesh: MeshId) -> Result<()> {
        // SAFETY: live world; ids are plain values checked by the library.
        let s = unsafe { sys::hgcd_mesh_destroy(self.raw.as_ptr(), mesh.to_raw()) };
        self.check(s)
    }

    /// What the library worked out about a mesh (`hgcd_mesh_get_info`).
    pub fn mesh_info(&self, mesh: MeshId) -> Result<MeshInfo> {
        // SAFETY: plain data; zero is valid.
        let mut info: sys::hgcd_mesh_info = unsafe { std::mem::zeroed() };
        info.struct_size = size_of::<sys::hgcd_mesh_info>() as u32;
        // SAFETY: live world, valid out pointer.
        let s = unsafe { sys::hgcd_mesh_get_info(self.raw.as_ptr(), mesh.to_raw(), &mut info) };
        Self::check_const(s, || format!("mesh_get_info: {mesh:?}"))?;
        Ok(MeshInfo::from(&info))
    }

    /// Places a body (`hgcd_body_create`).
    pub fn create_body(&mut self, desc: &BodyDesc) -> Result<BodyId> {
        let d = desc.to_raw();
        let mut out = BodyId::NULL.to_raw();
        // SAFETY: live world, valid pointers.
        let s = unsafe { sys::hgcd_body_create(self.raw.as_ptr(), &d, &mut out) };
        self.check(s)?;
        Ok(BodyId::from_raw(out))
    }

    /// Removes a body; its id becomes stale (`hgcd_body_destroy`).
    pub fn destroy_body(&mut self, body: BodyId) -> Result<()> {
        // SAFETY: live world.
        let s = unsafe { sys::hgcd_body_destroy(self.raw.as_ptr(), body.to_raw()) };
        self.check(s)
    }

    /// Sets position and orientation (x, y, z, w) (`hgcd_body_set_pose`).
    /// Nothing changes if either is invalid.
    pub fn set_pose(
        &mut self,
        body: BodyId,
        position: [f64; 3],
        orientation: [f64; 4],
    ) -> Result<()> {
        // SAFETY: live world; arrays of the sizes the header asks for.
        let s = unsafe {
            sys::hgcd_body_set_pose(
                self.raw.as_ptr(),
                body.to_raw(),
                position.as_ptr(),
                orientation.as_ptr(),
            )
        };
        self.check(s)
    }

    /// Sets the position only, keeping the orientation.
    pub fn set_position(&mut self, body: BodyId, position: [f64; 3]) -> Result<()> {
        // SAFETY: live world; NULL orientation means "keep".
        let s = unsafe {
            sys::hgcd_body_set_pose(
                self.raw.as_ptr(),
                body.to_raw(),
                position.as_ptr(),
                ptr::null(),
            )
        };
        self.check(s)
    }

    /// Sets the orientation only, keeping the position.
    pub fn set_orientation(&mut self, body: BodyId, orientation: [f64; 4]) -> Result<()> {
        // SAFETY: live world; NULL position means "keep".
        let s = unsafe {
            sys::hgcd_body_set_pose(
                self.raw.as_ptr(),
                body.to_raw(),
                ptr::null(),
                orientation.as_ptr(),
            )
        };
        self.check(s)
    }

    /// Sets the velocity (`hgcd_body_set_velocity`).
    pub fn set_velocity(&mut self, body: BodyId, velocity: [f64; 3]) -> Result<()> {
        // SAFETY: live world; array of 3.
        let s = unsafe {
            sys::hgcd_body_set_velocity(self.raw.as_ptr(), body.to_raw(), velocity.as_ptr())
        };
        self.check(s)
    }

    /// Position and orientation of a body (`hgcd_body_get_pose`).
    pub fn get_pose(&self, body: BodyId) -> Result<Pose> {
        let mut pose = Pose {
            position: [0.0; 3],
            orientation: [0.0; 4],
        };
        // SAFETY: live world; out arrays of the sizes the header asks for.
        let s = unsafe {
            sys::hgcd_body_get_pose(
                self.raw.as_ptr(),
                body.to_raw(),
                pose.position.as_mut_ptr(),
                pose.orientation.as_mut_ptr(),
            )
        };
        Self::check_const(s, || format!("body_get_pose: {body:?}"))?;
        Ok(pose)
    }

    /// Velocity of a body (`hgcd_body_get_velocity`).
    pub fn get_velocity(&self, body: BodyId) -> Result<[f64; 3]> {
        let mut v = [0.0; 3];
        // SAFETY: live world; out array of 3.
        let s = unsafe {
            sys::hgcd_body_get_velocity(self.raw.as_ptr(), body.to_raw(), v.as_mut_ptr())
        };
        Self::check_const(s, || format!("body_get_velocity: {body:?}"))?;
        Ok(v)
    }

    /// The mesh a body was created with (`hgcd_body_get_mesh`).
    pub fn body_mesh(&self, body: BodyId) -> Result<MeshId> {
        let mut m = MeshId::NULL.to_raw();
        // SAFETY: live world; valid out pointer.
        let s = unsafe { sys::hgcd_body_get_mesh(self.raw.as_ptr(), body.to_raw(), &mut m) };
        Self::check_const(s, || format!("body_get_mesh: {body:?}"))?;
        Ok(MeshId::from_raw(m))
    }

    /// The user data a body was created with (`hgcd_body_get_user_data`).
    pub fn body_user_data(&self, body: BodyId) -> Result<u64> {
        let mut u = 0u64;
        // SAFETY: live world; valid out pointer.
        let s = unsafe { sys::hgcd_body_get_user_data(self.raw.as_ptr(), body.to_raw(), &mut u) };
        Self::check_const(s, || format!("body_get_user_data: {body:?}"))?;
        Ok(u)
    }

    /// Whether `body` is a live body of this world (`hgcd_body_validate`).
    pub fn is_body_alive(&self, body: BodyId) -> bool {
        // SAFETY: live world.
        unsafe { sys::hgcd_body_validate(self.raw.as_ptr(), body.to_raw()) == sys::HGCD_OK }
    }

    /// Whether `mesh` is a live mesh of this world (`hgcd_mesh_validate`):
    /// false for the null id, a destroyed mesh, a forged id or another
    /// world's mesh.
    pub fn is_mesh_alive(&self, mesh: MeshId) -> bool {
        // SAFETY: live world; ids are plain values checked by the library.
        unsafe { sys::hgcd_mesh_validate(self.raw.as_ptr(), mesh.to_raw()) == sys::HGCD_OK }
    }
}

impl Drop for World {
    fn drop(&mut self) {
        // SAFETY: we own the live world; nothing borrows it any more (drop
        // takes `&mut self`, so every `pairs()` slice is gone).
        unsafe { sys::hgcd_world_destroy(self.raw.as_ptr()) }
    }
}

impl fmt::Debug for World {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("World")
            .field("bodies", &self.body_count())
            .field("meshes", &self.mesh_count())
            .finish()
    }
}
