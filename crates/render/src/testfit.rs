//! Plain shadow-map fits for tests and examples only.
//!
//! These are deliberately naive — the whole scene box, or the box of each split's sub-frustum —
//! so the renderer can be exercised without the focusing crate. They are not a focusing method
//! and make no claim of tightness; real maps come from `shadowfocus-focus`.

use glam::{DMat4, DVec3, Mat4};

use crate::error::RenderError;
use crate::scene::Scene;
use crate::types::{Bounds, CameraSpec, DepthTest, LightSpec, ShadowMapSpec};

fn any_perpendicular(d: DVec3) -> DVec3 {
    if d.y.abs() < 0.9 {
        DVec3::Y
    } else {
        DVec3::X
    }
}

/// Light view matrix looking along `d` from `eye`.
fn light_view(eye: DVec3, d: DVec3) -> DMat4 {
    glam::dcamera::rh::view::look_to_mat4(eye, d.normalize(), any_perpendicular(d.normalize()))
}

/// Orthographic world → clip fitted to the light-space box of `pts` in x, y (intersected with
/// that of `depth_pts`) and of `pts` ∪ `depth_pts` in z (z ∈ [0, 1], near the light = 0).
fn ortho_fit(d: DVec3, pts: &[DVec3], depth_pts: &[DVec3]) -> DMat4 {
    let view = light_view(DVec3::ZERO, d);
    let light_box = |ps: &[DVec3]| {
        let mut b = Bounds::EMPTY;
        for p in ps {
            b.grow(view.transform_point3(*p));
        }
        b
    };
    let (a, b) = (light_box(pts), light_box(depth_pts));
    let mut lo = a.min.max(b.min);
    let mut hi = a.max.min(b.max);
    if !(lo.x < hi.x && lo.y < hi.y) {
        lo = a.min;
        hi = a.max;
    }
    let (mut zlo, mut zhi) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in depth_pts.iter().chain(pts) {
        let z = view.transform_point3(*p).z;
        zlo = zlo.min(z);
        zhi = zhi.max(z);
    }
    // View space looks down −z: near = −zhi, far = −zlo; pad 0.1 % so the box is strictly inside.
    let pad = 1e-3 * (zhi - zlo).max(1e-9);
    let padx = 1e-3 * (hi.x - lo.x).max(1e-9);
    let pady = 1e-3 * (hi.y - lo.y).max(1e-9);
    glam::dcamera::rh::proj::directx::orthographic(lo.x - padx, hi.x + padx, lo.y - pady, hi.y + pady, -zhi - pad, -zlo + pad) * view
}

/// Perspective world → clip from `pos` covering every point of `pts` (square, z ∈ [0, 1]).
fn perspective_fit(pos: DVec3, pts: &[DVec3], toward: DVec3) -> Result<DMat4, RenderError> {
    let d = (toward - pos).normalize_or_zero();
    if d == DVec3::ZERO {
        return Err(RenderError::invalid("test fit", "light at the scene centre"));
    }
    let view = light_view(pos, d);
    let (mut t, mut near, mut far) = (0.0f64, f64::INFINITY, 0.0f64);
    for p in pts {
        let q = view.transform_point3(*p);
        let depth = -q.z;
        if depth <= 0.0 {
            return Err(RenderError::invalid("test fit", "scene point behind the light's view"));
        }
        t = t.max(q.x.abs() / depth).max(q.y.abs() / depth);
        near = near.min(depth);
        far = far.max(depth);
    }
    let fovy = 2.0 * (t * 1.001).atan();
    Ok(glam::dcamera::rh::proj::directx::perspective(fovy, 1.0, near * 0.999, far * 1.001) * view)
}

/// One map over the whole scene box: orthographic for a directional light; for a spot light its
/// own pyramid; for a point light a perspective map over the box, or over the camera frustum
/// when part of the box lies behind the light. Serves the camera's whole depth range and draws
/// every object.
pub fn scene_box_map(scene: &Scene, camera: &CameraSpec, light: &LightSpec, aspect: f64) -> Result<ShadowMapSpec, RenderError> {
    let corners = scene.bounds.corners();
    let m = match *light {
        LightSpec::Directional { direction } => ortho_fit(direction, &corners, &corners),
        LightSpec::Spot { .. } => light.spot_matrix().ok_or_else(|| RenderError::invalid("test fit", "bad spot light"))?,
        LightSpec::Point { position } => match perspective_fit(position, &corners, scene.bounds.center()) {
            Ok(m) => m,
            Err(_) => {
                let fc = camera.corners(aspect)?;
                let centre = fc.iter().fold(DVec3::ZERO, |a, &c| a + c) / 8.0;
                perspective_fit(position, &fc, centre)?
            }
        },
    };
    Ok(ShadowMapSpec {
        world_to_clip: m.as_mat4(),
        depth_test: DepthTest::Less,
        split: [camera.near as f32, camera.far as f32],
        casters: scene.all_objects(),
        face: None,
        resolution: None,
    })
}

/// PSSM practical split positions C_i = (n(f/n)^{i/m} + n + (f−n)i/m)/2, i = 0..=m.
pub fn practical_splits(near: f64, far: f64, m: usize) -> Vec<f64> {
    (0..=m)
        .map(|i| {
            let s = i as f64 / m as f64;
            if i == 0 {
                near
            } else if i == m {
                far
            } else {
                0.5 * (near * (far / near).powf(s) + near + (far - near) * s)
            }
        })
        .collect()
}

/// Parallel-split orthographic maps for a directional light: each fitted to its sub-frustum in
/// x, y and to the sub-frustum plus the scene box in depth, so every caster toward the light is
/// inside. Casters are the objects whose boxes meet the map's light-space box.
pub fn split_maps(scene: &Scene, camera: &CameraSpec, light: &LightSpec, aspect: f64, m: usize) -> Result<Vec<ShadowMapSpec>, RenderError> {
    let LightSpec::Directional { direction } = *light else {
        return Err(RenderError::invalid("test fit", "split maps are only fitted for directional lights"));
    };
    let cs = practical_splits(camera.near, camera.far, m.max(1));
    let box_corners = scene.bounds.corners();
    let mut out = Vec::new();
    for w in cs.windows(2) {
        let sub = CameraSpec { near: w[0], far: w[1], ..*camera };
        let c = sub.corners(aspect)?;
        let mat = ortho_fit(direction, &c, &box_corners);
        out.push(ShadowMapSpec {
            world_to_clip: mat.as_mat4(),
            depth_test: DepthTest::Less,
            split: [w[0] as f32, w[1] as f32],
            casters: objects_in_clip_box(scene, &mat),
            face: None,
            resolution: None,
        });
    }
    Ok(out)
}

/// Objects whose world boxes meet the clip volume of an affine (orthographic) map.
fn objects_in_clip_box(scene: &Scene, m: &DMat4) -> Vec<u32> {
    let mut out = Vec::new();
    for (k, o) in scene.objects.iter().enumerate() {
        let mut b = Bounds::EMPTY;
        for c in o.aabb.corners() {
            let q = *m * c.extend(1.0);
            b.grow(q.truncate() / q.w);
        }
        if b.max.x >= -1.0 && b.min.x <= 1.0 && b.max.y >= -1.0 && b.min.y <= 1.0 && b.max.z >= 0.0 && b.min.z <= 1.0 {
            out.push(k as u32);
        }
    }
    out
}

/// The same map with its depth reversed (z' = 1 − z after the divide; rows: z' = w − z), to be
/// used with [`DepthTest::Greater`] — what an inverted perspective shadow map looks like to the
/// renderer.
pub fn reverse_depth(map: &ShadowMapSpec) -> ShadowMapSpec {
    let m = map.world_to_clip.as_dmat4().transpose(); // rows as columns
    let rows = [m.x_axis, m.y_axis, m.w_axis - m.z_axis, m.w_axis];
    let flipped = DMat4::from_cols(rows[0], rows[1], rows[2], rows[3]).transpose();
    ShadowMapSpec { world_to_clip: flipped.as_mat4(), depth_test: DepthTest::Greater, ..map.clone() }
}

/// The map zoomed by `factor` about its centre (x, y only): with factor > 1 it covers less.
pub fn zoom(map: &ShadowMapSpec, factor: f32) -> ShadowMapSpec {
    let s = Mat4::from_cols(
        glam::Vec4::new(factor, 0.0, 0.0, 0.0),
        glam::Vec4::new(0.0, factor, 0.0, 0.0),
        glam::Vec4::new(0.0, 0.0, 1.0, 0.0),
        glam::Vec4::new(0.0, 0.0, 0.0, 1.0),
    );
    ShadowMapSpec { world_to_clip: s * map.world_to_clip, ..map.clone() }
}
