//! Loading glTF 2.0 scenes (.gltf with external or embedded buffers, .glb), with the camera node
//! and the `KHR_lights_punctual` light, node transforms composed down the node tree.

use std::path::{Path, PathBuf};

use glam::{DMat4, DVec3, Mat4};

use crate::error::RenderError;
use crate::scene::{MeshBuilder, Scene};
use crate::types::{Bounds, CameraSpec, LightSpec};

/// What a loaded file supplied and what was filled in.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GltfReport {
    pub camera_from_file: bool,
    pub light_from_file: bool,
    pub primitives: usize,
    /// Primitives skipped because they are points or lines.
    pub skipped_primitives: usize,
}

fn gerr(path: &Path, reason: impl Into<String>) -> RenderError {
    RenderError::Gltf { path: path.to_path_buf(), reason: reason.into() }
}

/// Standard base64 (RFC 4648), whitespace ignored.
fn base64_decode(s: &str) -> Option<Vec<u8>> {
    let mut out = Vec::with_capacity(s.len() * 3 / 4);
    let (mut acc, mut bits) = (0u32, 0u32);
    for c in s.bytes() {
        let v = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' | b'-' => 62,
            b'/' | b'_' => 63,
            b'=' => break,
            b' ' | b'\n' | b'\r' | b'\t' => continue,
            _ => return None,
        };
        acc = (acc << 6) | v as u32;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    Some(out)
}

/// `%XX` escapes in relative URIs.
fn percent_decode(s: &str) -> String {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' && i + 2 < b.len() {
            if let Ok(v) = u8::from_str_radix(&s[i + 1..i + 3], 16) {
                out.push(v);
                i += 3;
                continue;
            }
        }
        out.push(b[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

fn load_buffers(path: &Path, gltf: &gltf::Gltf) -> Result<Vec<Vec<u8>>, RenderError> {
    let base = path.parent().map(Path::to_path_buf).unwrap_or_else(|| PathBuf::from("."));
    let mut out = Vec::new();
    for buf in gltf.document.buffers() {
        let mut data = match buf.source() {
            gltf::buffer::Source::Bin => gltf.blob.clone().ok_or_else(|| gerr(path, "buffer refers to a missing GLB binary chunk"))?,
            gltf::buffer::Source::Uri(uri) => {
                if let Some(rest) = uri.strip_prefix("data:") {
                    let (_, payload) = rest.split_once(";base64,").ok_or_else(|| gerr(path, "data URI is not base64"))?;
                    base64_decode(payload).ok_or_else(|| gerr(path, "malformed base64 in a data URI"))?
                } else {
                    let p = base.join(percent_decode(uri));
                    std::fs::read(&p).map_err(|source| RenderError::Io { path: p, source })?
                }
            }
        };
        if data.len() < buf.length() {
            return Err(gerr(path, format!("buffer {} has {} bytes, declares {}", buf.index(), data.len(), buf.length())));
        }
        // GLB chunks are padded to 4 bytes; the declared length is what accessors may read.
        data.truncate(buf.length());
        out.push(data);
    }
    Ok(out)
}

fn srgb_u8(linear: f32) -> u8 {
    (linear.clamp(0.0, 1.0).powf(1.0 / 2.2) * 255.0).round() as u8
}

struct Found {
    camera: Option<(DMat4, f64, f64, Option<f64>)>, // world transform, yfov, znear, zfar
    orthographic_camera: bool,
    light: Option<(DMat4, gltf::khr_lights_punctual::Kind, Option<f64>)>,
    primitives: usize,
    skipped: usize,
}

fn visit(
    path: &Path,
    node: gltf::Node,
    parent: DMat4,
    buffers: &[Vec<u8>],
    mb: &mut MeshBuilder,
    found: &mut Found,
    depth: usize,
) -> Result<(), RenderError> {
    if depth > 256 {
        return Err(gerr(path, "node hierarchy deeper than 256 (cycle?)"));
    }
    let local = Mat4::from_cols_array_2d(&node.transform().matrix()).as_dmat4();
    let world = parent * local;
    if let Some(mesh) = node.mesh() {
        for prim in mesh.primitives() {
            let mode = prim.mode();
            if !matches!(mode, gltf::mesh::Mode::Triangles | gltf::mesh::Mode::TriangleStrip | gltf::mesh::Mode::TriangleFan) {
                found.skipped += 1;
                continue;
            }
            let reader = prim.reader(|b| buffers.get(b.index()).map(|v| v.as_slice()));
            let Some(pos) = reader.read_positions() else {
                found.skipped += 1;
                continue;
            };
            let c = prim.material().pbr_metallic_roughness().base_color_factor();
            let color = [srgb_u8(c[0]), srgb_u8(c[1]), srgb_u8(c[2])];
            let base = mb.vertices.len() as u32;
            let mut count = 0u32;
            for p in pos {
                let q = world.transform_point3(glam::Vec3::from(p).as_dvec3());
                mb.vertex(q, color);
                count += 1;
            }
            let idx: Vec<u32> = match reader.read_indices() {
                Some(i) => i.into_u32().collect(),
                None => (0..count).collect(),
            };
            if let Some(&bad) = idx.iter().find(|&&i| i >= count) {
                return Err(gerr(path, format!("mesh {} index {bad} ≥ vertex count {count}", mesh.index())));
            }
            mb.begin(true);
            match mode {
                gltf::mesh::Mode::Triangles => {
                    for t in idx.chunks_exact(3) {
                        mb.tri(base + t[0], base + t[1], base + t[2]);
                    }
                }
                gltf::mesh::Mode::TriangleStrip => {
                    for k in 2..idx.len() {
                        let (a, b) = if k % 2 == 0 { (idx[k - 2], idx[k - 1]) } else { (idx[k - 1], idx[k - 2]) };
                        mb.tri(base + a, base + b, base + idx[k]);
                    }
                }
                _ => {
                    for k in 2..idx.len() {
                        mb.tri(base + idx[0], base + idx[k - 1], base + idx[k]);
                    }
                }
            }
            mb.end();
            found.primitives += 1;
        }
    }
    if found.camera.is_none() && !found.orthographic_camera {
        if let Some(cam) = node.camera() {
            match cam.projection() {
                gltf::camera::Projection::Perspective(p) => {
                    found.camera = Some((world, p.yfov() as f64, p.znear() as f64, p.zfar().map(|f| f as f64)));
                }
                gltf::camera::Projection::Orthographic(_) => found.orthographic_camera = true,
            }
        }
    }
    if found.light.is_none() {
        if let Some(l) = node.light() {
            found.light = Some((world, l.kind(), l.range().map(|r| r as f64)));
        }
    }
    for child in node.children() {
        visit(path, child, world, buffers, mb, found, depth + 1)?;
    }
    Ok(())
}

/// A camera looking at the box from above one corner, for files without one.
pub fn default_camera(bounds: &Bounds) -> CameraSpec {
    let d = bounds.diagonal().max(1e-6);
    let c = bounds.center();
    let eye = c + DVec3::new(0.55, 0.45, 0.75).normalize() * d * 0.9;
    CameraSpec { eye, forward: c - eye, up: DVec3::Y, fovy: 50f64.to_radians(), near: d * 1e-3, far: d * 2.5 }
}

/// A sun from above, for files without a light.
pub fn default_light() -> LightSpec {
    LightSpec::Directional { direction: DVec3::new(0.4, -0.8, 0.3) }
}

/// Loads `path` (.gltf or .glb). The file's first perspective camera and first
/// `KHR_lights_punctual` light (depth-first in the default scene) are used unless overridden;
/// without either, [`default_camera`] / [`default_light`] fill in.
pub fn load_gltf(path: &Path, camera: Option<CameraSpec>, light: Option<LightSpec>) -> Result<(Scene, GltfReport), RenderError> {
    let bytes = std::fs::read(path).map_err(|source| RenderError::Io { path: path.to_path_buf(), source })?;
    let gltf = gltf::Gltf::from_slice(&bytes).map_err(|e| gerr(path, e.to_string()))?;
    let buffers = load_buffers(path, &gltf)?;
    let doc = &gltf.document;
    let scene = doc.default_scene().or_else(|| doc.scenes().next()).ok_or_else(|| gerr(path, "no scene"))?;
    let mut mb = MeshBuilder::default();
    let mut found = Found { camera: None, orthographic_camera: false, light: None, primitives: 0, skipped: 0 };
    for node in scene.nodes() {
        visit(path, node, DMat4::IDENTITY, &buffers, &mut mb, &mut found, 0)?;
    }
    mb.end();
    if mb.indices.is_empty() {
        return Err(gerr(path, "no triangles in the default scene"));
    }
    let mut bounds = Bounds::EMPTY;
    for v in &mb.vertices {
        bounds.grow(glam::Vec3::from(v.position).as_dvec3());
    }
    let far_corner = |p: DVec3| bounds.corners().iter().map(|c| (*c - p).length()).fold(0.0, f64::max);
    let camera_from_file = camera.is_none() && found.camera.is_some();
    let cam = match (camera, found.camera) {
        (Some(c), _) => c,
        (None, Some((m, yfov, znear, zfar))) => {
            let eye = m.transform_point3(DVec3::ZERO);
            let far = zfar.unwrap_or_else(|| far_corner(eye) * 1.01 + znear);
            CameraSpec { eye, forward: m.transform_vector3(-DVec3::Z), up: m.transform_vector3(DVec3::Y), fovy: yfov, near: znear, far }
        }
        (None, None) if found.orthographic_camera => {
            return Err(gerr(path, "the file's camera is orthographic; pass a perspective camera explicitly"))
        }
        (None, None) => default_camera(&bounds),
    };
    let light_from_file = light.is_none() && found.light.is_some();
    let lt = match (light, found.light) {
        (Some(l), _) => l,
        (None, Some((m, kind, range))) => {
            let pos = m.transform_point3(DVec3::ZERO);
            let dir = m.transform_vector3(-DVec3::Z);
            match kind {
                gltf::khr_lights_punctual::Kind::Directional => LightSpec::Directional { direction: dir },
                gltf::khr_lights_punctual::Kind::Point => LightSpec::Point { position: pos },
                gltf::khr_lights_punctual::Kind::Spot { outer_cone_angle, .. } => {
                    // The lit cone fits inside a square pyramid of the same half-angle.
                    let fovy = (2.0 * outer_cone_angle as f64).clamp(1e-3, std::f64::consts::PI - 1e-3);
                    let far = range.unwrap_or_else(|| far_corner(pos) * 1.01).max(1e-6);
                    let up = m.transform_vector3(DVec3::Y);
                    LightSpec::Spot { position: pos, direction: dir, up, fovy, near: (far * 1e-4).max(1e-6), far }
                }
            }
        }
        (None, None) => default_light(),
    };
    let name = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "gltf".into());
    let report = GltfReport { camera_from_file, light_from_file, primitives: found.primitives, skipped_primitives: found.skipped };
    let scene = Scene::new(name, mb.vertices, mb.indices, &mb.objects, cam, lt)?;
    Ok((scene, report))
}

/// A built-in scene name or a path to a .gltf/.glb file.
pub fn load_scene(name_or_path: &str) -> Result<Scene, RenderError> {
    let p = Path::new(name_or_path);
    let is_file = p.extension().map(|e| e.eq_ignore_ascii_case("gltf") || e.eq_ignore_ascii_case("glb")).unwrap_or(false);
    if is_file {
        load_gltf(p, None, None).map(|(s, _)| s)
    } else {
        crate::scenes::builtin_scene(name_or_path)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_decodes() {
        assert_eq!(base64_decode("aGVsbG8=").unwrap(), b"hello");
        assert_eq!(base64_decode("AAEC").unwrap(), vec![0, 1, 2]);
        assert!(base64_decode("a$").is_none());
    }

    #[test]
    fn percent_decodes() {
        assert_eq!(percent_decode("a%20b.bin"), "a b.bin");
        assert_eq!(percent_decode("plain.bin"), "plain.bin");
        assert_eq!(percent_decode("bad%2"), "bad%2");
    }
}
