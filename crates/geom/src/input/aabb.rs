//! The scene box `S`.

use crate::error::{check_finite, GeomError};
use glam::DVec3;

/// A closed axis-aligned box; zero thickness on any axis is allowed.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Aabb {
    /// Smallest corner.
    pub min: DVec3,
    /// Largest corner.
    pub max: DVec3,
}

impl Aabb {
    /// A checked box: finite corners with `min ≤ max` on every axis.
    pub fn new(min: DVec3, max: DVec3) -> Result<Aabb, GeomError> {
        let b = Aabb { min, max };
        b.validate()?;
        Ok(b)
    }

    pub(crate) fn validate(&self) -> Result<(), GeomError> {
        check_finite(self.min, "scene box min")?;
        check_finite(self.max, "scene box max")?;
        for axis in 0..3 {
            if self.min[axis] > self.max[axis] {
                return Err(GeomError::InvertedBox { axis });
            }
        }
        Ok(())
    }

    /// The smallest box containing the points (exact: no arithmetic).
    pub fn around(points: &[DVec3]) -> Option<Aabb> {
        let first = *points.first()?;
        let (mut min, mut max) = (first, first);
        for p in points {
            min = min.min(*p);
            max = max.max(*p);
        }
        Some(Aabb { min, max })
    }

    /// Corner `k` (0..8): bit 0 picks `max.x` over `min.x`, bit 1 `max.y`,
    /// bit 2 `max.z`.
    pub fn corner(&self, k: usize) -> DVec3 {
        let pick = |bit: usize, lo: f64, hi: f64| if k & bit == 0 { lo } else { hi };
        DVec3::new(pick(1, self.min.x, self.max.x), pick(2, self.min.y, self.max.y), pick(4, self.min.z, self.max.z))
    }

    /// Whether `p` lies in the closed box (exact comparisons).
    pub fn contains(&self, p: DVec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }
}
