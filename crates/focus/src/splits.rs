//! Parallel-split distances [PSSM06 §3.3] and the clip-space depths a shader
//! compares against to pick a split (PSSM eq. 8).

use crate::settings::{SplitScheme, SplitSettings};
use crate::MAX_SPLITS;

/// Split plane depths `C_0 = n < C_1 ≤ … ≤ C_m = f` along the camera's
/// forward axis, written to `out[..=m]`; returns `m`.
///
/// The outer planes are exactly `near` and `far`, and split `i` is
/// `[out[i], out[i + 1]]`, so consecutive splits share their boundary value
/// bit for bit: the splits cover `[near, far]` without gaps or overlap.
/// Inner planes get `delta_bias` added (eq. 7) and are then clamped to stay
/// monotone and inside `[near, far]`; a split can thus become empty, which
/// the fit reports.
pub fn split_depths(near: f64, far: f64, s: &SplitSettings, out: &mut [f64; MAX_SPLITS + 1]) -> usize {
    let m = s.count.clamp(1, MAX_SPLITS);
    out[0] = near;
    for i in 1..m {
        let t = i as f64 / m as f64;
        let uni = near + (far - near) * t;
        // NOTE: n·(f/n)^t as exp(t·ln(f/n)) keeps full relative precision
        // for any ratio; both ends are exact (t ∈ (0, 1) only here).
        let log = near * (t * (far / near).ln()).exp();
        let practical = |lambda: f64| lambda * log + (1.0 - lambda) * uni;
        let c = match s.scheme {
            SplitScheme::Uniform => uni,
            SplitScheme::Log => log,
            SplitScheme::Practical { lambda } => practical(lambda),
            // The fit moves these planes per light (`placement.rs`); they are
            // one of its two starts.
            SplitScheme::Optimal => practical(0.5),
            SplitScheme::Geometric { first } => {
                let first = first.clamp(near, far);
                let t = (i - 1) as f64 / (m - 1) as f64;
                first * (t * (far / first).ln()).exp()
            }
        } + s.delta_bias;
        out[i] = c.clamp(out[i - 1], far);
    }
    out[m] = far;
    m
}

/// Clip-space depth (wgpu/D3D/Vulkan convention, `z ∈ [0, 1]`) of the view
/// depth `z` under the right-handed camera projection with depth in `[0, 1]`
/// (glam's `dcamera::rh::proj::directx::perspective(…, n, f)`):
/// `f/(f − n) · (1 − n/z)` — PSSM eq. 8 with its typo (`n − 1/C_i`) corrected.
/// A fragment with clip depth in `[clip(C_i), clip(C_{i+1})]` uses map `i`.
/// Other conventions: [`crate::ClipConvention::camera_depth`].
pub fn clip_depth(near: f64, far: f64, z: f64) -> f64 {
    crate::ClipConvention::WGPU.camera_depth(near, far, z)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn depths(near: f64, far: f64, count: usize, scheme: SplitScheme, bias: f64) -> Vec<f64> {
        let mut out = [0.0; MAX_SPLITS + 1];
        let m = split_depths(near, far, &SplitSettings { count, scheme, delta_bias: bias }, &mut out);
        out[..=m].to_vec()
    }

    #[test]
    fn schemes_match_the_paper() {
        let u = depths(1.0, 101.0, 4, SplitScheme::Uniform, 0.0);
        assert_eq!(u, vec![1.0, 26.0, 51.0, 76.0, 101.0]);
        let l = depths(1.0, 10000.0, 4, SplitScheme::Log, 0.0);
        for (i, want) in [1.0, 10.0, 100.0, 1000.0, 10000.0].iter().enumerate() {
            assert!((l[i] - want).abs() <= 1e-9 * want, "{i}: {} vs {want}", l[i]);
        }
        let p = depths(1.0, 10000.0, 4, SplitScheme::Practical { lambda: 0.5 }, 0.0);
        let u = depths(1.0, 10000.0, 4, SplitScheme::Uniform, 0.0);
        for i in 0..=4 {
            assert!((p[i] - 0.5 * (l[i] + u[i])).abs() <= 1e-9 * p[i]);
        }
    }

    /// The engines' cascades: a first split of a given length, the rest
    /// geometric (a first split of 10 to a far of 1000 over four splits:
    /// 10, 10·100^⅓, 10·100^⅔).
    #[test]
    fn geometric_starts_at_first() {
        let g = depths(0.1, 1000.0, 4, SplitScheme::Geometric { first: 10.0 }, 0.0);
        for (i, want) in [0.1, 10.0, 46.415_888_336_127_8, 215.443_469_003_188_4, 1000.0].iter().enumerate() {
            assert!((g[i] - want).abs() <= 1e-12 * want, "{i}: {} vs {want}", g[i]);
        }
        // A first split beyond far is clamped to it: the others are empty.
        let g = depths(0.1, 5.0, 3, SplitScheme::Geometric { first: 10.0 }, 0.0);
        assert_eq!(g, vec![0.1, 5.0, 5.0, 5.0]);
        // Two splits: the first plane is `first`.
        let g = depths(0.5, 300.0, 2, SplitScheme::Geometric { first: 7.0 }, 0.0);
        assert_eq!(g, vec![0.5, 7.0, 300.0]);
    }

    #[test]
    fn bias_keeps_ends_and_order() {
        let b = depths(0.5, 20.0, 6, SplitScheme::Log, 15.0);
        assert_eq!(b[0], 0.5);
        assert_eq!(b[6], 20.0);
        assert!(b.windows(2).all(|w| w[0] <= w[1]), "{b:?}");
        // The bias pushed later planes into the far plane: empty splits.
        assert!(b.windows(2).any(|w| w[0] == w[1]), "{b:?}");
    }

    #[test]
    #[allow(deprecated)]
    fn clip_depth_matches_glam_projection() {
        let (n, f) = (0.3, 250.0);
        let p = glam::dcamera::rh::proj::directx::perspective(1.0, 1.5, n, f);
        for z in [0.3, 1.0, 17.0, 250.0] {
            let c = p * glam::DVec4::new(0.0, 0.0, -z, 1.0);
            assert!((c.z / c.w - clip_depth(n, f, z)).abs() < 1e-12, "{z}");
        }
        assert_eq!(clip_depth(n, f, n), 0.0);
        assert!((clip_depth(n, f, f) - 1.0).abs() < 1e-15);
    }
}
