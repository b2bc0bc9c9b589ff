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
}

/// All scene triangles in a BVH, in f64.
pub struct GroundTruth {
    mesh: TriMesh,
    /// Largest absolute coordinate in the scene, for the ray-origin offset.
    magnitude: f64,
    extent: f64,
}

impl GroundTruth {
    pub fn new(scene: &Scene) -> Result<GroundTruth, RenderError> {
        let vertices: Vec<DVec3> = scene.vertices.iter().map(|v| glam::Vec3::from(v.position).as_dvec3()).collect();
        let indices: Vec<[u32; 3]> = scene.indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
        let mesh = TriMesh::new(vertices, indices).map_err(|e| RenderError::GroundTruth(format!("{e:?}")))?;
        let b = scene.bounds;
        let magnitude = b.min.abs().max(b.max.abs()).max_element();
        Ok(GroundTruth { mesh, magnitude, extent: b.diagonal() })
    }

    /// Offset of ray origins along the surface normal.
    ///
    /// NOTE: the world position read back from the GPU is an f32 interpolation of f32 vertices; its
    /// error is a few ulps of the *vertex* coordinates (not of the point's own, which may be near
    /// 0 on a large triangle), i.e. bounded by a few ulps of the scene's largest coordinate M. A
    /// ray started exactly there may begin just below its own surface and hit it (false shadow),
    /// or graze a coplanar neighbour. Moving the origin M·2⁻¹⁴ (≈ 100 f32 ulps of M) off the
    /// surface, on the side the camera sees, clears that error by two orders of magnitude while
    /// staying far below a shadow-map texel in every scene (2 cm on the 700 m board, whose texels
    /// are ≈ 0.3–0.7 m at 1024²).
    pub fn ray_offset(&self) -> f64 {
        self.magnitude.max(1e-30) * (1.0 / 16384.0)
    }

    /// Whether anything blocks the light from `p`, whose unit normal `n` faces the viewer.
    pub fn classify(&self, p: DVec3, n: DVec3, light: &LightSpec) -> Visibility {
        if !light.in_spot(p) {
            return Visibility::OutsideSpot;
        }
        let (l, dist) = light.toward_light(p);
        if n.dot(l) <= 0.0 {
            return Visibility::BackFacing;
        }
        let eps = self.ray_offset();
        let origin = p + n * eps;
        let max_t = if dist.is_finite() {
            // Stop just short of a point light: nothing behind it can shadow.
            (dist - eps).max(0.0)
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
