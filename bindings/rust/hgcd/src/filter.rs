//! Body types and collision filters (`enum hgcd_body_type`, `hgcd_filter`).

use hgcd_sys as sys;

/// How a body moves, and so which of its pairs are considered
/// (`enum hgcd_body_type`): a pair with a dynamic body always; two static
/// bodies never; a kinematic body with a kinematic or static one only when
/// [`WorldDesc::kinematic_pairs`](crate::WorldDesc::kinematic_pairs) is set.
/// `World::step` moves dynamic and kinematic bodies, never static ones.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum BodyType {
    /// Moves every tick (the default).
    #[default]
    Dynamic,
    /// Moved by the caller.
    Kinematic,
    /// Level geometry: moved only when the caller sets its pose.
    Static,
    /// A value this crate does not know (from a newer library).
    Unknown(i32),
}

// (bindgen gives the enum's constants as u32: its values are all >= 0.)
const DYNAMIC: i32 = sys::HGCD_BODY_DYNAMIC as i32;
const KINEMATIC: i32 = sys::HGCD_BODY_KINEMATIC as i32;
const STATIC: i32 = sys::HGCD_BODY_STATIC as i32;

impl BodyType {
    pub fn from_raw(v: i32) -> BodyType {
        match v {
            DYNAMIC => BodyType::Dynamic,
            KINEMATIC => BodyType::Kinematic,
            STATIC => BodyType::Static,
            other => BodyType::Unknown(other),
        }
    }

    pub fn to_raw(self) -> i32 {
        match self {
            BodyType::Dynamic => DYNAMIC,
            BodyType::Kinematic => KINEMATIC,
            BodyType::Static => STATIC,
            BodyType::Unknown(v) => v,
        }
    }
}

/// Which bodies a body may collide with (`hgcd_filter`, Box2D v3's
/// semantics): the same non-zero `group_index` decides alone (positive:
/// always, negative: never); otherwise each body's `mask_bits` must share a
/// bit with the other's `category_bits`. [`Default`] is
/// `hgcd_filter_default()`: category 1, every mask bit, group 0.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Filter {
    pub category_bits: u64,
    pub mask_bits: u64,
    pub group_index: i32,
}

impl Default for Filter {
    fn default() -> Filter {
        // SAFETY: no arguments, returns a plain struct by value.
        Filter::from_raw(&unsafe { sys::hgcd_filter_default() })
    }
}

impl Filter {
    pub fn from_raw(f: &sys::hgcd_filter) -> Filter {
        Filter {
            category_bits: f.category_bits,
            mask_bits: f.mask_bits,
            group_index: f.group_index,
        }
    }

    pub fn to_raw(&self) -> sys::hgcd_filter {
        sys::hgcd_filter {
            category_bits: self.category_bits,
            mask_bits: self.mask_bits,
            group_index: self.group_index,
            reserved: 0,
        }
    }
}
