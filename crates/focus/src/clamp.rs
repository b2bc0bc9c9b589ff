//! Depth clamping ("pancaking"): each map's depth range fitted to its
//! receivers only.
//!
//! Shadows are looked up only at visible, lit points: the receivers
//! `R_i = V_i ∩ S ∩ L ⊆ H_i`. A caster between the light and `R_i` matters
//! only through being nearer the light than the receivers it shadows, and
//! with depth clamping (wgpu `unclipped_depth`, Vulkan `depthClamp`,
//! Direct3D `DepthClipEnable = false`) the rasteriser writes such a caster
//! at the range's near end instead of clipping it: it still occludes every
//! receiver. So the depth row only has to hold `R_i`, and the depth
//! resolution `H_i` would spend on the space toward the light goes to the
//! receivers. The `x`, `y` and `w` rows still hold all of `H_i`.
//!
//! A map without receivers cannot change a pixel: it becomes empty.
//!
//! `R_i` is computed as a focus body: for a point `p` inside `V_i`,
//! `hull(V_i ∪ p) = V_i`, so the body of a light at `p` is
//! `V_i ∩ S ∩ L` (with the map's own frustum as `L` where it has one:
//! spot lights, cube faces, truncated point lights).

use crate::clip::ClipConvention;
use crate::error::FocusError;
use crate::fit::f32_matrix;
use crate::project::{crop, from_rows};
use crate::result::{FocusResult, MapState};
use crate::settings::FocusSettings;
use glam::DVec3;
use shadowfocus_geom::{Aabb, Frustum, Light};

/// Refits the depth row of every active map of `out` to its receivers;
/// `frusta[i]` is split `i`'s view frustum.
pub(crate) fn clamp_depths(
    out: &mut FocusResult,
    frusta: &[Option<Frustum>],
    scene: &Aabb,
    settings: &FocusSettings,
) -> Result<(), FocusError> {
    let (maps, focuser, receivers) = out.maps_and_work();
    // The depth row keeps its orientation: the map's row is already in the
    // convention (reversed where asked), so it is re-centred without
    // reversing it a second time.
    let clip = ClipConvention { reversed_z: false, ..settings.clip };
    for map in maps.iter_mut().filter(|m| m.fit.state == MapState::Active) {
        let Some(view) = &frusta[map.split] else { continue };
        let p = view.corners().iter().fold(DVec3::ZERO, |s, c| s + *c) * 0.125;
        let light = match map.light {
            Light::Spot { frustum, .. } => Light::Spot { position: p, frustum },
            _ => Light::Point { position: p },
        };
        focuser.focus_into(receivers, view, &light, scene)?;
        if receivers.is_empty() {
            // No visible point is lit through this map: it cannot change a
            // pixel, and needs no shadow pass.
            map.set_empty();
            continue;
        }
        let Some(c) = crop(&map.fit.clip_from_world, receivers.vertices(), settings.f32_origin, clip) else { continue };
        let m = map.fit.clip_from_world;
        let m = from_rows(m.row(0), m.row(1), c.m.row(2), m.row(3));
        map.fit.clip_from_world = m;
        map.fit.clip_from_world_f32 = f32_matrix(&m, settings.f32_origin);
        map.fit.f32_exact &= c.f32_exact;
        map.fit.depth_clamp = true;
    }
    Ok(())
}
