//! The focused uniform map: the light's central projection, turned to the
//! least-area rectangle around the body's image, cropped.

use super::{light_space, orient, Fitted, SplitView};
use crate::project::crop;
use crate::settings::Method;
use glam::{DMat4, DVec3};
use shadowfocus_geom::{Body, Light};

pub(super) fn uniform(sv: &SplitView, light: &Light, body: &Body) -> Option<Fitted> {
    let verts = body.vertices();
    let c = light_space(sv, light, verts, sv.basis.forward)?;
    uniform_from(&c.m, verts, sv)
}

/// The uniform map of the central projection `m`: turned to the
/// least-area rectangle around the body's image, then cropped.
pub(super) fn uniform_from(m: &DMat4, verts: &[DVec3], sv: &SplitView) -> Option<Fitted> {
    let m = orient(m, verts, sv);
    Some(Fitted::plain(crop(&m, verts, sv.settings.f32_origin, sv.settings.clip)?, Method::Uniform))
}
