//! CPU ground truth: is a surface point lit, by casting a ray toward the light through all triangles.

use glam::DVec3;
use parry3d_f64::query::{Ray, RayCast};
use parry3d_f64::shape::TriMesh;

use crate::error::RenderError;
use crate::scene::Scene;
use crate::types::LightSpec;

/// Per-pixel classification of the light reaching a visible surface point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum Visibility {
    /// No geometry under the pixel.
    Background = 0,
    /// The ray to the light is unobstructed.
    Lit = 1,
    /// Some triangle blocks the ray to the light.
    Occluded = 2,
    /// The surface faces away from the light (shadowed by itself).
    BackFacing = 3,
    /// Outside a spot light's pyramid.
    OutsideSpot = 4,
}

impl Visibility {
    pub fn is_lit(self) -> bool {
        self == Visibility::Lit
    }

    /// Whether a shadow can show here: a surface the light would reach
    /// but for what stands in its way (lit or occluded), not one facing
    /// away from the light or outside a spot's pyramid, whatever a map
    /// answers there.
    pub fn shows_shadow(self) -> bool {
        matches!(self, Visibility::Lit | Visibility::Occluded)
    }
}

/// All scene triangles in a BVH, in f64.
pub struct GroundTruth {
    mesh: TriMesh,
    /// [`Scene::surface_offset`]: how far off its surface a point is decided.
    offset: f64,
    extent: f64,
}

impl GroundTruth {
    pub fn new(scene: &Scene) -> Result<GroundTruth, RenderError> {
        let vertices: Vec<DVec3> = scene.vertices.iter().map(|v| glam::Vec3::from(v.position).as_dvec3()).collect();
        let indices: Vec<[u32; 3]> = scene.indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
        let mesh = TriMesh::new(vertices, indices).map_err(|e| RenderError::GroundTruth(format!("{e:?}")))?;
        Ok(GroundTruth { mesh, offset: scene.surface_offset(), extent: scene.bounds.diagonal() })
    }

    /// [`Scene::surface_offset`] of the scene this truth was built for.
    pub fn surface_offset(&self) -> f64 {
        self.offset
    }

    /// Whether anything blocks the light from `p`, whose unit normal `n` faces the viewer: the
    /// ray starts at `p` lifted off its surface by the surface offset, where the main pass looks
    /// `p` up too.
    pub fn classify(&self, p: DVec3, n: DVec3, light: &LightSpec) -> Visibility {
        self.classify_lifted(p + n * self.offset, n, light)
    }

    /// As [`GroundTruth::classify`] for a point `origin` already lifted off its surface (unit
    /// normal `n`): the ray starts at `origin` itself.
    pub fn classify_lifted(&self, origin: DVec3, n: DVec3, light: &LightSpec) -> Visibility {
        if !light.in_spot(origin) {
            return Visibility::OutsideSpot;
        }
        let (l, dist) = light.toward_light(origin);
        if n.dot(l) <= 0.0 {
            return Visibility::BackFacing;
        }
        let max_t = if dist.is_finite() {
            // Stop just short of a point light: nothing behind it can shadow.
            (dist - self.offset).max(0.0)
        } else {
            // Far enough to leave the scene box from anywhere inside it.
            2.0 * self.extent + 2.0 * origin.abs().max_element() + 1.0
        };
        if self.mesh.intersects_local_ray(&Ray::new(origin, l), max_t) {
            Visibility::Occluded
        } else {
            Visibility::Lit
        }
    }

    /// Classifies every pixel. `world[i].w == 0` marks background; `normal` is the camera-facing
    /// unit normal. Runs on all cores.
    pub fn classify_image(&self, world: &[[f32; 4]], normal: &[[f32; 4]], light: &LightSpec) -> Vec<Visibility> {
        let n = world.len();
        let mut out = vec![Visibility::Background; n];
        let threads = std::thread::available_parallelism().map(|t| t.get()).unwrap_or(1).clamp(1, 64);
        let chunk = n.div_ceil(threads).max(1);
        std::thread::scope(|s| {
            for (k, slot) in out.chunks_mut(chunk).enumerate() {
                let start = k * chunk;
                s.spawn(move || {
                    for (j, v) in slot.iter_mut().enumerate() {
                        let w = world[start + j];
                        if w[3] == 0.0 {
                            continue;
                        }
                        let p = DVec3::new(w[0] as f64, w[1] as f64, w[2] as f64);
                        let nn = normal[start + j];
                        let nrm = DVec3::new(nn[0] as f64, nn[1] as f64, nn[2] as f64).normalize_or_zero();
                        *v = self.classify(p, nrm, light);
                    }
                });
            }
        });
        out
    }
}
