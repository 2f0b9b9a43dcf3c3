//! The reference scenes of docs/scenes.md (`hgcd_scene_tetra_*`), generated bit
//! for bit by the C library.

use hgcd_sys as sys;

use crate::error::{Error, ErrorKind, Result};
use crate::types::{BodyDesc, BodyId, MeshDesc, MeshId, WorldDesc};
use crate::world::World;

/// Parameters of scene `tetra` (`hgcd_scene_tetra_desc`). [`Default`] is
/// `hgcd_scene_tetra_desc_default()`: n = 750000, seed 1, side 200, radii
/// 0.25..2, speed 0.05.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TetraDesc {
    /// Number of tetrahedra.
    pub n: u64,
    /// splitmix64 seed.
    pub seed: u64,
    /// Cube side.
    pub side: f64,
    /// Circumradius range, log-uniform.
    pub rmin: f64,
    pub rmax: f64,
    /// Speed bound per tick.
    pub vmax: f64,
}

impl Default for TetraDesc {
    fn default() -> TetraDesc {
        // SAFETY: returns a plain struct.
        let d = unsafe { sys::hgcd_scene_tetra_desc_default() };
        TetraDesc {
            n: d.n,
            seed: d.seed,
            side: d.side,
            rmin: d.rmin,
            rmax: d.rmax,
            vmax: d.vmax,
        }
    }
}

impl TetraDesc {
    /// The default scene with `n` objects and `seed`.
    pub fn new(n: u64, seed: u64) -> TetraDesc {
        TetraDesc {
            n,
            seed,
            ..TetraDesc::default()
        }
    }

    /// The C descriptor (size and init tag from the C default).
    pub fn to_raw(&self) -> sys::hgcd_scene_tetra_desc {
        // SAFETY: returns a plain struct.
        let mut d = unsafe { sys::hgcd_scene_tetra_desc_default() };
        d.n = self.n;
        d.seed = self.seed;
        d.side = self.side;
        d.rmin = self.rmin;
        d.rmax = self.rmax;
        d.vmax = self.vmax;
        d
    }

    /// Draws the scene (`hgcd_scene_tetra_generate`).
    pub fn generate(&self) -> Result<TetraScene> {
        generate(self)
    }

    /// The world descriptor the reference scene runs in: reflection at the
    /// cube [0, side]^3, time step 1, `thread_count` threads (0 = all).
    pub fn world_desc(&self, thread_count: u32) -> WorldDesc {
        WorldDesc {
            thread_count,
            reflect_at_bounds: true,
            time_step: 1.0,
            bounds_min: [0.0; 3],
            bounds_max: [self.side; 3],
            ..WorldDesc::default()
        }
    }
}

/// The n objects of a tetra scene, one entry per object.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TetraScene {
    pub centers: Vec<[f64; 3]>,
    /// Circumradius r.
    pub radii: Vec<f64>,
    /// r / sqrt(3): the body scale for [`unit_mesh`].
    pub scales: Vec<f64>,
    /// Quaternions (x, y, z, w).
    pub orientations: Vec<[f64; 4]>,
    pub velocities: Vec<[f64; 3]>,
}

fn alloc<T: Copy>(n: usize, zero: T) -> Result<Vec<T>> {
    let mut v = Vec::new();
    v.try_reserve_exact(n).map_err(|_| {
        Error::new(
            ErrorKind::OutOfMemory,
            format!("scene_tetra_generate: cannot allocate {n} entries"),
        )
    })?;
    v.resize(n, zero);
    Ok(v)
}

/// Draws the n objects of scene `tetra` (`hgcd_scene_tetra_generate`).
pub fn generate(desc: &TetraDesc) -> Result<TetraScene> {
    let n = usize::try_from(desc.n)
        .ok()
        .filter(|n| n.checked_mul(4 * std::mem::size_of::<f64>()).is_some())
        .ok_or_else(|| {
            Error::new(
                ErrorKind::Capacity,
                format!("scene_tetra_generate: n = {} is too large", desc.n),
            )
        })?;
    let mut s = TetraScene {
        centers: alloc(n, [0.0; 3])?,
        radii: alloc(n, 0.0)?,
        scales: alloc(n, 0.0)?,
        orientations: alloc(n, [0.0; 4])?,
        velocities: alloc(n, [0.0; 3])?,
    };
    let d = desc.to_raw();
    // SAFETY: each array holds n entries of the documented width
    // ([[f64; K]] is contiguous f64s).
    let status = unsafe {
        sys::hgcd_scene_tetra_generate(
            &d,
            s.centers.as_mut_ptr().cast::<f64>(),
            s.radii.as_mut_ptr(),
            s.scales.as_mut_ptr(),
            s.orientations.as_mut_ptr().cast::<f64>(),
            s.velocities.as_mut_ptr().cast::<f64>(),
        )
    };
    if status != sys::HGCD_OK {
        return Err(Error::from_status(
            status,
            "scene_tetra_generate: invalid scene parameters",
        ));
    }
    Ok(s)
}

/// The unit sign-pattern tetrahedron (`hgcd_scene_tetra_unit_mesh`):
/// vertices (1,1,1), (1,-1,-1), (-1,1,-1), (-1,-1,1) and faces (0,1,2)
/// (0,3,1) (0,2,3) (1,3,2).
pub fn unit_mesh() -> ([[f64; 3]; 4], [[u32; 3]; 4]) {
    let mut v = [[0.0f64; 3]; 4];
    let mut t = [[0u32; 3]; 4];
    // SAFETY: 12 doubles and 12 indices, as the header asks.
    unsafe {
        sys::hgcd_scene_tetra_unit_mesh(v.as_mut_ptr().cast::<f64>(), t.as_mut_ptr().cast::<u32>())
    };
    (v, t)
}

/// One tick of the scene's own motion (`hgcd_scene_tetra_move`), for callers
/// that move bodies themselves: center += velocity, mirrored into [0, side].
/// The two slices must have the same length (else `InvalidArgument`).
pub fn move_tick(side: f64, centers: &mut [[f64; 3]], velocities: &mut [[f64; 3]]) -> Result<()> {
    if centers.len() != velocities.len() {
        return Err(Error::new(
            ErrorKind::InvalidArgument,
            format!(
                "scene_tetra_move: {} centers but {} velocities",
                centers.len(),
                velocities.len()
            ),
        ));
    }
    // SAFETY: both arrays hold n entries of 3 doubles.
    unsafe {
        sys::hgcd_scene_tetra_move(
            centers.len() as u64,
            side,
            centers.as_mut_ptr().cast::<f64>(),
            velocities.as_mut_ptr().cast::<f64>(),
        )
    };
    Ok(())
}

impl TetraScene {
    /// Number of objects.
    pub fn len(&self) -> usize {
        self.centers.len()
    }

    pub fn is_empty(&self) -> bool {
        self.centers.is_empty()
    }

    /// Adds the unit mesh and one body per object (in order, so on a fresh
    /// world body i has index i), with scale, orientation and velocity from
    /// the scene and `user_data` = i.
    pub fn populate(&self, world: &mut World) -> Result<(MeshId, Vec<BodyId>)> {
        let (v, t) = unit_mesh();
        let mesh = world.create_mesh(&MeshDesc::new(&v, &t))?;
        let mut bodies = Vec::new();
        bodies.try_reserve_exact(self.len()).map_err(|_| {
            Error::new(
                ErrorKind::OutOfMemory,
                "populate: cannot allocate the body ids",
            )
        })?;
        let mut desc = BodyDesc::new(mesh);
        for i in 0..self.len() {
            desc.position = self.centers[i];
            desc.orientation = self.orientations[i];
            desc.velocity = self.velocities[i];
            desc.scale = self.scales[i];
            desc.user_data = i as u64;
            bodies.push(world.create_body(&desc)?);
        }
        Ok((mesh, bodies))
    }
}

/// A fresh world holding scene `desc` as the reference runs it
/// ([`TetraDesc::world_desc`]), body i at index i.
pub fn tetra_world(desc: &TetraDesc, thread_count: u32) -> Result<World> {
    let scene = desc.generate()?;
    let mut world = World::new(&desc.world_desc(thread_count))?;
    scene.populate(&mut world)?;
    Ok(world)
}
