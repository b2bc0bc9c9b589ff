//! Scene data: one shared triangle list, objects as index ranges, camera, light and bounds.

use std::sync::{Arc, OnceLock};

use glam::{DVec3, Vec3};

use crate::error::RenderError;
use crate::ground_truth::GroundTruth;
use crate::types::{Bounds, CameraSpec, LightSpec};

/// One vertex as the GPU reads it (16 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Vertex {
    pub position: [f32; 3],
    /// sRGB-ish albedo; alpha is overwritten by the renderer with the object's receiver flag.
    pub color: [u8; 4],
}

/// A drawable unit: a contiguous range of the scene's index list.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneObject {
    pub first_index: u32,
    pub index_count: u32,
    /// Box of the object's vertices (for caster culling).
    pub aabb: Bounds,
    /// Whether aliasing statistics count this object's pixels.
    pub receiver: bool,
}

/// A static scene: triangles, objects, default camera and light.
pub struct Scene {
    pub name: String,
    pub vertices: Vec<Vertex>,
    /// Triangle list; every object is a contiguous range of it.
    pub indices: Vec<u32>,
    pub objects: Vec<SceneObject>,
    pub camera: CameraSpec,
    pub light: LightSpec,
    /// Box of all vertices.
    pub bounds: Bounds,
    ground_truth: OnceLock<Arc<GroundTruth>>,
}

impl std::fmt::Debug for Scene {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Scene")
            .field("name", &self.name)
            .field("vertices", &self.vertices.len())
            .field("triangles", &(self.indices.len() / 3))
            .field("objects", &self.objects.len())
            .field("camera", &self.camera)
            .field("light", &self.light)
            .field("bounds", &self.bounds)
            .finish()
    }
}

impl Scene {
    /// How far off its surface, along the normal on the side the camera sees, a visible point is
    /// decided lit or shadowed: by the ground truth (its ray starts there) and by the main pass
    /// (its shadow lookup is made there), so that both judge the same point.
    ///
    /// NOTE: the world position read back from the GPU is an f32 interpolation of f32 vertices; its
    /// error is a few ulps of the *vertex* coordinates (not of the point's own, which may be near
    /// 0 on a large triangle), i.e. bounded by a few ulps of the scene's largest coordinate M. A
    /// ray started exactly there may begin just below its own surface and hit it (false shadow),
    /// or graze a coplanar neighbour. Moving the point M·2⁻¹⁴ (≈ 100 f32 ulps of M) off the
    /// surface clears that error by two orders of magnitude while staying far below a shadow-map
    /// texel in every scene (2 cm on the 700 m board, whose texels are ≈ 0.3–0.7 m at 1024²).
    /// The shadow lookup must use the same point: its receiver-plane reference extends the
    /// receiver's plane to neighbouring texels, and on a curved receiver (the forest's terrain,
    /// its facets 2 m wide) the next facet can rise above that plane by more than the lookup's
    /// tolerance yet less than the offset, where a lookup at the unlifted point shadows a point
    /// whose lifted ray is lit.
    pub fn surface_offset(&self) -> f64 {
        let b = self.bounds;
        b.min.abs().max(b.max.abs()).max_element().max(1e-30) * (1.0 / 16384.0)
    }

    /// Builds a scene, checking indices and object ranges and computing bounds and object boxes.
    /// `objects` give (first_index, index_count, receiver).
    pub fn new(
        name: impl Into<String>,
        vertices: Vec<Vertex>,
        indices: Vec<u32>,
        objects: &[(u32, u32, bool)],
        camera: CameraSpec,
        light: LightSpec,
    ) -> Result<Scene, RenderError> {
        let name = name.into();
        if !indices.len().is_multiple_of(3) {
            return Err(RenderError::invalid("scene indices", "length is not a multiple of 3"));
        }
        if let Some(&bad) = indices.iter().find(|&&i| i as usize >= vertices.len()) {
            return Err(RenderError::invalid("scene indices", format!("index {bad} ≥ vertex count {}", vertices.len())));
        }
        if vertices.iter().any(|v| v.position.iter().any(|c| !c.is_finite())) {
            return Err(RenderError::NonFinite { what: format!("a vertex position of scene '{name}'") });
        }
        camera.validate()?;
        light.validate()?;
        let mut objs = Vec::with_capacity(objects.len());
        let mut bounds = Bounds::EMPTY;
        for (k, &(first, count, receiver)) in objects.iter().enumerate() {
            let end = first as u64 + count as u64;
            if count % 3 != 0 || first % 3 != 0 || end > indices.len() as u64 {
                return Err(RenderError::invalid(
                    format!("scene object {k}"),
                    format!("range {first}..{end} is not whole triangles within {} indices", indices.len()),
                ));
            }
            let mut aabb = Bounds::EMPTY;
            for &i in &indices[first as usize..end as usize] {
                aabb.grow(Vec3::from(vertices[i as usize].position).as_dvec3());
            }
            bounds = bounds.union(&aabb);
            objs.push(SceneObject { first_index: first, index_count: count, aabb, receiver });
        }
        if bounds.is_empty() {
            return Err(RenderError::invalid("scene", format!("'{name}' has no triangles")));
        }
        Ok(Scene { name, vertices, indices, objects: objs, camera, light, bounds, ground_truth: OnceLock::new() })
    }

    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// The ray-casting structure over all triangles, built on first use and kept.
    pub fn ground_truth(&self) -> Result<Arc<GroundTruth>, RenderError> {
        if let Some(g) = self.ground_truth.get() {
            return Ok(g.clone());
        }
        let g = Arc::new(GroundTruth::new(self)?);
        Ok(self.ground_truth.get_or_init(|| g).clone())
    }

    /// Every object index: the "draw everything" caster list.
    pub fn all_objects(&self) -> Vec<u32> {
        (0..self.objects.len() as u32).collect()
    }

    /// Indices of receiver objects.
    pub fn receivers(&self) -> Vec<u32> {
        (0..self.objects.len() as u32).filter(|&i| self.objects[i as usize].receiver).collect()
    }
}

/// Accumulates triangles object by object. Used by the procedural scenes and the glTF loader.
#[derive(Default)]
pub(crate) struct MeshBuilder {
    pub vertices: Vec<Vertex>,
    pub indices: Vec<u32>,
    pub objects: Vec<(u32, u32, bool)>,
    open: Option<(u32, bool)>,
}

impl MeshBuilder {
    pub fn begin(&mut self, receiver: bool) {
        self.end();
        self.open = Some((self.indices.len() as u32, receiver));
    }

    pub fn end(&mut self) {
        if let Some((first, receiver)) = self.open.take() {
            let count = self.indices.len() as u32 - first;
            if count > 0 {
                self.objects.push((first, count, receiver));
            }
        }
    }

    pub fn vertex(&mut self, p: DVec3, color: [u8; 3]) -> u32 {
        self.vertices.push(Vertex { position: p.as_vec3().to_array(), color: [color[0], color[1], color[2], 255] });
        self.vertices.len() as u32 - 1
    }

    pub fn tri(&mut self, a: u32, b: u32, c: u32) {
        self.indices.extend_from_slice(&[a, b, c]);
    }

    pub fn quad(&mut self, p: [DVec3; 4], color: [u8; 3]) {
        let v: Vec<u32> = p.iter().map(|&q| self.vertex(q, color)).collect();
        self.tri(v[0], v[1], v[2]);
        self.tri(v[0], v[2], v[3]);
    }

    /// Axis-aligned box from `min` to `max`.
    pub fn cuboid(&mut self, min: DVec3, max: DVec3, color: [u8; 3]) {
        self.oriented_box(0.5 * (min + max), 0.5 * (max - min), DVec3::X, DVec3::Z, color);
    }

    /// Box with centre `c`, half extents `h` along (ax, up, ax × up)… expressed as local x = `ax`,
    /// local y = world up, local z = `az` (both horizontal, orthonormal).
    pub fn oriented_box(&mut self, c: DVec3, h: DVec3, ax: DVec3, az: DVec3, color: [u8; 3]) {
        let ay = DVec3::Y;
        let base = self.vertices.len() as u32;
        for k in 0..8u32 {
            let sx = if k & 1 == 0 { -h.x } else { h.x };
            let sy = if k & 2 == 0 { -h.y } else { h.y };
            let sz = if k & 4 == 0 { -h.z } else { h.z };
            self.vertex(c + ax * sx + ay * sy + az * sz, color);
        }
        // Faces as corner-index quads; winding does not matter (no culling, normals from derivatives).
        const FACES: [[u32; 4]; 6] = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]];
        for f in FACES {
            self.tri(base + f[0], base + f[1], base + f[2]);
            self.tri(base + f[0], base + f[2], base + f[3]);
        }
    }

    /// Surface of revolution about the vertical axis through `base`: `profile` is (radius, height)
    /// from bottom to top; a zero radius closes the surface at that height.
    pub fn lathe(&mut self, base: DVec3, profile: &[(f64, f64)], segments: u32, color: [u8; 3]) {
        let ring0 = self.vertices.len() as u32;
        let n = segments.max(3);
        for &(r, y) in profile {
            for s in 0..n {
                let a = std::f64::consts::TAU * s as f64 / n as f64;
                self.vertex(base + DVec3::new(r * a.cos(), y, r * a.sin()), color);
            }
        }
        for k in 0..profile.len().saturating_sub(1) as u32 {
            // A ring of radius 0 is a point: emit only the non-degenerate triangle of each quad.
            let (r0, r1) = (profile[k as usize].0, profile[k as usize + 1].0);
            for s in 0..n {
                let (a, b) = (ring0 + k * n + s, ring0 + k * n + (s + 1) % n);
                let (c, d) = (a + n, b + n);
                if r0 > 0.0 {
                    self.tri(a, b, d);
                }
                if r1 > 0.0 {
                    self.tri(a, d, c);
                }
            }
        }
        // Caps: fans on the first and last rings where the radius is not already zero.
        for (k, (r, _)) in [(0usize, profile[0]), (profile.len() - 1, profile[profile.len() - 1])] {
            if r > 0.0 {
                let ring = ring0 + k as u32 * n;
                for s in 1..n - 1 {
                    self.tri(ring, ring + s, ring + s + 1);
                }
            }
        }
    }

    /// Height field over [x0, x1] × [z0, z1] with `nx` × `nz` cells.
    #[allow(clippy::too_many_arguments)]
    pub fn heightfield(
        &mut self,
        x0: f64,
        z0: f64,
        x1: f64,
        z1: f64,
        nx: u32,
        nz: u32,
        height: impl Fn(f64, f64) -> f64,
        color: impl Fn(f64, f64, f64) -> [u8; 3],
    ) {
        let base = self.vertices.len() as u32;
        for j in 0..=nz {
            for i in 0..=nx {
                let x = x0 + (x1 - x0) * i as f64 / nx as f64;
                let z = z0 + (z1 - z0) * j as f64 / nz as f64;
                let y = height(x, z);
                self.vertex(DVec3::new(x, y, z), color(x, y, z));
            }
        }
        let w = nx + 1;
        for j in 0..nz {
            for i in 0..nx {
                let a = base + j * w + i;
                self.tri(a, a + 1, a + w + 1);
                self.tri(a, a + w + 1, a + w);
            }
        }
    }
}
