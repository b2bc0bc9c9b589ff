//! The light's view frame of a map, for engines that upload a view and a
//! projection separately: `clip_from_world = clip_from_view · view_from_world`.

use crate::project::from_rows;
use glam::{DMat4, DVec3, DVec4};
use shadowfocus_geom::{unit_direction, Body, Light};

/// A rigid, right-handed `view_from_world` for the map `clip_from_world`
/// of `light` over `body` (see [`crate::ShadowMap::light_view`]).
///
/// Axis: a finite light's map has its `w` row through the light,
/// `w = g·(x − l)`, so `g` points to where the map sees (`w > 0`); a
/// directional light's `w` is constant along the light, whose travel
/// direction is the axis. Up: the map's `y` row gradient, made
/// perpendicular to the axis.
pub(crate) fn view_from_world(light: &Light, clip_from_world: &DMat4, body: &Body) -> DMat4 {
    let m = clip_from_world;
    let (eye, forward) = match *light {
        Light::Directional { direction } => {
            let d = unit_direction(direction);
            let (lo, hi) = bounds(body.vertices());
            ((lo + hi) * 0.5 - d * (hi - lo).length(), d)
        }
        Light::Point { position } | Light::Spot { position, .. } => {
            let g = m.row(3).truncate().normalize_or_zero();
            (position, if g == DVec3::ZERO { DVec3::NEG_Z } else { g })
        }
    };
    // NOTE: right = forward × y, cleared of any component along forward (a
    // short cross product, y near the axis, carries its rounding there) and
    // normalised, then up = right × forward: both unit and perpendicular to
    // rounding, as long as y is not within 2⁻²⁰ of the axis (then any
    // perpendicular will do: the map's y row has almost no component across
    // the axis).
    let y = m.row(1).truncate();
    let across = forward.cross(y);
    let right = if across.length() > y.length() * (1.0 / (1u64 << 20) as f64) {
        (across - forward * forward.dot(across)).normalize()
    } else {
        forward.any_orthonormal_vector()
    };
    let up = right.cross(forward);
    // Rows: right, up and −forward, each as a plane through the eye.
    let row = |a: DVec3| a.extend(-a.dot(eye));
    from_rows(row(right), row(up), row(-forward), DVec4::W)
}

/// The inverse of a rigid `view_from_world`: transposed rotation, and the
/// eye as translation.
pub(crate) fn world_from_view(view: &DMat4) -> DMat4 {
    let r = glam::DMat3::from_mat4(*view).transpose();
    let eye = -(r * view.w_axis.truncate());
    DMat4::from_cols(r.x_axis.extend(0.0), r.y_axis.extend(0.0), r.z_axis.extend(0.0), eye.extend(1.0))
}

/// Bounding box of `pts` (the origin for none).
fn bounds(pts: &[DVec3]) -> (DVec3, DVec3) {
    if pts.is_empty() {
        return (DVec3::ZERO, DVec3::ZERO);
    }
    pts.iter().fold((DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)), |(lo, hi), p| (lo.min(*p), hi.max(*p)))
}
