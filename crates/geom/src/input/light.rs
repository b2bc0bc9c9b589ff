//! The light `l`: a point, or a point at infinity for directional lights,
//! and a spot light's frustum `L`.

use crate::error::{check_finite, GeomError};
use crate::input::frustum::{Apex, Frustum};
use glam::DVec3;

/// A light. A directional light is the point at infinity it comes from.
// NOTE: a spot light carries its validated frustum by value, so that a
// `Light` is `Copy` and nothing is allocated per frame; the other variants
// pay its size.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Light {
    /// Light travelling along `direction` (from the light into the scene).
    Directional {
        /// The travel direction, any non-zero length.
        direction: DVec3,
    },
    /// An omnidirectional point light.
    Point {
        /// The light's position.
        position: DVec3,
    },
    /// A spot light: its apex and the frustum it lights.
    Spot {
        /// The apex.
        position: DVec3,
        /// The lit frustum, with its apex at `position`.
        frustum: Frustum,
    },
}

impl Light {
    /// A checked directional light (finite, non-zero direction).
    pub fn directional(direction: DVec3) -> Result<Light, GeomError> {
        let l = Light::Directional { direction };
        l.validate()?;
        Ok(l)
    }

    /// A checked point light (finite position).
    pub fn point(position: DVec3) -> Result<Light, GeomError> {
        let l = Light::Point { position };
        l.validate()?;
        Ok(l)
    }

    /// A checked spot light (finite apex).
    pub fn spot(position: DVec3, frustum: Frustum) -> Result<Light, GeomError> {
        let l = Light::Spot { position, frustum };
        l.validate()?;
        Ok(l)
    }

    /// Checks a light built from its fields: finite numbers, a nonzero
    /// direction (a spot light's frustum is valid by construction).
    pub fn validate(&self) -> Result<(), GeomError> {
        match *self {
            Light::Directional { direction } => {
                check_finite(direction, "light direction")?;
                if direction == DVec3::ZERO {
                    return Err(GeomError::ZeroDirection { what: "light direction" });
                }
                Ok(())
            }
            Light::Point { position } | Light::Spot { position, .. } => check_finite(position, "light position"),
        }
    }

    /// The unit vector along a directional light's travel direction, for
    /// any finite nonzero direction however long or short (see
    /// [`unit_direction`]); `None` for point and spot lights.
    pub fn unit_direction(&self) -> Option<DVec3> {
        match *self {
            Light::Directional { direction } => Some(unit_direction(direction)),
            _ => None,
        }
    }

    /// The light as a homogeneous point (at infinity for directional lights).
    pub fn apex(&self) -> Apex {
        match *self {
            Light::Directional { direction } => Apex::Infinite(-direction),
            Light::Point { position } | Light::Spot { position, .. } => Apex::Finite(position),
        }
    }
}

/// `d / |d|` for any finite nonzero `d`, also where `|d|²` overflows
/// (|d| above ~1e154) or underflows (below ~1e-154), which `normalize`
/// turns into zero, infinity or NaN.
///
/// `d` is first multiplied by the power of two `2^-e` that brings its
/// largest component into `[1, 2)` (exact: only the exponents change, except
/// for components below 2⁻¹⁰²² of the largest, which round as a unit vector
/// would round them anyway), then normalised. The zero vector and
/// non-finite input give NaN components (validated lights never have them).
pub fn unit_direction(d: DVec3) -> DVec3 {
    let m = d.abs().max_element();
    if !(m > 0.0 && m.is_finite()) {
        return DVec3::splat(f64::NAN);
    }
    let bits = m.to_bits();
    let biased = ((bits >> 52) & 0x7ff) as i32;
    // floor(log2 m), exactly, for normal and subnormal m: in [-1074, 1023].
    let e = if biased == 0 { -1074 + (63 - (bits & ((1u64 << 52) - 1)).leading_zeros() as i32) } else { biased - 1023 };
    // 2^-e in two factors, each a normal power of two (|k| ≤ 537).
    let pow2 = |k: i32| f64::from_bits(((k + 1023) as u64) << 52);
    let (a, b) = (-e / 2, -e - (-e / 2));
    (d * pow2(a) * pow2(b)).normalize()
}
