//! The began and ended pairs of the last detect (`hgcd_world_events`).

use std::mem::{align_of, offset_of, size_of};
use std::ptr;

use hgcd_sys as sys;

use crate::types::Pair;
use crate::World;

/// A pair that began or ended colliding, with both bodies' user data.
/// Layout-identical to `hgcd_pair_event` (checked at compile time), so
/// [`World::events`] hands out the library's own arrays.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(C)]
pub struct PairEvent {
    pub pair: Pair,
    pub user_data_a: u64,
    pub user_data_b: u64,
}

const _: () = {
    assert!(size_of::<PairEvent>() == size_of::<sys::hgcd_pair_event>());
    assert!(align_of::<PairEvent>() == align_of::<sys::hgcd_pair_event>());
    assert!(offset_of!(PairEvent, user_data_a) == offset_of!(sys::hgcd_pair_event, user_data_a));
    assert!(offset_of!(PairEvent, user_data_b) == offset_of!(sys::hgcd_pair_event, user_data_b));
};

impl World {
    /// The pairs that began and those that ended colliding at the last
    /// step/detect, against the previous one (compared by full ids), each
    /// sorted by (a.index, b.index): the library's own arrays, borrowed from
    /// the world (`hgcd_world_events`).
    pub fn events(&self) -> (&[PairEvent], &[PairEvent]) {
        let (mut b, mut e): (*const sys::hgcd_pair_event, *const sys::hgcd_pair_event) = (ptr::null(), ptr::null());
        let (mut nb, mut ne) = (0usize, 0usize);
        // SAFETY: live world and valid out pointers.
        let s = unsafe { sys::hgcd_world_events(self.as_ptr(), &mut b, &mut nb, &mut e, &mut ne) };
        if s != sys::HGCD_OK {
            return (&[], &[]);
        }
        // SAFETY: as for `World::pairs`: `n` events at each pointer, valid
        // until the next call that changes the world (which takes `&mut
        // self`); the layouts are identical and every bit pattern is valid.
        let slice = |p: *const sys::hgcd_pair_event, n: usize| -> &[PairEvent] {
            if p.is_null() || n == 0 {
                &[]
            } else {
                unsafe { std::slice::from_raw_parts(p.cast::<PairEvent>(), n) }
            }
        };
        (slice(b, nb), slice(e, ne))
    }
}
