//! Stable LiSPSM and TSM maps of a directional light [LISPSM04, TSM04]: the
//! method's own warp with every parameter on a lattice fixed in the world,
//! so that while the parameters hold, the map is one warped texel grid
//! fixed in the world and the crop moves it by whole texels.
//!
//! The map is `crop ∘ warp ∘ Λ`, as every method's, each stage world-fixed:
//! - `Λ`: the light's orthographic image in the stable uniform map's
//!   world-fixed frame (`ξ`, `η` in world units), turned so that `η` runs
//!   along the image of the warp's view direction quantised to sixteenths of
//!   a turn ([`DIRECTIONS`]);
//! - the warp: the perspective with centre `(ξ_a, η_a)` in that image, a
//!   distance `n` before the body: `α = (ξ − ξ_a)/t`, `β = 1 − n/t`,
//!   `t = η − η_a`. `n` is the method's own (`n_opt` for LiSPSM, the 80 %
//!   rule for TSM) rounded up to a quarter octave (rounding up weakens the
//!   warp); the centre lies on a grid of `n/4`, `η_a` rounded away from the
//!   body, so `t ≥ n` on the body;
//! - the crop: half extents in `α` and `β` on quarter octaves, the centre
//!   snapped to the texel grid anchored at `α = β = 0`; the stored depth
//!   `(d·x − z_c)·(n/2)/(z_h t)` mapped from `[−1, 1]` to the convention's
//!   range, with `z_c`, `z_h` quantised as the stable uniform map's. Along a
//!   light ray `t` is constant, so the depth orders the ray; it lies in
//!   `[−1, 1]` wherever `t ≥ n/2`.
//!
//! With a [`crate::FitState`], each step is held while it still holds the
//! body and stays near this frame's choice ([`WarpHold`]): the direction
//! within [`DIRECTION_HOLD`] sixteenths of the view's, `n` within
//! `[1/2, 4]` of the method's ([`STRENGTH_HOLD`]), the centre between `n/2`
//! and `2n` before the body and within `2n` of the method's centre line
//! across it ([`APEX_HOLD`]), each extent at most [`EXTENT_HOLD`] steps
//! looser than the tightest. Without a
//! state every step is this frame's nearest, and the map changes where a
//! step does.
//!
//! A warp the prediction finds worse than the stable uniform map, or that
//! loses the f32 guarantee the stable uniform map keeps, is given up for that
//! map (`warp_limited`): the stable uniform map is kept. The prediction's
//! verdict has hysteresis too: a new warp must be predicted no worse, a held
//! one is kept while it is not worse by more than [`GUARD_HOLD`], so that a
//! split whose warp hovers at the margin does not switch grids every frame.
//! Stateless fits (every sweep) keep the plain rule.

use super::stable::{convention_row, inside_by, quantise_depth, stable};
use super::warp::Frame;
use super::{light_point, rotate_image, Fitted, SplitView};
use crate::frame::tangent_frame;
use crate::predict::Samples;
use crate::project::{from_rows, Cropped};
use crate::state::WarpHold;
use glam::{DMat4, DVec2, DVec3, DVec4};
use shadowfocus_geom::{unit_direction, Body, Light, UNIT_ROUNDOFF_F32};
use std::f64::consts::TAU;

/// Warp directions per turn.
pub(crate) const DIRECTIONS: i16 = 16;
/// A held direction is kept while the view's is within this many
/// sixteenths of a turn of it (45°).
const DIRECTION_HOLD: f64 = 2.0;
/// Strength and extent steps per octave.
const STEPS_PER_OCTAVE: f64 = 4.0;
/// A held extent is kept while at most this many steps looser than the
/// tightest (1.5 octaves: a body that shrinks in the warped image as the eye
/// moves keeps its grid, at up to 2.8× the tightest texels across it).
const EXTENT_HOLD: f64 = 6.0;
/// A held apex is kept while at most this many `n` across the method's
/// centre line, and at most this many `n` before the body.
const APEX_HOLD: f64 = 2.0;
/// A held strength is kept while `n` is within `[2^(−S/4), 2^(2S/4)]` of
/// the method's, `S` this many steps.
const STRENGTH_HOLD: f64 = 4.0;
/// The warp guard's hysteresis: a new warp's predicted aliasing must be no
/// worse than the stable uniform map's, a warp held from the last frame is
/// kept while at most this factor of it (the prediction moves by ±20 % from
/// frame to frame on the built-in orbits).
const GUARD_HOLD: f64 = 1.25;
/// The apex grid: `n / APEX_GRID`.
const APEX_GRID: f64 = 4.0;
/// Lattice indices beyond this are refused (the grid would not be exact).
const MAX_INDEX: f64 = (1u64 << 52) as f64;

/// The stable warped map of `body` for the directional `light`, the warp
/// along `v` with the strength and centre line `warp_of` gives in the frame
/// (see the module docs); `None` where the light is not directional.
pub(super) fn stable_warped(
    sv: &SplitView,
    light: &Light,
    body: &Body,
    v: DVec3,
    hold: &WarpHold,
    warp_of: impl FnOnce(&Frame) -> (f64, f64),
) -> Option<Fitted> {
    let s = sv.settings;
    let Light::Directional { direction } = *light else { return None };
    let d = unit_direction(direction);
    let reference = stable(sv, light, body)?;
    let given_up = |limited: bool| Some(Fitted { method: s.method, warp_vanished: !limited, warp_limited: limited, ..reference });
    let (ex, ey) = tangent_frame(d, DVec3::Z, DVec3::X);
    let Some(k) = direction_step(DVec2::new(ex.dot(v), ey.dot(v)), v.length(), hold) else { return given_up(false) };
    let turn = f64::from(k) * (TAU / f64::from(DIRECTIONS));
    let m = rotate_image(&from_rows(ex.extend(0.0), ey.extend(0.0), d.extend(0.0), DVec4::W), DVec2::new(turn.cos(), turn.sin()));
    let verts = body.vertices();
    let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
    for p in verts {
        let q = DVec2::new(m.row(0).truncate().dot(*p), m.row(1).truncate().dot(*p));
        lo = lo.min(q);
        hi = hi.max(q);
    }
    let cam = sv.camera;
    let p_near = cam.eye + sv.basis.forward * cam.near;
    let frame = Frame { m, lp: light_point(light), p_near, p_ref: p_near, xi: (lo.x, hi.x), eta: (lo.y, hi.y) };
    let (epsilon, xi_c) = warp_of(&frame);
    if !(epsilon > 0.0 && (1.0 / epsilon).is_finite() && xi_c.is_finite()) {
        return given_up(false);
    }
    let held = (hold.is_held() && hold.direction == k).then_some(hold);
    let Some(strength) = strength_step(1.0 / epsilon, held) else { return given_up(true) };
    let n = step_value(strength);
    let held = held.filter(|h| h.strength == strength);
    let Some(apex) = apex_steps(n, xi_c, lo.y, held) else { return given_up(true) };
    let held = held.filter(|h| h.apex == apex);
    let g = n / APEX_GRID;
    let (xi_a, eta_a) = (apex[0] as f64 * g, apex[1] as f64 * g);
    // Rows of the warp (see the module docs): W = t, X = ξ − ξ_a,
    // Y = t − n, so α = X/W, β = Y/W.
    let e_w = DVec4::W;
    let w_row = m.row(1) - e_w * eta_a;
    let x_row = m.row(0) - e_w * xi_a;
    let y_row = w_row - e_w * n;
    let Some((rows, extent)) = crop_rows([x_row, y_row], w_row, verts, s.resolution, held.map(|h| h.extent)) else { return given_up(true) };
    let (zlo, zhi) = verts.iter().map(|p| d.dot(*p)).fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), z| (lo.min(z), hi.max(z)));
    let (zc, zh) = quantise_depth(0.5 * (zlo + zhi), (0.5 * (zhi - zlo)).max((zlo.abs().max(zhi.abs()) + n) * (1.0 / (1u64 << 20) as f64)));
    // The `[0, 1]` row: ½ (1 + (d·x − z_c)·(n/2)/(z_h t)), times W = t.
    let d01 = ((m.row(2) - e_w * zc) * (0.5 * n / zh) + w_row) * 0.5;
    let mm = from_rows(rows[0], rows[1], convention_row(s.clip, d01, w_row), w_row);
    // NOTE: checked as the stable spot map is, with the `[0, 1]` row and
    // twice the rounding bound, so that every convention's outcome is the
    // same (see `stable_spot`).
    let canonical = from_rows(rows[0], rows[1], d01, w_row);
    if !(mm.is_finite() && inside_by(&canonical, verts, 0.0, DVec3::ZERO, 16.0 * f64::EPSILON)) {
        return given_up(true);
    }
    let o = s.f32_origin;
    let f32_exact = inside_by(&(canonical * DMat4::from_translation(o)), verts, 0.0, o, 16.0 * UNIT_ROUNDOFF_F32);
    if reference.f32_exact && !f32_exact {
        return given_up(true);
    }
    if s.warp_guard {
        // Hysteresis: a new warp must not lose; one held whole from the last
        // frame stays while it does not lose by more than GUARD_HOLD.
        let factor = if held.is_some_and(|h| h.extent == extent) { GUARD_HOLD } else { 1.0 };
        let mut samples = Samples::new(sv, body, light_point(light));
        // NOTE: with no sample to judge by, the warp is given up (see `choose_warp`).
        let target = samples.judge(&reference.m);
        if !target.is_some_and(|t| samples.predict(&mm).is_some_and(|p| p.no_worse_than_by(&t, factor))) {
            return given_up(true);
        }
    }
    let mut out = Fitted::plain(Cropped { m: mm, f32_exact }, s.method);
    out.warp_near = n;
    out.held.warp = WarpHold { direction: k, strength, extent, apex };
    Some(out)
}

/// The image rows `rows` (over `w_row`) cropped to the body's image: each
/// half extent on the quarter-octave ladder ([`extent_step`], holding
/// `held`'s steps where they still fit), the centre snapped to the texel
/// grid anchored at image 0; with the extent steps chosen.
fn crop_rows(rows: [DVec4; 2], w_row: DVec4, verts: &[DVec3], resolution: u32, held: Option<[i16; 2]>) -> Option<([DVec4; 2], [i16; 2])> {
    let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
    for p in verts {
        let hp = p.extend(1.0);
        let q = DVec2::new(rows[0].dot(hp), rows[1].dot(hp)) / w_row.dot(hp);
        lo = lo.min(q);
        hi = hi.max(q);
    }
    let res = f64::from(resolution);
    let room = 1.0 - 1.0 / res - 1.0 / (1u64 << 16) as f64;
    let (mut out, mut extent) = ([DVec4::ZERO; 2], [0i16; 2]);
    for i in 0..2 {
        let k = extent_step(0.5 * (hi[i] - lo[i]) / room, held.map(|h| h[i]))?;
        let size = step_value(k);
        let texel = 2.0 * size / res;
        let centre = (0.5 * (lo[i] + hi[i]) / texel).round() * texel;
        out[i] = (rows[i] - w_row * centre) / size;
        extent[i] = k;
    }
    Some((out, extent))
}

/// `2^(k/4)`.
fn step_value(k: i16) -> f64 {
    (f64::from(k) / STEPS_PER_OCTAVE).exp2()
}

/// The direction step of the image direction `dir` of a view vector of
/// length `len`: the held one while within [`DIRECTION_HOLD`], else the
/// nearest; `None` where the view has (all but) no image direction.
fn direction_step(dir: DVec2, len: f64, hold: &WarpHold) -> Option<i16> {
    if !(dir.length() > len * (1.0 / (1u64 << 26) as f64)) {
        return None;
    }
    let steps = f64::from(DIRECTIONS);
    let at = dir.y.atan2(dir.x) / (TAU / steps);
    if hold.is_held() {
        let off = (at - f64::from(hold.direction)).rem_euclid(steps);
        if off.min(steps - off) <= DIRECTION_HOLD {
            return Some(hold.direction);
        }
    }
    Some(at.round().rem_euclid(steps) as i16)
}

/// The strength step for the method's warp distance `n`: the held one
/// while `2^(k/4)` lies in `[n/2, 4n]` ([`STRENGTH_HOLD`]), else `n`
/// rounded up to a quarter octave; `None` where that is out of range.
fn strength_step(n: f64, held: Option<&WarpHold>) -> Option<i16> {
    let at = STEPS_PER_OCTAVE * n.log2();
    if let Some(h) = held {
        let k = f64::from(h.strength);
        if k >= at - STRENGTH_HOLD && k <= at + 2.0 * STRENGTH_HOLD {
            return Some(h.strength);
        }
    }
    let k = at.ceil();
    (k.abs() < 4000.0).then_some(k as i16)
}

/// The apex on the grid `g = n/4`: the held one while it lies between
/// `n/2` and `2n` before the body's near end `eta0` and within `2n` of the
/// centre line `xi_c` ([`APEX_HOLD`]); else `ξ_c` rounded and `η0 − n` rounded away from the
/// body. `None` where an index would exceed [`MAX_INDEX`].
fn apex_steps(n: f64, xi_c: f64, eta0: f64, held: Option<&WarpHold>) -> Option<[i64; 2]> {
    let g = n / APEX_GRID;
    if let Some(h) = held {
        let (xa, ea) = (h.apex[0] as f64 * g, h.apex[1] as f64 * g);
        let ahead = eta0 - ea;
        if (xa - xi_c).abs() <= APEX_HOLD * n && ahead >= 0.5 * n && ahead <= APEX_HOLD * n {
            return Some(h.apex);
        }
    }
    let (a, b) = ((xi_c / g).round(), ((eta0 - n) / g).floor());
    (a.abs() < MAX_INDEX && b.abs() < MAX_INDEX).then_some([a as i64, b as i64])
}

/// The extent step for a half extent of at least `need`: the held one while
/// it holds and is at most [`EXTENT_HOLD`] steps looser than the tightest,
/// else the tightest; `None` where out of range.
fn extent_step(need: f64, held: Option<i16>) -> Option<i16> {
    // NOTE: a flat body has no extent across; 2⁻⁴⁰ keeps the matrix
    // invertible (the f32 check decides whether f32 resolves it).
    let need = need.max(1.0 / (1u64 << 40) as f64);
    let mut at = (STEPS_PER_OCTAVE * need.log2()).ceil();
    if !(at.abs() < 4000.0) {
        return None;
    }
    // NOTE: log2 and exp2 round; the step must hold `need` exactly.
    if step_value(at as i16) < need {
        at += 1.0;
    }
    if let Some(k) = held {
        let k = f64::from(k);
        if k >= at && k <= at + EXTENT_HOLD {
            return held;
        }
    }
    Some(at as i16)
}
