//! The smallest possible maximum perspective aliasing for a texel budget.
//!
//! Model (the perspective-aliasing analysis of the PSSM paper, eq. 1–2, and
//! Lloyd et al.'s logarithmic parameterisation): receivers are seen at view
//! depths `z ∈ [n, f]`, the angle terms `cos φ / cos θ` are taken as 1, and
//! pixels are square with focal length `P = H / (2 tan(fovy/2))` pixels.
//!
//! Derivation. Aliasing here is what the renderer measures: screen pixels
//! per texel, `e = 1/sqrt(texels per pixel)`, an area ratio. Cut the view
//! frustum into slabs `[z, z + dz]`. A slab spans the full image width `W`
//! laterally and `P·dz/z` pixels in depth (a depth step `dz` at depth `z`
//! projects to `P·dz/z` pixels), so it covers `W·P·dz/z` pixels. If every
//! point keeps `e ≤ a`, that slab needs at least `W·P·dz/(z·a²)` texels, and
//! all slabs together
//!
//! ```text
//!   T ≥ ∫ₙᶠ W·P/(z·a²) dz = W·P·ln(f/n)/a²   ⇒   a ≥ sqrt(W·P·ln(f/n) / T).
//! ```
//!
//! Equality holds for the parameterisation whose depth coordinate is
//! `s = ln(z/n)/ln(f/n)` (texel density ∝ 1/z, the PSSM paper's eq. 2 in the
//! limit of infinitely many splits) with the lateral coordinate perspective
//! (`x/z`): every slab then gets exactly the texels it needs. No
//! parameterisation of `T` texels does better in this model, so a measured
//! `max e / a_min` is how far a method is from ideal (real scenes add the
//! angle terms, so ratios below 1 are possible at grazing light and
//! ratios well above 1 are usual).

/// `sqrt(W·P·ln(f/n)/T)`: the least maximum aliasing (screen pixels per
/// texel) any parameterisation of `texels` texels can reach over `[near, far]`.
/// `None` for a non-positive or non-finite input.
pub fn min_max_aliasing(width: u32, height: u32, fovy: f64, near: f64, far: f64, texels: f64) -> Option<f64> {
    // NOTE: every comparison is false for NaN, so NaN input is rejected too.
    let ok = width > 0 && height > 0 && fovy > 0.0 && fovy < std::f64::consts::PI && near > 0.0 && far > near && texels > 0.0;
    if !(ok && far.is_finite() && texels.is_finite()) {
        return None;
    }
    let p = height as f64 / (2.0 * (0.5 * fovy).tan());
    // NOTE: ln_1p of (f − n)/n keeps the log accurate when f/n is close to 1.
    let log_ratio = ((far - near) / near).ln_1p();
    Some((width as f64 * p * log_ratio / texels).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bound_scales_as_inverse_square_root_of_budget() {
        let a = min_max_aliasing(640, 360, 1.0, 0.5, 200.0, 1024.0 * 1024.0).unwrap();
        let b = min_max_aliasing(640, 360, 1.0, 0.5, 200.0, 4.0 * 1024.0 * 1024.0).unwrap();
        assert!((a / b - 2.0).abs() < 1e-12, "{a} {b}");
    }

    #[test]
    fn log_parameterisation_meets_the_bound() {
        // Discretise: T texels spread with density ∝ 1/z over [n, f]; the
        // worst slab's aliasing must equal the bound.
        let (w, h, fovy, n, f, t) = (320u32, 180u32, 0.9f64, 0.3, 300.0, 512.0 * 512.0);
        let a = min_max_aliasing(w, h, fovy, n, f, t).unwrap();
        let p = h as f64 / (2.0 * (0.5 * fovy).tan());
        let k = 4096;
        let mut worst: f64 = 0.0;
        for i in 0..k {
            let z0 = n * (f / n).powf(i as f64 / k as f64);
            let z1 = n * (f / n).powf((i + 1) as f64 / k as f64);
            let texels = t / k as f64;
            let pixels = w as f64 * p * (z1 / z0).ln();
            worst = worst.max((pixels / texels).sqrt());
        }
        assert!((worst / a - 1.0).abs() < 1e-9, "{worst} vs {a}");
        // A uniform depth parameterisation is worse, by a lot for f/n = 1000.
        let mut uniform: f64 = 0.0;
        for i in 0..k {
            let z0 = n + (f - n) * i as f64 / k as f64;
            let z1 = n + (f - n) * (i + 1) as f64 / k as f64;
            uniform = uniform.max((w as f64 * p * (z1 / z0).ln() / (t / k as f64)).sqrt());
        }
        assert!(uniform > 5.0 * a, "{uniform} vs {a}");
    }

    #[test]
    fn bad_input_is_none() {
        assert!(min_max_aliasing(0, 1, 1.0, 1.0, 2.0, 1.0).is_none());
        assert!(min_max_aliasing(1, 1, 1.0, 2.0, 2.0, 1.0).is_none());
        assert!(min_max_aliasing(1, 1, f64::NAN, 1.0, 2.0, 1.0).is_none());
        assert!(min_max_aliasing(1, 1, 1.0, 1.0, f64::INFINITY, 1.0).is_none());
    }
}
