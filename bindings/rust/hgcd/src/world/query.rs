//! The scene queries of `World`: rays, boxes, points and meshes at a pose
//! against the bodies, many at once, over slices.

use std::mem::{align_of, size_of};
use std::ptr;
use std::slice;

use hgcd_sys as sys;

use crate::error::{Error, ErrorKind, Result};
use crate::filter::Filter;
use crate::types::{BodyId, MeshId};
use crate::World;

/// A ray: the closed segment from `origin` to `origin + max_distance *
/// direction` (`hgcd_ray`, layout-identical). `direction` need not be a unit
/// vector; distances are in units of its length.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct Ray {
    pub origin: [f64; 3],
    pub direction: [f64; 3],
    pub max_distance: f64,
}

/// What a ray hit (`hgcd_ray_hit`, layout-identical).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct RayHit {
    /// The body hit; the null id when the ray hit nothing.
    pub body: BodyId,
    /// The triangle crossed, or `u32::MAX` when the origin lies in the body's
    /// closed solid.
    pub triangle: u32,
    /// 1 when the origin lies in the closed solid of the body's closed mesh.
    pub inside: u32,
    /// `max_distance * t`, t the hit's exact parameter on the segment
    /// (relative error below 2^-40).
    pub distance: f64,
}

impl RayHit {
    /// Whether the ray hit a body.
    pub fn is_hit(&self) -> bool {
        !self.body.is_null()
    }
}

/// A pose of a query mesh (`hgcd_mesh_pose`, layout-identical).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct MeshPose {
    pub position: [f64; 3],
    pub orientation: [f64; 4],
    pub scale: f64,
}

/// Closest hit or any hit (`enum hgcd_ray_mode`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RayMode {
    /// The hit with the smallest parameter; ties by body, then triangle index.
    Closest,
    /// Whether the ray hits anything; the hit reported is a true hit.
    Any,
}

const _: () = {
    assert!(size_of::<Ray>() == size_of::<sys::hgcd_ray>());
    assert!(align_of::<Ray>() == align_of::<sys::hgcd_ray>());
    assert!(size_of::<RayHit>() == size_of::<sys::hgcd_ray_hit>());
    assert!(align_of::<RayHit>() == align_of::<sys::hgcd_ray_hit>());
    assert!(size_of::<MeshPose>() == size_of::<sys::hgcd_mesh_pose>());
};

/// The results of a batch of box, point or mesh queries, borrowed from the
/// world until its next query (the borrow checker enforces it).
#[derive(Clone, Copy, Debug)]
pub struct QueryResults<'a> {
    offsets: &'a [usize],
    bodies: &'a [BodyId],
}

impl<'a> QueryResults<'a> {
    /// The number of queries.
    pub fn len(&self) -> usize {
        self.offsets.len() - 1
    }

    /// Whether there were no queries.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The bodies found by query `k`, ascending by index.
    pub fn get(&self, k: usize) -> &'a [BodyId] {
        &self.bodies[self.offsets[k]..self.offsets[k + 1]]
    }

    /// Every query's bodies, in query order.
    pub fn iter(&self) -> impl Iterator<Item = &'a [BodyId]> + '_ {
        (0..self.len()).map(move |k| self.get(k))
    }

    /// All bodies, query after query; `offsets()[k]..offsets()[k + 1]` are
    /// query k's.
    pub fn bodies(&self) -> &'a [BodyId] {
        self.bodies
    }

    /// Where each query's bodies start (one more entry than queries).
    pub fn offsets(&self) -> &'a [usize] {
        self.offsets
    }
}

/// A query's filter as the C call takes it: the query stands for a body
/// with that filter (hgcd.h, "Scene queries"); `None`, every enabled body.
fn raw_filter(filter: Option<&Filter>) -> Option<sys::hgcd_filter> {
    filter.map(Filter::to_raw)
}

fn filter_ptr(raw: &Option<sys::hgcd_filter>) -> *const sys::hgcd_filter {
    raw.as_ref().map_or(ptr::null(), |f| f as *const sys::hgcd_filter)
}

impl World {
    /// Casts the rays (`hgcd_world_cast_rays`) into `hits`, one per ray;
    /// `hits.len()` must equal `rays.len()` (else `InvalidArgument`, no C
    /// call). A refusal writes nothing.
    ///
    /// ```
    /// # use hgcd::{BodyDesc, MeshDesc, World, WorldDesc, Ray, RayHit, RayMode};
    /// # let mut world = World::new(&WorldDesc::default())?;
    /// # let (v, t) = hgcd::scene::unit_mesh();
    /// # let mesh = world.create_mesh(&MeshDesc::new(&v, &t))?;
    /// let body = world.create_body(&BodyDesc::new(mesh))?;
    /// let rays = [Ray { origin: [-5.0, 0.0, 0.0], direction: [1.0, 0.0, 0.0], max_distance: 10.0 }];
    /// let hits = world.cast_rays(&rays, RayMode::Closest, None)?;
    /// assert_eq!(hits[0].body, body);
    /// assert!(hits[0].distance > 3.0 && hits[0].distance < 5.0);
    /// # Ok::<(), hgcd::Error>(())
    /// ```
    pub fn cast_rays_into(
        &mut self,
        rays: &[Ray],
        mode: RayMode,
        filter: Option<&Filter>,
        hits: &mut [RayHit],
    ) -> Result<()> {
        if hits.len() != rays.len() {
            return Err(Error::new(
                ErrorKind::InvalidArgument,
                format!("world_cast_rays: {} rays but room for {} hits", rays.len(), hits.len()),
            ));
        }
        let mode = match mode {
            RayMode::Closest => sys::HGCD_RAY_CLOSEST,
            RayMode::Any => sys::HGCD_RAY_ANY,
        } as i32;
        let raw = raw_filter(filter);
        // SAFETY: live world, exclusively borrowed; `Ray` and `RayHit` are
        // layout-identical to the C structs (checked above); the library
        // reads `rays.len()` rays and writes as many hits during the call.
        let s = unsafe {
            sys::hgcd_world_cast_rays(
                self.as_mut_ptr(),
                rays.as_ptr().cast(),
                rays.len(),
                0,
                mode,
                filter_ptr(&raw),
                hits.as_mut_ptr().cast(),
            )
        };
        self.check(s)
    }

    /// [`World::cast_rays_into`] into a new vector.
    pub fn cast_rays(&mut self, rays: &[Ray], mode: RayMode, filter: Option<&Filter>) -> Result<Vec<RayHit>> {
        let none = RayHit { body: BodyId::NULL, triangle: u32::MAX, inside: 0, distance: 0.0 };
        let mut hits = vec![none; rays.len()];
        self.cast_rays_into(rays, mode, filter, &mut hits)?;
        Ok(hits)
    }

    /// The bodies whose closed solid meets each closed box `[min x y z, max
    /// x y z]` (`hgcd_world_query_box`).
    pub fn query_boxes(&mut self, boxes: &[[f64; 6]], filter: Option<&Filter>) -> Result<QueryResults<'_>> {
        let mut out = empty_results();
        let raw = raw_filter(filter);
        // SAFETY: live world, exclusively borrowed; `boxes` is 6 packed
        // doubles per box, read during the call.
        let s = unsafe {
            sys::hgcd_world_query_box(
                self.as_mut_ptr(),
                boxes.as_ptr().cast(),
                boxes.len(),
                0,
                filter_ptr(&raw),
                &mut out,
            )
        };
        self.check(s)?;
        Ok(self.results(&out))
    }

    /// The bodies whose closed solid contains each point
    /// (`hgcd_world_query_point`).
    pub fn query_points(&mut self, points: &[[f64; 3]], filter: Option<&Filter>) -> Result<QueryResults<'_>> {
        let mut out = empty_results();
        let raw = raw_filter(filter);
        // SAFETY: as query_boxes, 3 doubles per point.
        let s = unsafe {
            sys::hgcd_world_query_point(
                self.as_mut_ptr(),
                points.as_ptr().cast(),
                points.len(),
                0,
                filter_ptr(&raw),
                &mut out,
            )
        };
        self.check(s)?;
        Ok(self.results(&out))
    }

    /// The bodies a body of `mesh` at each pose would collide with
    /// (`hgcd_world_query_mesh`).
    pub fn query_mesh(
        &mut self,
        mesh: MeshId,
        poses: &[MeshPose],
        filter: Option<&Filter>,
    ) -> Result<QueryResults<'_>> {
        let mut out = empty_results();
        let raw = raw_filter(filter);
        // SAFETY: as query_boxes; `MeshPose` is layout-identical to
        // `hgcd_mesh_pose`.
        let s = unsafe {
            sys::hgcd_world_query_mesh(
                self.as_mut_ptr(),
                mesh.to_raw(),
                poses.as_ptr().cast(),
                poses.len(),
                0,
                filter_ptr(&raw),
                &mut out,
            )
        };
        self.check(s)?;
        Ok(self.results(&out))
    }

    fn results(&self, out: &sys::hgcd_query_results) -> QueryResults<'_> {
        // SAFETY: the arrays are the world's, valid until its next query,
        // which needs `&mut self` while the result borrows `self`. offsets
        // has query_count + 1 entries; bodies body_count (may be NULL when 0).
        unsafe {
            let offsets = slice::from_raw_parts(out.offsets, out.query_count + 1);
            let bodies = if out.body_count == 0 {
                &[][..]
            } else {
                slice::from_raw_parts(out.bodies.cast::<BodyId>(), out.body_count)
            };
            QueryResults { offsets, bodies }
        }
    }
}

fn empty_results() -> sys::hgcd_query_results {
    sys::hgcd_query_results { offsets: ptr::null(), bodies: ptr::null(), query_count: 0, body_count: 0 }
}
