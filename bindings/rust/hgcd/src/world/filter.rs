//! Body types, enabling, filters and excluded pairs of `World`.

use hgcd_sys as sys;

use crate::error::Result;
use crate::filter::{BodyType, Filter};
use crate::types::BodyId;
use crate::World;

impl World {
    /// Sets a body's type from the next detect (`hgcd_body_set_type`).
    pub fn set_body_type(&mut self, body: BodyId, body_type: BodyType) -> Result<()> {
        // SAFETY: live world.
        let s = unsafe { sys::hgcd_body_set_type(self.as_mut_ptr(), body.to_raw(), body_type.to_raw()) };
        self.check(s)
    }

    /// A body's type (`hgcd_body_get_type`).
    pub fn body_type(&self, body: BodyId) -> Result<BodyType> {
        let mut t = 0i32;
        // SAFETY: live world; valid out pointer.
        let s = unsafe { sys::hgcd_body_get_type(self.as_ptr(), body.to_raw(), &mut t) };
        Self::check_const(s, || format!("body_get_type: {body:?}"))?;
        Ok(BodyType::from_raw(t))
    }

    /// Enables or disables a body from the next detect
    /// (`hgcd_body_set_enabled`): a disabled body keeps its id and state but
    /// leaves every pair, and `step` does not move it.
    pub fn set_body_enabled(&mut self, body: BodyId, enabled: bool) -> Result<()> {
        // SAFETY: live world.
        let s = unsafe { sys::hgcd_body_set_enabled(self.as_mut_ptr(), body.to_raw(), u32::from(enabled)) };
        self.check(s)
    }

    /// Whether a body is enabled (`hgcd_body_get_enabled`).
    pub fn is_body_enabled(&self, body: BodyId) -> Result<bool> {
        let mut e = 0u32;
        // SAFETY: live world; valid out pointer.
        let s = unsafe { sys::hgcd_body_get_enabled(self.as_ptr(), body.to_raw(), &mut e) };
        Self::check_const(s, || format!("body_get_enabled: {body:?}"))?;
        Ok(e != 0)
    }

    /// Sets a body's filter from the next detect (`hgcd_body_set_filter`).
    pub fn set_body_filter(&mut self, body: BodyId, filter: &Filter) -> Result<()> {
        let f = filter.to_raw();
        // SAFETY: live world; `f` outlives the call.
        let s = unsafe { sys::hgcd_body_set_filter(self.as_mut_ptr(), body.to_raw(), &f) };
        self.check(s)
    }

    /// A body's filter (`hgcd_body_get_filter`).
    pub fn body_filter(&self, body: BodyId) -> Result<Filter> {
        let mut f = Filter::default().to_raw();
        // SAFETY: live world; valid out pointer.
        let s = unsafe { sys::hgcd_body_get_filter(self.as_ptr(), body.to_raw(), &mut f) };
        Self::check_const(s, || format!("body_get_filter: {body:?}"))?;
        Ok(Filter::from_raw(&f))
    }

    /// Sets a body's contact margin (`hgcd_body_set_margin`): finite, >= 0,
    /// <= 1e15. The next detect rebuilds the broad phase.
    pub fn set_body_margin(&mut self, body: BodyId, margin: f64) -> Result<()> {
        // SAFETY: live world.
        let s = unsafe { sys::hgcd_body_set_margin(self.as_mut_ptr(), body.to_raw(), margin) };
        self.check(s)
    }

    /// A body's contact margin (`hgcd_body_get_margin`).
    pub fn body_margin(&self, body: BodyId) -> Result<f64> {
        let mut m = 0.0;
        // SAFETY: live world; valid out pointer.
        let s = unsafe { sys::hgcd_body_get_margin(self.as_ptr(), body.to_raw(), &mut m) };
        Self::check_const(s, || format!("body_get_margin: {body:?}"))?;
        Ok(m)
    }

    /// Sets the world's contact margin (`hgcd_world_set_contact_margin`):
    /// finite, >= 0, <= 1e15. Every pair is tested again and the next
    /// detect rebuilds the broad phase; a refused value changes nothing.
    pub fn set_contact_margin(&mut self, margin: f64) -> Result<()> {
        // SAFETY: live world.
        let s = unsafe { sys::hgcd_world_set_contact_margin(self.as_mut_ptr(), margin) };
        self.check(s)
    }

    /// The world's contact margin (`hgcd_world_get_contact_margin`).
    pub fn contact_margin(&self) -> Result<f64> {
        let mut m = 0.0;
        // SAFETY: live world; valid out pointer.
        let s = unsafe { sys::hgcd_world_get_contact_margin(self.as_ptr(), &mut m) };
        Self::check_const(s, || "world_get_contact_margin".to_string())?;
        Ok(m)
    }

    /// Excludes the pair {a, b} from detection (`hgcd_world_exclude_pair`)
    /// until [`World::include_pair`] or either body's destruction.
    pub fn exclude_pair(&mut self, a: BodyId, b: BodyId) -> Result<()> {
        // SAFETY: live world.
        let s = unsafe { sys::hgcd_world_exclude_pair(self.as_mut_ptr(), a.to_raw(), b.to_raw()) };
        self.check(s)
    }

    /// Ends the exclusion of {a, b} (`hgcd_world_include_pair`).
    pub fn include_pair(&mut self, a: BodyId, b: BodyId) -> Result<()> {
        // SAFETY: live world.
        let s = unsafe { sys::hgcd_world_include_pair(self.as_mut_ptr(), a.to_raw(), b.to_raw()) };
        self.check(s)
    }

    /// Whether {a, b} is excluded (`hgcd_world_pair_excluded`).
    pub fn is_pair_excluded(&self, a: BodyId, b: BodyId) -> Result<bool> {
        let mut e = 0u32;
        // SAFETY: live world; valid out pointer.
        let s = unsafe { sys::hgcd_world_pair_excluded(self.as_ptr(), a.to_raw(), b.to_raw(), &mut e) };
        Self::check_const(s, || format!("world_pair_excluded: {a:?}, {b:?}"))?;
        Ok(e != 0)
    }
}
