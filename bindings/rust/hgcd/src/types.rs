//! Ids, pairs, descriptors and the plain result structs.

use std::cmp::Ordering;
use std::fmt;
use std::mem::{align_of, size_of};

use hgcd_sys as sys;

use crate::filter::{BodyType, Filter};

macro_rules! id_type {
    ($(#[$doc:meta])* $name:ident, $raw:ty) => {
        $(#[$doc])*
        #[derive(Clone, Copy, PartialEq, Eq, Hash)]
        #[repr(transparent)]
        pub struct $name($raw);

        impl $name {
            /// The null id (all zero): never the id of a live object; the
            /// library refuses it as `StaleId`.
            pub const NULL: $name = $name(<$raw>::NULL_RAW);

            /// Wraps a C id. Safe: any value is fine, the library checks
            /// ids and refuses a stale, forged or foreign one as `StaleId`.
            pub const fn from_raw(raw: $raw) -> $name {
                $name(raw)
            }

            /// The C id.
            pub const fn to_raw(self) -> $raw {
                self.0
            }

            /// The slot index. On a fresh world, bodies get indices 0, 1,
            /// 2, ... in creation order (a destroyed body's index is reused
            /// later), so it maps back to the caller's arrays.
            pub const fn index(self) -> u32 {
                self.0.index
            }

            /// The generation (it changes each time the index is reused, and
            /// carries a world tag).
            pub const fn generation(self) -> u32 {
                self.0.generation
            }

            /// Whether this is the null id.
            pub const fn is_null(self) -> bool {
                self.0.index == 0 && self.0.generation == 0
            }
        }

        impl Default for $name {
            /// The null id.
            fn default() -> $name {
                $name::NULL
            }
        }

        impl fmt::Debug for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.debug_struct(stringify!($name))
                    .field("index", &self.0.index)
                    .field("generation", &self.0.generation)
                    .finish()
            }
        }

        /// Ordered by (index, generation), the order pairs are reported in.
        impl Ord for $name {
            fn cmp(&self, other: &$name) -> Ordering {
                (self.0.index, self.0.generation).cmp(&(other.0.index, other.0.generation))
            }
        }

        impl PartialOrd for $name {
            fn partial_cmp(&self, other: &$name) -> Option<Ordering> {
                Some(self.cmp(other))
            }
        }

        impl From<$raw> for $name {
            fn from(raw: $raw) -> $name {
                $name(raw)
            }
        }

        impl From<$name> for $raw {
            fn from(id: $name) -> $raw {
                id.0
            }
        }
    };
}

trait NullRaw {
    const NULL_RAW: Self;
}
impl NullRaw for sys::hgcd_mesh {
    const NULL_RAW: Self = sys::hgcd_mesh {
        index: 0,
        generation: 0,
    };
}
impl NullRaw for sys::hgcd_body {
    const NULL_RAW: Self = sys::hgcd_body {
        index: 0,
        generation: 0,
    };
}

id_type!(
    /// A mesh (shared shape) of one [`World`](crate::World): `hgcd_mesh`.
    MeshId,
    sys::hgcd_mesh
);
id_type!(
    /// A body (placed instance of a mesh) of one [`World`](crate::World):
    /// `hgcd_body`.
    BodyId,
    sys::hgcd_body
);

/// One colliding pair, `a.index() < b.index()`. Layout-identical to
/// `hgcd_pair` (checked at compile time), so [`World::pairs`](crate::World::pairs)
/// hands out the library's own array without copying.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[repr(C)]
pub struct Pair {
    pub a: BodyId,
    pub b: BodyId,
}

const _: () = {
    assert!(size_of::<Pair>() == size_of::<sys::hgcd_pair>());
    assert!(align_of::<Pair>() == align_of::<sys::hgcd_pair>());
    // Both are repr(C) structs of two 8-byte, 4-aligned ids: equal size and
    // alignment imply equal field offsets (also checked in the tests).
    assert!(size_of::<BodyId>() == size_of::<sys::hgcd_body>());
    assert!(align_of::<BodyId>() == align_of::<sys::hgcd_body>());
};

impl Pair {
    /// The two bodies' indices, `(a, b)`.
    pub fn indices(&self) -> (u32, u32) {
        (self.a.index(), self.b.index())
    }
}

impl From<sys::hgcd_pair> for Pair {
    fn from(p: sys::hgcd_pair) -> Pair {
        Pair {
            a: BodyId(p.a),
            b: BodyId(p.b),
        }
    }
}

/// World parameters: `hgcd_world_desc` without its size and init tag.
/// [`Default`] is `hgcd_world_desc_default()`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WorldDesc {
    /// OpenMP threads per parallel region; 0 = all cores.
    pub thread_count: u32,
    /// `World::step` mirrors bodies back inside the bounds box (and negates
    /// that velocity component), as the reference scenes do.
    pub reflect_at_bounds: bool,
    /// `position += velocity * time_step` per step. Finite, >= 0.
    pub time_step: f64,
    /// Bounds read only when `reflect_at_bounds` is set: then finite,
    /// |x| <= 1e15, min < max per axis; otherwise ignored.
    pub bounds_min: [f64; 3],
    pub bounds_max: [f64; 3],
    /// Broad-phase grid overrides (0 = adapt to the bodies); see the header.
    pub min_cell_size: f64,
    pub max_cell_size: f64,
    /// Narrow phase of the world's pairs: `Exact` (default), `Gjk` or `Mpr`
    /// (libccd, convex meshes only; see [`NarrowPhase`]). `World` is refused.
    pub narrow_phase: NarrowPhase,
    /// Record what each colliding pair is made of ([`crate::World::contacts`]).
    pub contacts: bool,
    /// How many of `thread_count` threads a detect uses: `Adaptive`
    /// (default: fewer while the cores are busy with other work) or `Fixed`
    /// (see [`ThreadPolicy`]).
    pub thread_policy: ThreadPolicy,
    /// Report kinematic-kinematic and kinematic-static pairs ([`BodyType`]).
    pub kinematic_pairs: bool,
    /// Contact margin of every pair: a pair is reported when the solids
    /// come within `contact_margin + (margin_a + margin_b)` (each sum
    /// rounded to f64), decided exactly. 0 (default): exact touching.
    /// Finite, >= 0, <= 1e15.
    pub contact_margin: f64,
}

impl Default for WorldDesc {
    fn default() -> WorldDesc {
        // SAFETY: no arguments, returns a plain struct by value.
        let d = unsafe { sys::hgcd_world_desc_default() };
        WorldDesc {
            thread_count: d.thread_count,
            reflect_at_bounds: d.reflect_at_bounds != 0,
            time_step: d.time_step,
            bounds_min: d.bounds_min,
            bounds_max: d.bounds_max,
            min_cell_size: d.min_cell_size,
            max_cell_size: d.max_cell_size,
            narrow_phase: NarrowPhase::from_raw(d.narrow_phase),
            contacts: d.contacts != 0,
            thread_policy: ThreadPolicy::from_raw(d.thread_policy),
            kinematic_pairs: d.kinematic_pairs != 0,
            contact_margin: d.contact_margin,
        }
    }
}

impl WorldDesc {
    /// The C descriptor: starts from `hgcd_world_desc_default()` (so size
    /// and init tag are right) and copies every field.
    pub fn to_raw(&self) -> sys::hgcd_world_desc {
        // SAFETY: as in `default`.
        let mut d = unsafe { sys::hgcd_world_desc_default() };
        d.thread_count = self.thread_count;
        d.reflect_at_bounds = u32::from(self.reflect_at_bounds);
        d.time_step = self.time_step;
        d.bounds_min = self.bounds_min;
        d.bounds_max = self.bounds_max;
        d.min_cell_size = self.min_cell_size;
        d.max_cell_size = self.max_cell_size;
        d.narrow_phase = self.narrow_phase.to_raw();
        d.contacts = u32::from(self.contacts);
        d.thread_policy = self.thread_policy.to_raw();
        d.kinematic_pairs = u32::from(self.kinematic_pairs);
        d.contact_margin = self.contact_margin;
        d
    }
}

/// Mesh data: `hgcd_mesh_desc` with slices in place of pointer and count.
/// Both are copied into the world by `World::create_mesh`. [`Default`] (the
/// C default: no data) is refused as `InvalidMesh`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MeshDesc<'a> {
    /// Vertices (x, y, z) in the mesh's frame. Finite, within 1e15.
    pub vertices: &'a [[f64; 3]],
    /// Triangles as vertex indices, each < `vertices.len()`; at least one.
    pub triangles: &'a [[u32; 3]],
}

impl<'a> MeshDesc<'a> {
    pub fn new(vertices: &'a [[f64; 3]], triangles: &'a [[u32; 3]]) -> MeshDesc<'a> {
        MeshDesc {
            vertices,
            triangles,
        }
    }
}

/// A body: `hgcd_body_desc` without its size and init tag. [`Default`] is
/// `hgcd_body_desc_default()` (null mesh, which is refused: set `mesh`, or
/// use [`BodyDesc::new`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyDesc {
    /// The shape: a live mesh of the same world.
    pub mesh: MeshId,
    /// Position of the mesh frame's origin. Finite, |x| <= 1e15.
    pub position: [f64; 3],
    /// Orientation quaternion (x, y, z, w), unit length within 1e-6; used
    /// exactly as given (not normalised).
    pub orientation: [f64; 4],
    /// Velocity used by `World::step`. Finite.
    pub velocity: [f64; 3],
    /// Uniform scale of the mesh, finite and > 0.
    pub scale: f64,
    /// Opaque value returned by `World::body_user_data`.
    pub user_data: u64,
    /// How the body moves, and which of its pairs are considered.
    pub body_type: BodyType,
    /// Whether it takes part in detection (default true).
    pub enabled: bool,
    /// Which bodies it may collide with.
    pub filter: Filter,
    /// The body's own contact margin, added to the world's and the other
    /// body's ([`WorldDesc::contact_margin`]). Finite, >= 0, <= 1e15.
    pub margin: f64,
}

impl Default for BodyDesc {
    fn default() -> BodyDesc {
        // SAFETY: no arguments, returns a plain struct by value.
        let d = unsafe { sys::hgcd_body_desc_default() };
        BodyDesc {
            mesh: MeshId(d.mesh),
            position: d.position,
            orientation: d.orientation,
            velocity: d.velocity,
            scale: d.scale,
            user_data: d.user_data,
            body_type: BodyType::from_raw(d.type_),
            enabled: d.enabled != 0,
            filter: Filter::from_raw(&d.filter),
            margin: d.margin,
        }
    }
}

impl BodyDesc {
    /// The default descriptor for a body of `mesh`.
    pub fn new(mesh: MeshId) -> BodyDesc {
        BodyDesc {
            mesh,
            ..BodyDesc::default()
        }
    }

    /// The C descriptor, from `hgcd_body_desc_default()` plus every field.
    pub fn to_raw(&self) -> sys::hgcd_body_desc {
        // SAFETY: as in `default`.
        let mut d = unsafe { sys::hgcd_body_desc_default() };
        d.mesh = self.mesh.0;
        d.position = self.position;
        d.orientation = self.orientation;
        d.velocity = self.velocity;
        d.scale = self.scale;
        d.user_data = self.user_data;
        d.type_ = self.body_type.to_raw();
        d.enabled = u32::from(self.enabled);
        d.filter = self.filter.to_raw();
        d.margin = self.margin;
        d
    }
}

/// A body's position and orientation quaternion (x, y, z, w).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    pub position: [f64; 3],
    pub orientation: [f64; 4],
}

/// What hgcd worked out about a mesh (`hgcd_mesh_info`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MeshInfo {
    pub vertex_count: u32,
    pub triangle_count: u32,
    /// Every edge is shared by an even number of triangles (bounds a volume).
    pub closed: bool,
    /// Closed, and every vertex lies on or behind every face plane.
    pub convex: bool,
    /// Connected components (via shared vertices).
    pub component_count: u32,
    /// Zero-area triangles.
    pub degenerate_triangle_count: u32,
    /// Live bodies using the mesh.
    pub body_count: u32,
    /// Bounding sphere in the mesh frame.
    pub center: [f64; 3],
    pub radius: f64,
    /// The narrow phase set for the mesh (`NarrowPhase::World` by default).
    pub narrow_phase_setting: NarrowPhase,
    /// The test the mesh's pairs get now: the setting or the world's, and
    /// `Exact` for a mesh that is not convex.
    pub narrow_phase: NarrowPhase,
    /// The largest norm of a used vertex: a body needs `scale * reach <= 1e15`.
    pub reach: f64,
}

impl From<&sys::hgcd_mesh_info> for MeshInfo {
    fn from(i: &sys::hgcd_mesh_info) -> MeshInfo {
        MeshInfo {
            vertex_count: i.vertex_count,
            triangle_count: i.triangle_count,
            closed: i.closed != 0,
            convex: i.convex != 0,
            component_count: i.component_count,
            degenerate_triangle_count: i.degenerate_triangle_count,
            body_count: i.body_count,
            center: i.center,
            radius: i.radius,
            narrow_phase_setting: NarrowPhase::from_raw(i.narrow_phase_setting),
            narrow_phase: NarrowPhase::from_raw(i.narrow_phase),
            reach: i.reach,
        }
    }
}

/// Statistics of the last step/detect (`hgcd_stats` without its size).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stats {
    /// Grid levels in use and bodies in the oversize set.
    pub level_count: u32,
    pub oversize_count: u32,
    pub thread_count: u32,
    /// Bodies that changed grid cell in the last update.
    pub moved_bodies: u64,
    /// Pairs whose axis-aligned boxes overlap (broad-phase output; see
    /// `hgcd_stats.candidate_pairs` in hgcd.h).
    pub candidate_pairs: u64,
    /// Candidate pairs that reached the exact test.
    pub narrow_tests: u64,
    /// Triangle-triangle tests performed.
    pub triangle_tests: u64,
    /// Colliding pairs, and those of them found by containment alone.
    pub colliding_pairs: u64,
    pub containment_pairs: u64,
    /// Wall-clock seconds per phase and in total.
    pub motion_seconds: f64,
    pub update_seconds: f64,
    pub broad_seconds: f64,
    pub narrow_seconds: f64,
    pub total_seconds: f64,
    /// Candidate pairs decided by libccd.
    pub libccd_tests: u64,
    /// Candidate pairs whose meshes asked for libccd, one of them not
    /// convex: tested exactly instead.
    pub libccd_fallback_tests: u64,
    /// Pairs whose answer is the previous detect's (temporal coherence:
    /// neither body's pose changed since); when the search ran around the
    /// moved bodies alone, those of them that collide.
    pub unmoved_pairs: u64,
    /// Bodies the broad phase searched pairs for: every live body, or, when
    /// few moved since the previous detect, those created or moved since
    /// alone; 0 when none was.
    pub searched_bodies: u64,
    /// Candidate pairs dropped before the narrow phase by body types,
    /// filters or excluded pairs.
    pub filtered_pairs: u64,
    /// Seconds finding the began and ended pairs.
    pub events_seconds: f64,
}

impl From<&sys::hgcd_stats> for Stats {
    fn from(s: &sys::hgcd_stats) -> Stats {
        Stats {
            level_count: s.level_count,
            oversize_count: s.oversize_count,
            thread_count: s.thread_count,
            moved_bodies: s.moved_bodies,
            candidate_pairs: s.candidate_pairs,
            narrow_tests: s.narrow_tests,
            triangle_tests: s.triangle_tests,
            colliding_pairs: s.colliding_pairs,
            containment_pairs: s.containment_pairs,
            motion_seconds: s.motion_seconds,
            update_seconds: s.update_seconds,
            broad_seconds: s.broad_seconds,
            narrow_seconds: s.narrow_seconds,
            total_seconds: s.total_seconds,
            libccd_tests: s.libccd_tests,
            libccd_fallback_tests: s.libccd_fallback_tests,
            unmoved_pairs: s.unmoved_pairs,
            searched_bodies: s.searched_bodies,
            filtered_pairs: s.filtered_pairs,
            events_seconds: s.events_seconds,
        }
    }
}

/// Which test decides a pair (`enum hgcd_narrow_phase`). `Gjk` and `Mpr` use
/// libccd on convex meshes, with a tolerance (see hgcd.h); they need a library
/// built with libccd ([`crate::libccd_precision`]), else `NotSupported`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum NarrowPhase {
    /// Per mesh only: follow the world's setting.
    World,
    /// The exact test (the default).
    #[default]
    Exact,
    /// libccd's GJK (EPA for contacts).
    Gjk,
    /// libccd's Minkowski portal refinement.
    Mpr,
    /// A value this crate does not know (from a newer library).
    Unknown(i32),
}

impl NarrowPhase {
    pub fn from_raw(v: i32) -> NarrowPhase {
        match v {
            sys::HGCD_NARROW_WORLD => NarrowPhase::World,
            sys::HGCD_NARROW_EXACT => NarrowPhase::Exact,
            sys::HGCD_NARROW_GJK => NarrowPhase::Gjk,
            sys::HGCD_NARROW_MPR => NarrowPhase::Mpr,
            other => NarrowPhase::Unknown(other),
        }
    }

    pub fn to_raw(self) -> i32 {
        match self {
            NarrowPhase::World => sys::HGCD_NARROW_WORLD,
            NarrowPhase::Exact => sys::HGCD_NARROW_EXACT,
            NarrowPhase::Gjk => sys::HGCD_NARROW_GJK,
            NarrowPhase::Mpr => sys::HGCD_NARROW_MPR,
            NarrowPhase::Unknown(v) => v,
        }
    }
}

/// How many of its threads a world's detects use (`enum hgcd_thread_policy`).
/// The pairs never depend on it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ThreadPolicy {
    /// All `thread_count` threads while they get the cores; fewer while they
    /// are descheduled (other busy processes on the cores), measured per
    /// detect, with the larger count tried again now and then (see hgcd.h).
    #[default]
    Adaptive,
    /// Always `thread_count` threads.
    Fixed,
    /// A value this crate does not know (from a newer library).
    Unknown(i32),
}

impl ThreadPolicy {
    pub fn from_raw(v: i32) -> ThreadPolicy {
        match v {
            v if v == sys::HGCD_THREADS_ADAPTIVE as i32 => ThreadPolicy::Adaptive,
            v if v == sys::HGCD_THREADS_FIXED as i32 => ThreadPolicy::Fixed,
            other => ThreadPolicy::Unknown(other),
        }
    }

    pub fn to_raw(self) -> i32 {
        match self {
            ThreadPolicy::Adaptive => sys::HGCD_THREADS_ADAPTIVE as i32,
            ThreadPolicy::Fixed => sys::HGCD_THREADS_FIXED as i32,
            ThreadPolicy::Unknown(v) => v,
        }
    }
}

/// What a colliding pair is made of (`hgcd_contact`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ContactKind {
    /// The surfaces meet: this triangle of a's mesh and this one of b's.
    Surface { triangle_a: u32, triangle_b: u32 },
    /// Surfaces apart; a's closed mesh holds (a component of) b.
    AContainsB,
    /// Surfaces apart; b's closed mesh holds (a component of) a.
    BContainsA,
    /// Decided by libccd: moving b by `depth` along the unit `normal`
    /// separates the hulls; `point` is libccd's contact position.
    Penetration {
        depth: f64,
        normal: [f64; 3],
        point: [f64; 3],
    },
    /// The solids are apart but within the pair's contact margin: this
    /// triangle of a's mesh is within the margin of this one of b's.
    Near { triangle_a: u32, triangle_b: u32 },
    /// A kind this crate does not know (from a newer library).
    Unknown(i32),
}

/// One colliding pair and what it is made of.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    pub pair: Pair,
    pub kind: ContactKind,
}

impl From<&sys::hgcd_contact> for Contact {
    fn from(c: &sys::hgcd_contact) -> Contact {
        let kind = match c.kind as u32 {
            sys::HGCD_CONTACT_SURFACE => ContactKind::Surface {
                triangle_a: c.triangle_a,
                triangle_b: c.triangle_b,
            },
            sys::HGCD_CONTACT_NEAR => ContactKind::Near {
                triangle_a: c.triangle_a,
                triangle_b: c.triangle_b,
            },
            sys::HGCD_CONTACT_A_CONTAINS_B => ContactKind::AContainsB,
            sys::HGCD_CONTACT_B_CONTAINS_A => ContactKind::BContainsA,
            sys::HGCD_CONTACT_PENETRATION => ContactKind::Penetration {
                depth: c.depth,
                normal: c.normal,
                point: c.point,
            },
            _ => ContactKind::Unknown(c.kind),
        };
        Contact {
            pair: Pair::from(c.pair),
            kind,
        }
    }
}
