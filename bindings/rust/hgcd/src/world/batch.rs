//! The batch calls of `World`: poses and velocities of many bodies in one
//! call, over slices.

use std::ptr;

use hgcd_sys as sys;

use crate::error::{Error, ErrorKind, Result};
use crate::types::BodyId;
use crate::World;

impl World {
    /// Sets the poses of many bodies in one call (`hgcd_world_set_poses`), as
    /// one [`World::set_pose`] per entry would, but checked whole first: a
    /// refusal changes nothing and its message names the first bad entry
    /// (`"world_set_poses: entry 3: ..."`).
    ///
    /// Entry `k` is `bodies[k]`, or with `bodies` `None` the body of index
    /// `k` (on a world without destroyed bodies, the `k`-th created). Either
    /// of `positions` and `orientations` may be `None` to keep that part of
    /// every pose, not both. The given slices must have the same length:
    /// otherwise, or with both `None`, the error is `InvalidArgument` and no
    /// C call is made. The library refuses a stale id (`StaleId`), an id
    /// named twice or a value [`World::set_pose`] refuses
    /// (`InvalidArgument`).
    ///
    /// ```
    /// # use hgcd::{BodyDesc, MeshDesc, World, WorldDesc};
    /// # let mut world = World::new(&WorldDesc::default())?;
    /// # let (v, t) = hgcd::scene::unit_mesh();
    /// # let mesh = world.create_mesh(&MeshDesc::new(&v, &t))?;
    /// let a = world.create_body(&BodyDesc::new(mesh))?;
    /// let b = world.create_body(&BodyDesc::new(mesh))?;
    /// // Every body, by index: b moves away from a.
    /// world.set_poses(None, Some(&[[0.0; 3], [10.0, 0.0, 0.0]]), None)?;
    /// world.detect()?;
    /// assert!(world.pairs().is_empty());
    /// // Listed ids: b comes back, turned.
    /// let half_turn = [0.0, 0.0, 1.0, 0.0];
    /// world.set_poses(Some(&[b]), Some(&[[0.5, 0.0, 0.0]]), Some(&[half_turn]))?;
    /// world.detect()?;
    /// assert_eq!(world.pairs(), &[hgcd::Pair { a, b }]);
    /// # Ok::<(), hgcd::Error>(())
    /// ```
    pub fn set_poses(
        &mut self,
        bodies: Option<&[BodyId]>,
        positions: Option<&[[f64; 3]]>,
        orientations: Option<&[[f64; 4]]>,
    ) -> Result<()> {
        const WHAT: &str = "world_set_poses";
        if positions.is_none() && orientations.is_none() {
            return Err(Error::new(
                ErrorKind::InvalidArgument,
                format!("{WHAT}: positions and orientations are both None"),
            ));
        }
        let count = entry_count(
            WHAT,
            bodies,
            &[
                ("positions", positions.map(<[_]>::len)),
                ("orientations", orientations.map(<[_]>::len)),
            ],
        )?;
        // SAFETY: live world, exclusively borrowed. Every non-NULL array holds
        // `count` entries: `BodyId` is `repr(transparent)` over `hgcd_body`,
        // `[[f64; N]]` is N * count contiguous doubles (stride 0 = packed).
        // The library only reads them during the call.
        let s = unsafe {
            sys::hgcd_world_set_poses(
                self.raw.as_ptr(),
                bodies_ptr(bodies),
                count,
                positions.map_or(ptr::null(), |p| p.as_ptr().cast::<f64>()),
                0,
                orientations.map_or(ptr::null(), |q| q.as_ptr().cast::<f64>()),
                0,
            )
        };
        self.check(s)
    }

    /// Sets the velocities of many bodies in one call
    /// (`hgcd_world_set_velocities`): entry `k` as in [`World::set_poses`].
    /// A length mismatch between `bodies` and `velocities` is
    /// `InvalidArgument` before any C call; a stale or repeated id or a
    /// non-finite value is refused by the library, and nothing changes.
    pub fn set_velocities(
        &mut self,
        bodies: Option<&[BodyId]>,
        velocities: &[[f64; 3]],
    ) -> Result<()> {
        let count = entry_count(
            "world_set_velocities",
            bodies,
            &[("velocities", Some(velocities.len()))],
        )?;
        // SAFETY: as in `set_poses`; `velocities` holds `count` packed entries.
        let s = unsafe {
            sys::hgcd_world_set_velocities(
                self.raw.as_ptr(),
                bodies_ptr(bodies),
                count,
                velocities.as_ptr().cast::<f64>(),
                0,
            )
        };
        self.check(s)
    }

    /// Reads the poses of many bodies into the caller's slices
    /// (`hgcd_world_get_poses`), bit for bit as [`World::get_pose`] would:
    /// entry `k` as in [`World::set_poses`]; either output may be `None`, not
    /// both. Writing into the caller's slices, rather than returning vectors,
    /// lets a loop over ticks reuse its buffers (and read positions only),
    /// which is what the batch call is for.
    ///
    /// Lengths must agree (`InvalidArgument` before any C call). `StaleId`
    /// when an entry has no live body: the message names the first such
    /// entry. Nothing is written on failure.
    pub fn get_poses(
        &self,
        bodies: Option<&[BodyId]>,
        positions: Option<&mut [[f64; 3]]>,
        orientations: Option<&mut [[f64; 4]]>,
    ) -> Result<()> {
        const WHAT: &str = "world_get_poses";
        if positions.is_none() && orientations.is_none() {
            return Err(Error::new(
                ErrorKind::InvalidArgument,
                format!("{WHAT}: positions and orientations are both None"),
            ));
        }
        let count = entry_count(
            WHAT,
            bodies,
            &[
                ("positions", positions.as_ref().map(|p| p.len())),
                ("orientations", orientations.as_ref().map(|q| q.len())),
            ],
        )?;
        // SAFETY: live world (read-only call); every non-NULL output holds
        // `count` packed entries and is exclusively borrowed for the call.
        let s = unsafe {
            sys::hgcd_world_get_poses(
                self.raw.as_ptr(),
                bodies_ptr(bodies),
                count,
                positions.map_or(ptr::null_mut(), |p| p.as_mut_ptr().cast::<f64>()),
                0,
                orientations.map_or(ptr::null_mut(), |q| q.as_mut_ptr().cast::<f64>()),
                0,
            )
        };
        // A const call records no message: name the first entry without a
        // live body here (only on failure, so the cost does not matter).
        Self::check_const(s, || match bodies {
            Some(ids) => match ids.iter().position(|&b| !self.is_body_alive(b)) {
                Some(k) => format!(
                    "{WHAT}: entry {k}: {:?} is not a live body of this world",
                    ids[k]
                ),
                None => WHAT.to_string(),
            },
            None => format!("{WHAT}: an index below {count} holds no live body"),
        })
    }
}

/// The entry count of a batch call: the length of `bodies` if given, else of
/// the arrays; every given length must agree (checked here, before C).
fn entry_count(
    what: &str,
    bodies: Option<&[BodyId]>,
    arrays: &[(&str, Option<usize>)],
) -> Result<usize> {
    let mut count = bodies.map(<[_]>::len);
    let mut named = "bodies";
    for &(name, len) in arrays {
        match (count, len) {
            (Some(c), Some(n)) if c != n => {
                return Err(Error::new(
                    ErrorKind::InvalidArgument,
                    format!("{what}: {named} has {c} entries, {name} {n}"),
                ))
            }
            (None, Some(n)) => {
                count = Some(n);
                named = name;
            }
            _ => {}
        }
    }
    Ok(count.unwrap_or(0))
}

/// `bodies` as the C array (`BodyId` is `repr(transparent)` over
/// `hgcd_body`), or NULL for "indices 0 .. count-1".
fn bodies_ptr(bodies: Option<&[BodyId]>) -> *const sys::hgcd_body {
    bodies.map_or(ptr::null(), |b| b.as_ptr().cast::<sys::hgcd_body>())
}
