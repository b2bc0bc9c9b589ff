//! Recovering a camera from eight frustum corners.

use crate::error::FocusError;
use glam::{DMat3, DVec3};
use shadowfocus_geom::{Camera, Frustum};

/// A camera recovered from corners, and how well it reproduces them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RecoveredCamera {
    /// The camera whose frustum has these corners.
    pub camera: Camera,
    /// Largest distance between a given corner and the recovered camera's
    /// corner, relative to the largest eye–corner distance. Around 1e-15
    /// for corners computed from a camera; large for asymmetric frusta.
    pub residual: f64,
}

/// Recovers the symmetric perspective camera whose frustum has the given
/// corners (near face first, then far, each (−r−u), (+r−u), (+r+u),
/// (−r+u), as `Camera::corners` produces them).
///
/// The eye is where the four side edges meet — the least-squares point
/// closest to the four lines, `Σ (I − d dᵀ) x = Σ (I − d dᵀ) c` — the
/// forward axis is the near face's normal (pointing to the far face), up
/// follows the near face's −u→+u edges, and near/far are the depths of the
/// two face centres along forward. Field of view and aspect come from the
/// far face (the larger, better conditioned one). Errors when the corners
/// do not form a valid frustum or the side edges do not converge in front
/// of the near face; check `residual` for how symmetric the frustum was.
pub fn camera_from_corners(c: &[DVec3; 8]) -> Result<RecoveredCamera, FocusError> {
    Frustum::from_corners(*c)?;
    let bad = |reason| Err(FocusError::InvalidCorners { reason });
    let mut a = DMat3::ZERO;
    let mut rhs = DVec3::ZERO;
    for i in 0..4 {
        let d = (c[i + 4] - c[i]).normalize_or_zero();
        if d == DVec3::ZERO {
            return bad("a side edge has zero length");
        }
        let p = DMat3::IDENTITY - DMat3::from_cols(d * d.x, d * d.y, d * d.z);
        a += p;
        rhs += p * c[i];
    }
    if !(a.determinant().abs() > 1e-12) {
        return bad("the side edges are parallel (orthographic frustum)");
    }
    let eye = a.inverse() * rhs;
    let nc = (c[0] + c[1] + c[2] + c[3]) * 0.25;
    let fc = (c[4] + c[5] + c[6] + c[7]) * 0.25;
    // (c2 − c0) × (c3 − c1) = 2(r + u) × (u − r)·s² ∝ r × u = −forward.
    let mut forward = -(c[2] - c[0]).cross(c[3] - c[1]).normalize_or_zero();
    if forward.dot(fc - nc) < 0.0 {
        forward = -forward;
    }
    let near = forward.dot(nc - eye);
    let far = forward.dot(fc - eye);
    if !(near > 0.0 && far > near) {
        return bad("the side edges do not meet behind the near face");
    }
    let up_dir = (c[7] + c[6]) - (c[4] + c[5]);
    let up = (up_dir - forward * up_dir.dot(forward)).normalize_or_zero();
    if up == DVec3::ZERO {
        return bad("the far face has no height");
    }
    let right = forward.cross(up);
    let half_h = 0.25 * up.dot((c[7] + c[6]) - (c[4] + c[5]));
    let half_w = 0.25 * right.dot((c[5] + c[6]) - (c[4] + c[7]));
    if !(half_h > 0.0 && half_w > 0.0) {
        return bad("the far face is mirrored or flat");
    }
    let fovy = 2.0 * (half_h / far).atan();
    let camera = Camera { eye, forward, up, fovy, aspect: half_w / half_h, near, far };
    let rc = camera.corners()?;
    let scale = c.iter().map(|p| (*p - eye).length()).fold(0.0, f64::max);
    let residual = c.iter().zip(rc.iter()).map(|(p, q)| (*p - *q).length()).fold(0.0, f64::max) / scale;
    Ok(RecoveredCamera { camera, residual })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_a_camera() {
        let cam = Camera {
            eye: DVec3::new(3.0, -2.0, 7.5),
            forward: DVec3::new(0.3, -0.2, -1.0),
            up: DVec3::new(0.1, 1.0, 0.0),
            fovy: 0.9,
            aspect: 1.7,
            near: 0.25,
            far: 300.0,
        };
        let r = camera_from_corners(&cam.corners().unwrap()).unwrap();
        let b0 = cam.basis().unwrap();
        let b1 = r.camera.basis().unwrap();
        assert!(r.residual < 1e-12, "{}", r.residual);
        assert!((r.camera.eye - cam.eye).length() < 1e-9);
        assert!((b0.forward - b1.forward).length() < 1e-12);
        assert!((b0.up - b1.up).length() < 1e-12);
        assert!((r.camera.near - cam.near).abs() < 1e-9 && (r.camera.far - cam.far).abs() < 1e-9);
        assert!((r.camera.fovy - cam.fovy).abs() < 1e-12 && (r.camera.aspect - cam.aspect).abs() < 1e-12);
    }

    #[test]
    fn rejects_boxes_and_reports_asymmetry() {
        let b = [
            DVec3::new(-1.0, -1.0, 0.0),
            DVec3::new(1.0, -1.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(-1.0, 1.0, 0.0),
            DVec3::new(-1.0, -1.0, -5.0),
            DVec3::new(1.0, -1.0, -5.0),
            DVec3::new(1.0, 1.0, -5.0),
            DVec3::new(-1.0, 1.0, -5.0),
        ];
        assert!(matches!(camera_from_corners(&b), Err(FocusError::InvalidCorners { .. })));
        // An off-centre (sheared) frustum: recovered, with a large residual.
        let mut s = b;
        for (i, p) in s.iter_mut().enumerate() {
            let t = if i < 4 { 1.0 } else { 3.0 };
            *p = DVec3::new(p.x * t + if i < 4 { 0.0 } else { 1.5 }, p.y * t, p.z - 1.0);
        }
        let r = camera_from_corners(&s).unwrap();
        assert!(r.residual > 1e-3, "{}", r.residual);
    }
}
