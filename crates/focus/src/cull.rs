//! Caster culling: which bounding boxes can shadow what a map covers.
//!
//! A caster can shadow a visible point `p` only where it meets the segment
//! from `p` to the light. For map `i` those segments fill the region
//!
//! - `R = H_i ⊕ {−s d : s ≥ 0}` (H swept toward the light) for a
//!   directional light travelling along `d`,
//! - `R = hull(H_i ∪ {l})` for a point or spot light at `l`,
//!
//! which contains `H_i` and also every part of a caster that pokes out of
//! the scene box toward the light. A box is culled only when a plane is
//! found that provably separates it from `R`.
//!
//! Planes used (each is checked to satisfy the rule below, else dropped —
//! dropping a plane only ever keeps more casters):
//! - faces of `H_i` that do not face the light: `n·d ≥ τ` (directional) or
//!   `l` on the inner side by a margin (point);
//! - silhouette planes: through an edge of `H_i` between a kept face and a
//!   dropped one, containing `d` (directional) or `l` (point), oriented away
//!   from `H_i`;
//! - the three axes: `R`'s bounding box, unbounded on the sides the light
//!   direction leaves open.
//!
//! Rule: a plane with `H_i` on its inner side bounds `R` iff the sweep
//! direction `−d` does not leave it (`n·d ≥ 0`), respectively `l` is inside
//! too (a halfspace is convex). Both conditions are required with a
//! rounding allowance in their favour; the separation test
//! `n·c − |n|·e + w > 0` (box centre `c`, half-size `e`) also needs to
//! exceed a bound on its own rounding error plus the few-ulp rounding of
//! `H_i`'s vertices. So the test never culls a box that meets `R`; it may
//! keep a box that misses `R` near an edge (edge–edge separating axes are
//! not tried).

use crate::error::FocusError;
use crate::methods::light_point;
use crate::result::ShadowMap;
use glam::{DVec3, DVec4};
use shadowfocus_geom::{Aabb, Body, Dimension, Light};

/// Most planes a region can have: the body's faces, one silhouette plane
/// per edge and the six sides of the bounding box.
pub const MAX_REGION_PLANES: usize = 3 * shadowfocus_geom::MAX_FACES + 6;

/// Relative rounding allowance (2⁻⁴⁰ ≈ 1e-12 of the magnitudes involved):
/// far above the error of the f64 expressions below and of the body's
/// rounded vertices, far below any geometric feature size that matters.
const REL: f64 = 1.0 / (1u64 << 40) as f64;

/// The region of one map that casters must meet to matter, as planes an
/// engine can test its own bounding volumes against ([`CasterRegion::planes`]).
#[derive(Clone, Debug)]
pub struct CasterRegion {
    /// Inside is `n·x + w ≤ 0`; pushed out by the rounding allowance once
    /// the region is built (`seal`).
    planes: [DVec4; MAX_REGION_PLANES],
    n_planes: usize,
    /// Bounding box of R (±∞ where the sweep is unbounded).
    lo: DVec3,
    hi: DVec3,
    /// Magnitude of the coordinates, for rounding bounds.
    mag: f64,
    empty: bool,
}

impl CasterRegion {
    /// The region of `map` (empty for an empty map).
    pub fn of_map(map: &ShadowMap) -> CasterRegion {
        let light = match map.light {
            // A cube face or truncated point map is a spot at the light.
            Light::Spot { position, .. } => Light::Point { position },
            l => l,
        };
        CasterRegion::new(map.body(), &light)
    }

    /// The region of body `h` lit by `light`.
    pub fn new(h: &Body, light: &Light) -> CasterRegion {
        let mut r = CasterRegion {
            planes: [DVec4::ZERO; MAX_REGION_PLANES],
            n_planes: 0,
            lo: DVec3::splat(f64::INFINITY),
            hi: DVec3::splat(f64::NEG_INFINITY),
            mag: 0.0,
            empty: h.is_empty(),
        };
        if r.empty {
            return r.seal();
        }
        let lp = light_point(light);
        let verts = h.vertices();
        for p in verts {
            r.lo = r.lo.min(*p);
            r.hi = r.hi.max(*p);
            r.mag = r.mag.max(p.abs().max_element());
        }
        let sweep = if lp.w == 0.0 {
            // Unbounded toward the light: −d = lp.xyz.
            let up = lp.truncate();
            for k in 0..3 {
                if up[k] > 0.0 {
                    r.hi[k] = f64::INFINITY;
                } else if up[k] < 0.0 {
                    r.lo[k] = f64::NEG_INFINITY;
                }
            }
            None
        } else {
            let l = lp.truncate();
            r.lo = r.lo.min(l);
            r.hi = r.hi.max(l);
            r.mag = r.mag.max(l.abs().max_element());
            Some(l)
        };
        if h.dimension() != Dimension::Solid {
            // Flat bodies: the bounding box alone (conservative).
            return r.seal();
        }
        let planes = h.face_planes();
        // Keep a face iff it certainly does not face the light.
        let mut keep = [false; shadowfocus_geom::MAX_FACES];
        for (i, pl) in planes.iter().enumerate() {
            let n = pl.truncate();
            keep[i] = match sweep {
                None => n.dot(-lp.truncate()) >= REL * 4.0,
                Some(l) => n.dot(l) + pl.w <= -REL * 4.0 * (r.mag + pl.w.abs()),
            };
            if keep[i] {
                r.push(*pl);
            }
        }
        // Silhouette edges: an edge of a kept face whose twin lies in a
        // dropped face. Twins are found by scanning the other faces (bodies
        // have at most a few dozen edges).
        for (i, fi) in h.faces().enumerate() {
            if !keep[i] {
                continue;
            }
            for k in 0..fi.len() {
                let (a, b) = (fi[k], fi[(k + 1) % fi.len()]);
                let twin_dropped = h.faces().enumerate().any(|(j, fj)| {
                    if j == i || keep[j] {
                        return false;
                    }
                    (0..fj.len()).any(|m| fj[m] == b && fj[(m + 1) % fj.len()] == a)
                });
                if twin_dropped {
                    let (pa, pb) = (verts[a as usize], verts[b as usize]);
                    let dir = match sweep {
                        None => -lp.truncate(),
                        Some(l) => l - pa,
                    };
                    r.silhouette(pa, pb - pa, dir, verts, sweep);
                }
            }
        }
        r.seal()
    }

    /// Adds the bounding box's finite sides as planes and pushes every plane
    /// out by its rounding allowance `16 REL (mag + |w|)`, so that the
    /// planes alone state the region. An empty region is the one plane
    /// `1 ≤ 0`, which no box satisfies.
    fn seal(mut self) -> CasterRegion {
        if self.empty {
            self.n_planes = 0;
            self.push(DVec4::W);
            return self;
        }
        for k in 0..3 {
            let axis = DVec3::AXES[k];
            // x_k ≥ lo_k, i.e. −x_k + lo_k ≤ 0; x_k ≤ hi_k, i.e. x_k − hi_k ≤ 0.
            if self.lo[k].is_finite() {
                self.push((-axis).extend(self.lo[k]));
            }
            if self.hi[k].is_finite() {
                self.push(axis.extend(-self.hi[k]));
            }
        }
        let mag = self.mag;
        for p in &mut self.planes[..self.n_planes] {
            p.w -= REL * 16.0 * (mag + p.w.abs());
        }
        self
    }

    fn push(&mut self, p: DVec4) {
        if self.n_planes < MAX_REGION_PLANES {
            self.planes[self.n_planes] = p;
            self.n_planes += 1;
        }
    }

    /// The plane through `a` spanned by `e` and `dir`, oriented away from
    /// the body; kept only if every vertex (and the light) is inside.
    fn silhouette(&mut self, a: DVec3, e: DVec3, dir: DVec3, verts: &[DVec3], light: Option<DVec3>) {
        let n = e.cross(dir);
        let len = n.length();
        if !(len > 0.0) {
            return;
        }
        let mut n = n / len;
        let tol = REL * 16.0 * (self.mag + a.abs().max_element());
        // Orient away from the body: the farthest vertex must be inside.
        let (mut lo, mut hi) = (0.0f64, 0.0f64);
        for v in verts {
            let s = n.dot(*v - a);
            lo = lo.min(s);
            hi = hi.max(s);
        }
        if hi > -lo {
            n = -n;
            (lo, hi) = (-hi, -lo);
        }
        let _ = lo;
        if hi > tol {
            return; // the body is not on one side: not a silhouette plane
        }
        if let Some(l) = light {
            if n.dot(l - a) > tol {
                return;
            }
        }
        self.push(n.extend(-n.dot(a)));
    }

    /// Whether nothing can shadow this map.
    pub fn is_empty(&self) -> bool {
        self.empty
    }

    /// The region as planes `(n, w)`, inside `n·x + w ≤ 0`: the faces of
    /// `H` that do not face the light, the silhouette planes of `H` swept
    /// toward the light, and the sides of that sweep's bounding box, each
    /// already pushed out by the region's rounding allowance (an empty region
    /// is the single plane `1 ≤ 0`). Every point that can shadow the map is
    /// inside every plane, so a bounding volume wholly outside one plane
    /// casts no shadow into it. For a box with centre `c` and half-size `e`
    /// that is `n·c − |n|·e + w > 0`; evaluated in f64, require more than
    /// `2⁻³⁶ · max |box coordinate|` (what [`CasterRegion::may_shadow`]
    /// does), in f32 more than `2⁻²⁰ (|n|·|c| + |n|·e + |w|)`.
    pub fn planes(&self) -> &[DVec4] {
        &self.planes[..self.n_planes]
    }

    /// `false` only when the box provably misses the region: it lies
    /// outside one of [`CasterRegion::planes`] by more than its rounding.
    pub fn may_shadow(&self, b: &Aabb) -> bool {
        let bmag = b.min.abs().max(b.max.abs()).max_element();
        let slack = REL * 16.0 * bmag;
        let c = (b.min + b.max) * 0.5;
        let e = (b.max - b.min) * 0.5;
        // NOTE: `!(s > slack)` keeps a box whose test is NaN.
        !self.planes().iter().any(|p| {
            let n = p.truncate();
            n.dot(c) - n.abs().dot(e) + p.w > slack
        })
    }
}

/// Writes the planes of the region whose casters can shadow `map`
/// ([`CasterRegion::planes`]) to `out`; returns how many. `out` must hold
/// [`MAX_REGION_PLANES`] planes (checked first: [`FocusError::Capacity`]).
/// [`cull_casters`] tests boxes against exactly these planes.
pub fn caster_planes(map: &ShadowMap, out: &mut [DVec4]) -> Result<usize, FocusError> {
    if out.len() < MAX_REGION_PLANES {
        return Err(FocusError::Capacity { what: "caster_planes output (it must hold MAX_REGION_PLANES planes)" });
    }
    let region = CasterRegion::of_map(map);
    let planes = region.planes();
    out[..planes.len()].copy_from_slice(planes);
    Ok(planes.len())
}

/// Writes to `out` the indices of the casters that may shadow `map`;
/// returns how many (the first that many entries of `out`).
///
/// `out` must hold `casters.len()` indices (every caster may be kept), and
/// fewer than `u32::MAX` casters are indexed: otherwise the call is a
/// [`FocusError::Capacity`] error, checked before any work, so a short
/// buffer fails on the first frame rather than on the frame that happens to
/// keep more casters than it holds.
pub fn cull_casters(map: &ShadowMap, casters: &[Aabb], out: &mut [u32]) -> Result<usize, FocusError> {
    if out.len() < casters.len() {
        return Err(FocusError::Capacity { what: "cull_casters output (it must hold one index per caster)" });
    }
    if casters.len() > u32::MAX as usize {
        return Err(FocusError::Capacity { what: "cull_casters input (at most u32::MAX casters)" });
    }
    let region = CasterRegion::of_map(map);
    let mut n = 0;
    for (i, b) in casters.iter().enumerate() {
        if region.may_shadow(b) {
            out[n] = i as u32;
            n += 1;
        }
    }
    Ok(n)
}
