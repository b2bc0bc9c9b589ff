//! Fitting to the receivers: each map's image (its footprint) or its depth
//! range, or both, fitted to the part of its body that can be seen.
//!
//! Shadows are looked up only at visible, lit points: the receivers
//! `R_i = V_i ∩ S ∩ L ⊆ H_i`. A caster matters only through shadowing one
//! of them, along the light ray through that receiver.
//!
//! - **Footprint** ([`Footprint::Receivers`]). Every method's map is a
//!   projection in which a light ray keeps its `x/w, y/w` (orthographic
//!   along a directional light, central from a point light, and PSM's
//!   post-perspective light is again one or the other), so the light rays
//!   through `R_i` fill exactly the part of the map's image that `R_i`
//!   covers: the `x`, `y` rows only have to hold `R_i`. The texels `H_i`
//!   would spend on casters over empty space (under the ground, beyond the
//!   scene's walls) go to the receivers. The `z` and `w` rows still hold
//!   all of `H_i`, so every caster on those rays is in the depth range.
//!   The image is grown by the lookup filter's reach in texels, so that a
//!   filter tap beside a receiver at the image's edge still reads a texel
//!   the map rendered.
//! - **Depth** ([`crate::FocusSettings::depth_clamp`], "pancaking"). A
//!   caster between the light and `R_i` matters only through being nearer
//!   the light than the receivers it shadows, and with depth clamping
//!   (wgpu `unclipped_depth`, Vulkan `depthClamp`, Direct3D
//!   `DepthClipEnable = false`) the rasteriser writes such a caster at the
//!   range's near end instead of clipping it: it still occludes every
//!   receiver. So the depth row only has to hold `R_i`, and the depth
//!   resolution `H_i` would spend on the space toward the light goes to
//!   the receivers.
//!
//! A map without receivers cannot change a pixel: it becomes empty.
//!
//! `R_i` is computed as a focus body: for a point `p` inside `V_i`,
//! `hull(V_i ∪ p) = V_i`, so the body of a light at `p` is
//! `V_i ∩ S ∩ L` (with the map's own frustum as `L` where it has one:
//! spot lights, cube faces, truncated point lights). Culling stays on
//! `H_i` ([`crate::cull_casters`]).

use crate::clip::ClipConvention;
use crate::error::FocusError;
use crate::methods::light_point;
use crate::project::f32_matrix;
use crate::project::{crop_grown, from_rows, texel_size};
use crate::result::{FocusResult, MapState, ShadowMap};
use crate::settings::Footprint;
use crate::view::PreparedView;
use glam::{DMat4, DVec3};
use shadowfocus_geom::{Aabb, Body, Light};

/// Refits every active map of `out` to its receivers, as the view's
/// settings ask (a footprint, a depth range, or both).
pub(crate) fn fit_receivers(out: &mut FocusResult, view: &PreparedView, scene: &Aabb) -> Result<(), FocusError> {
    // With receiver boxes, every receiver lies in their bounds too.
    let scene = match view.settings().receivers.bounds() {
        None => Some(*scene),
        Some(b) => intersection(scene, &b),
    };
    let (maps, focuser, receivers) = out.maps_and_work();
    for map in maps.iter_mut().filter(|m| m.fit.state == MapState::Active) {
        let Some(scene) = &scene else {
            // No receiver in the scene box: nothing to shadow.
            map.set_empty();
            continue;
        };
        let mut cut = None;
        let Some(frustum) = view.frustum_in(map.split, map.split_range, &mut cut)? else { continue };
        let p = frustum.corners().iter().fold(DVec3::ZERO, |s, c| s + *c) * 0.125;
        let light = match map.light {
            Light::Spot { frustum, .. } => Light::Spot { position: p, frustum },
            _ => Light::Point { position: p },
        };
        focuser.focus_into(receivers, frustum, &light, scene)?;
        if receivers.is_empty() {
            // No visible point is lit through this map: it cannot change a
            // pixel, and needs no shadow pass.
            map.set_empty();
            continue;
        }
        refit(map, receivers, view);
    }
    Ok(())
}

/// The common part of two boxes; `None` where they do not meet.
fn intersection(a: &Aabb, b: &Aabb) -> Option<Aabb> {
    let (min, max) = (a.min.max(b.min), a.max.min(b.max));
    min.cmple(max).all().then_some(Aabb { min, max })
}

/// The rows of `map` that the settings fit to the receivers `r`, refitted.
fn refit(map: &mut ShadowMap, r: &Body, view: &PreparedView) {
    let settings = view.settings();
    let grow = match settings.footprint {
        Footprint::Body => None,
        Footprint::Receivers { margin_texels } => Some(margin_grow(margin_texels, map.fit.resolution)),
    };
    // The depth row keeps its orientation: the map's row is already in the
    // convention (reversed where asked), so it is re-centred without
    // reversing it a second time.
    let clip = ClipConvention { reversed_z: false, ..settings.clip };
    let m = map.fit.clip_from_world;
    let Some(c) = crop_grown(&m, r.vertices(), settings.f32_origin, clip, grow.unwrap_or(1.0)) else { return };
    let (x, y) = if grow.is_some() { (c.m.row(0), c.m.row(1)) } else { (m.row(0), m.row(1)) };
    let z = if settings.depth_clamp { c.m.row(2) } else { m.row(2) };
    let m = from_rows(x, y, z, m.row(3));
    map.fit.clip_from_world = m;
    map.fit.clip_from_world_f32 = f32_matrix(&m, settings.f32_origin);
    map.fit.f32_exact &= c.f32_exact;
    map.fit.depth_clamp = settings.depth_clamp;
    if grow.is_some() {
        map.fit.footprint = settings.footprint;
        map.fit.texel_size = texel_sizes(&m, &map.light, view, map.split_range, map.fit.resolution);
    }
}

/// The factor [`crop_grown`] grows a receiver footprint by for a margin of
/// `margin_texels` on each side of a map `resolution` texels wide: the
/// receivers fill `1 − 2·margin / resolution` of its side.
pub(crate) fn margin_grow(margin_texels: f64, resolution: u32) -> f64 {
    1.0 / (1.0 - 2.0 * margin_texels / resolution as f64)
}

/// [`crate::MapFit::texel_size`] of a matrix `resolution` texels wide.
pub(crate) fn texel_sizes(m: &DMat4, light: &Light, view: &PreparedView, [near, far]: [f64; 2], resolution: u32) -> [f64; 2] {
    let (eye, fwd) = (view.camera().eye, view.forward());
    let lp = light_point(light);
    [texel_size(m, lp, eye + fwd * near, resolution), texel_size(m, lp, eye + fwd * far, resolution)]
}
