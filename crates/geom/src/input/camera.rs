//! Camera description → frustum corners.
//!
//! Corner order (shared by view and spot-light frusta): near plane first,
//! then far plane, each as (−right −up), (+right −up), (+right +up),
//! (−right +up).
//!
//! With f = forward/|forward|, r = (f × up)/|f × up| and u = r × f, the
//! corner at depth t ∈ {near, far} and signs (sx, sy) is
//! `eye + t·f + sx·t·tan(fovy/2)·aspect·r + sy·t·tan(fovy/2)·u`.

use crate::error::{check_finite, GeomError};
use glam::DVec3;

/// A perspective camera (or spot light) looking along `forward`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Camera {
    /// Eye position.
    pub eye: DVec3,
    /// View direction (any non-zero length).
    pub forward: DVec3,
    /// Up hint, not parallel to `forward`.
    pub up: DVec3,
    /// Full vertical field of view, radians, in (0, π).
    pub fovy: f64,
    /// Width / height, > 0.
    pub aspect: f64,
    /// Distances along `forward`, 0 < near < far.
    pub near: f64,
    /// Far plane distance along `forward`, greater than `near`.
    pub far: f64,
}

/// Orthonormal camera basis: forward, right, up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraBasis {
    /// Unit view direction.
    pub forward: DVec3,
    /// Unit right, `forward × up`.
    pub right: DVec3,
    /// Unit up, perpendicular to `forward`.
    pub up: DVec3,
}

impl Camera {
    /// Field of view, aspect, near and far: finite and in range.
    fn check_scalars(&self) -> Result<(), GeomError> {
        for (v, what) in [(self.fovy, "camera fovy"), (self.aspect, "camera aspect"), (self.near, "camera near"), (self.far, "camera far")]
        {
            if !v.is_finite() {
                return Err(GeomError::NonFinite { what });
            }
        }
        if !(self.fovy > 0.0 && self.fovy < std::f64::consts::PI) {
            return Err(GeomError::InvalidCamera { reason: "fovy must lie strictly between 0 and 180 degrees" });
        }
        if !(self.aspect > 0.0) {
            return Err(GeomError::InvalidCamera { reason: "aspect must be positive" });
        }
        if !(self.near > 0.0) {
            return Err(GeomError::InvalidCamera { reason: "near must be positive" });
        }
        if !(self.near < self.far) {
            return Err(GeomError::InvalidCamera { reason: "near must be smaller than far" });
        }
        Ok(())
    }

    /// Checks every parameter and returns the orthonormal basis.
    pub fn basis(&self) -> Result<CameraBasis, GeomError> {
        check_finite(self.eye, "camera eye")?;
        check_finite(self.forward, "camera forward")?;
        check_finite(self.up, "camera up")?;
        self.check_scalars()?;
        let f_len = self.forward.length();
        if !(f_len > 0.0) || !f_len.is_finite() {
            return Err(GeomError::ZeroDirection { what: "camera forward" });
        }
        if exactly_parallel(self.forward, self.up) {
            return Err(GeomError::InvalidCamera { reason: "up is zero or parallel to forward" });
        }
        let forward = self.forward / f_len;
        let side = forward.cross(self.up);
        let s_len = side.length();
        if !(s_len > 0.0) || !s_len.is_finite() {
            return Err(GeomError::InvalidCamera { reason: "up is zero or parallel to forward" });
        }
        let right = side / s_len;
        let up = right.cross(forward);
        Ok(CameraBasis { forward, right, up })
    }

    /// The eight frustum corners in the documented order.
    pub fn corners(&self) -> Result<[DVec3; 8], GeomError> {
        let b = self.basis()?;
        self.corner_points(&b)
    }

    /// [`Camera::corners`] with the basis already computed by
    /// [`Camera::basis`] for a camera with the same eye, forward and up (the
    /// splits of one view share it); the other parameters are checked here.
    pub fn corners_in(&self, b: &CameraBasis) -> Result<[DVec3; 8], GeomError> {
        self.check_scalars()?;
        self.corner_points(b)
    }

    /// The corners for checked parameters.
    fn corner_points(&self, b: &CameraBasis) -> Result<[DVec3; 8], GeomError> {
        let tan_half = (0.5 * self.fovy).tan();
        let mut out = [DVec3::ZERO; 8];
        for (k, t) in [self.near, self.far].into_iter().enumerate() {
            let hh = t * tan_half;
            let hw = hh * self.aspect;
            let centre = self.eye + b.forward * t;
            let signs = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
            for (i, (sx, sy)) in signs.into_iter().enumerate() {
                out[4 * k + i] = centre + b.right * (sx * hw) + b.up * (sy * hh);
            }
        }
        for c in &out {
            check_finite(*c, "frustum corner computed from camera")?;
        }
        Ok(out)
    }
}

/// Whether `a × b = 0` exactly (each component's sign decided exactly).
fn exactly_parallel(a: DVec3, b: DVec3) -> bool {
    use crate::arith::number::{cross, lift, Exact, Filtered};
    // NOTE: a component `a_i b_j − a_j b_i` rounds each product and the
    // difference once: within 2u(1 + u) of |a_i b_j| + |a_j b_i|, plus at
    // most 2^-1074 per product where one underflows. The bound takes 6u of
    // the rounded sum (which covers that sum's own rounding) and 1e-300;
    // beyond it the exact component is nonzero. An infinite bound proves
    // nothing (NaN compares false).
    let (c, perm) = (a.cross(b), crate::arith::number::abs_cross(a, b));
    let bound = perm * (3.0 * f64::EPSILON) + DVec3::splat(1e-300);
    if c.abs().cmpgt(bound).any() {
        return false;
    }
    let f = cross(&lift::<Filtered>(a), &lift::<Filtered>(b));
    if f.iter().any(|c| matches!(c.sign(), Some(s) if s != 0)) {
        return false;
    }
    cross(&lift::<Exact>(a), &lift::<Exact>(b)).iter().all(|c| c.sign() == 0)
}
