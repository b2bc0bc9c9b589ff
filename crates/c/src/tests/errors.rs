//! Every status code, reached; nothing written where it must not be.

use super::common::*;
use crate::error::{focus_status, Failure};
use crate::*;
use shadowfocus_focus::FocusError;
use shadowfocus_geom::GeomError;
use std::ffi::{c_int, CStr};
use std::ptr;

const OK: c_int = SfStatus::SF_OK as c_int;
const NULL: c_int = SfStatus::SF_ERR_NULL_POINTER as c_int;
const INVALID: c_int = SfStatus::SF_ERR_INVALID_INPUT as c_int;
const SMALL: c_int = SfStatus::SF_ERR_BUFFER_TOO_SMALL as c_int;

static NAN_BOX: [SfAabb; 1] = [SfAabb { min: [0.0; 3], max: [1.0, f64::NAN, 1.0] }];

fn sun() -> SfLight {
    lights()[0]
}

/// A successful fit (4 maps) in `ctx`.
fn fit_ok(ctx: &Ctx) -> Vec<SfMap> {
    let mut maps = vec![canary_map(); SF_MAX_MAPS as usize];
    let (rc, n) = ctx.fit(&camera(5), &sun(), &scene(), &settings(SfMethod::SF_METHOD_LISPSM, 4), &mut maps);
    assert_eq!((rc, n), (OK, 4), "{}", ctx.error());
    maps.truncate(n);
    maps
}

/// A change to one input of a fit.
type Edit = Box<dyn FnOnce(&mut SfCamera, &mut SfLight, &mut SfAabb, &mut SfSettings)>;

/// sf_fit with one input changed; returns the status and the message.
fn fit_with(ctx: &Ctx, edit: impl FnOnce(&mut SfCamera, &mut SfLight, &mut SfAabb, &mut SfSettings)) -> (c_int, String) {
    let (mut cam, mut light, mut box_, mut s) = (camera(5), sun(), scene(), settings(SfMethod::SF_METHOD_LISPSM, 4));
    edit(&mut cam, &mut light, &mut box_, &mut s);
    let mut maps = vec![canary_map(); SF_MAX_MAPS as usize];
    let (rc, n) = ctx.fit(&cam, &light, &box_, &s, &mut maps);
    if rc != OK {
        assert_eq!(n, 0, "no maps counted on error {rc}");
    }
    (rc, ctx.error())
}

#[test]
fn null_pointers_are_reported_not_dereferenced() {
    let ctx = Ctx::new();
    let (cam, light, box_, s) = (camera(0), sun(), scene(), settings(SfMethod::SF_METHOD_UNIFORM, 1));
    let mut maps = vec![canary_map(); 4];
    let mut n = 7usize;
    let m = maps.as_mut_ptr();
    // SAFETY: every non-NULL pointer is valid; NULL ones must be caught.
    unsafe {
        assert_eq!(sf_fit(ptr::null_mut(), &cam, &light, &box_, &s, m, 4, &mut n), NULL);
        assert_eq!(sf_fit(ctx.0, ptr::null(), &light, &box_, &s, m, 4, &mut n), NULL);
        assert_eq!(ctx.error(), "camera is NULL");
        assert_eq!(sf_fit(ctx.0, &cam, ptr::null(), &box_, &s, m, 4, &mut n), NULL);
        assert_eq!(sf_fit(ctx.0, &cam, &light, ptr::null(), &s, m, 4, &mut n), NULL);
        assert_eq!(sf_fit(ctx.0, &cam, &light, &box_, ptr::null(), m, 4, &mut n), NULL);
        assert_eq!(sf_fit(ctx.0, &cam, &light, &box_, &s, ptr::null_mut(), 4, &mut n), NULL);
        assert_eq!(ctx.error(), "maps is NULL");
        let no_boxes = SfSettings { receiver_count: 2, ..s };
        assert_eq!(sf_fit(ctx.0, &cam, &light, &box_, &no_boxes, m, 4, &mut n), NULL);
        assert_eq!(ctx.error(), "settings.receivers is NULL");
        assert_eq!(sf_fit(ctx.0, &cam, &light, &box_, &s, m, 4, ptr::null_mut()), NULL);
        assert_eq!(sf_prepare_view(ctx.0, ptr::null(), &s), NULL);
        assert_eq!(sf_fit_light(ctx.0, &light, &box_, m, 4, ptr::null_mut()), NULL);
        assert_eq!(sf_fit_light_held(ctx.0, &light, &box_, ptr::null_mut(), m, 4, &mut n), NULL);
        assert_eq!(ctx.error(), "state is NULL");
        assert_eq!(sf_body(ptr::null_mut(), 0, ptr::null_mut(), 0, &mut n), NULL);
        assert_eq!(sf_body(ctx.0, 0, ptr::null_mut(), 5, &mut n), NULL);
        assert_eq!(sf_view_body(ctx.0, ptr::null_mut(), 0, ptr::null_mut()), NULL);
        assert_eq!(sf_cull_casters(ctx.0, 0, ptr::null(), 3, ptr::null_mut(), 0, &mut n), NULL);
        assert_eq!(ctx.error(), "boxes is NULL");
        // NULL is harmless where it is documented to be.
        sf_context_free(ptr::null_mut());
        sf_settings_default(ptr::null_mut());
        sf_fit_state_init(ptr::null_mut());
        assert_eq!(CStr::from_ptr(sf_last_error(ptr::null())).to_bytes(), b"");
        assert!(!CStr::from_ptr(sf_version()).to_bytes().is_empty());
    }
    assert!(maps.iter().all(|m| bytes(m) == bytes(&canary_map())), "nothing written on a NULL-pointer error");
}

#[test]
fn invalid_inputs_are_errors_with_messages() {
    let ctx = Ctx::new();
    let cases: Vec<(&str, Edit, &str)> = vec![
        ("NaN eye", Box::new(|c, _, _, _| c.eye[1] = f64::NAN), "camera eye is not finite"),
        ("infinite far", Box::new(|c, _, _, _| c.far_dist = f64::INFINITY), "camera far is not finite"),
        ("near = far", Box::new(|c, _, _, _| c.far_dist = c.near_dist), "near must be smaller than far"),
        ("near > far", Box::new(|c, _, _, _| c.near_dist = 500.0), "near must be smaller than far"),
        ("up parallel to forward", Box::new(|c, _, _, _| c.up = c.forward), "up is zero or parallel"),
        ("zero light direction", Box::new(|_, l, _, _| l.direction = [0.0; 3]), "light direction has zero length"),
        ("NaN light direction", Box::new(|_, l, _, _| l.direction[0] = f64::NAN), "light direction is not finite"),
        ("inverted box", Box::new(|_, _, b, _| b.min[2] = 200.0), "min > max on axis z"),
        ("spot near >= far", Box::new(|_, l, _, _| *l = SfLight { far_dist: 0.5, ..lights()[2] }), "spot light frustum"),
        ("light kind 3", Box::new(|_, l, _, _| l.kind = 3), "light.kind: 3 is not an SfLightKind value"),
        ("light kind -1", Box::new(|_, l, _, _| l.kind = -1), "light.kind: -1 is not an SfLightKind value"),
        ("method 5", Box::new(|_, _, _, s| s.method = 5), "settings.method: 5 is not an SfMethod value"),
        ("method MIN", Box::new(|_, _, _, s| s.method = c_int::MIN), "is not an SfMethod value"),
        ("split scheme 5", Box::new(|_, _, _, s| s.split_scheme = 5), "not an SfSplitScheme value"),
        ("geometric, first split not set", Box::new(|_, _, _, s| s.split_scheme = 3), "invalid setting splits.first"),
        (
            "optimal and stable",
            Box::new(|_, _, _, s| {
                s.split_scheme = 4;
                s.stable = 1;
            }),
            "moves the split planes with the view",
        ),
        ("warp direction 2", Box::new(|_, _, _, s| s.lispsm_warp = 2), "not an SfWarpDirection value"),
        ("point mode 9", Box::new(|_, _, _, s| s.point_mode = 9), "not an SfPointMode value"),
        ("orientation -3", Box::new(|_, _, _, s| s.orientation = -3), "not an SfOrientation value"),
        ("ground 7", Box::new(|_, _, _, s| s.ground = 7), "settings.ground: 7 is not an SfGround value"),
        ("ground -1", Box::new(|_, _, _, s| s.ground = -1), "settings.ground: -1 is not an SfGround value"),
        ("level, no ground", Box::new(|_, _, _, s| s.ground_at_level = 1), "a ground level needs a ground face"),
        (
            "ground level NaN",
            Box::new(|_, _, _, s| (s.ground, s.ground_at_level, s.ground_level) = (3, 1, f64::NAN)),
            "invalid setting ground.level: must be finite",
        ),
        (
            "ground level outside the box",
            Box::new(|_, _, _, s| (s.ground, s.ground_at_level, s.ground_level) = (3, 1, 1e9)),
            "invalid setting ground.level: must lie in the scene box",
        ),
        ("0 splits", Box::new(|_, _, _, s| s.splits = 0), "invalid setting splits.count"),
        ("9 splits", Box::new(|_, _, _, s| s.splits = 9), "invalid setting splits.count"),
        (
            "lambda 2",
            Box::new(|_, _, _, s| (s.split_scheme, s.lambda) = (SfSplitScheme::SF_SPLIT_PRACTICAL as c_int, 2.0)),
            "invalid setting splits.lambda",
        ),
        ("resolution 2", Box::new(|_, _, _, s| s.resolution = 2), "invalid setting resolution"),
        ("budget sizes 5", Box::new(|_, _, _, s| (s.texel_budget, s.budget_sizes) = (1 << 20, 5)), "not an SfMapSizes value"),
        ("a budget of 15 texels", Box::new(|_, _, _, s| s.texel_budget = 15), "invalid setting texel_budget.texels"),
        (
            "a budget with stable maps",
            Box::new(|_, _, _, s| (s.texel_budget, s.stable, s.split_scheme) = (1 << 20, 1, SfSplitScheme::SF_SPLIT_LOG as c_int)),
            "invalid setting texel_budget",
        ),
        ("NaN f32 origin", Box::new(|_, _, _, s| s.f32_origin[0] = f64::NAN), "invalid setting f32_origin"),
        ("negative psm near", Box::new(|_, _, _, s| s.psm_near = -1.0), "invalid setting psm.near"),
        ("NaN light_near_fixed", Box::new(|_, _, _, s| s.light_near_fixed = f64::NAN), "invalid setting light_near"),
        ("a NaN receiver box", Box::new(|_, _, _, s| (s.receivers, s.receiver_count) = (NAN_BOX.as_ptr(), 1)), "invalid setting receivers"),
        (
            "visible depth 5..1",
            Box::new(|_, _, _, s| (s.visible_depth_min, s.visible_depth_max) = (5.0, 1.0)),
            "invalid setting visible_depth",
        ),
    ];
    for (what, edit, message) in cases {
        let (rc, got) = fit_with(&ctx, edit);
        assert_eq!(rc, INVALID, "{what}: {got}");
        assert!(got.contains(message), "{what}: message {got:?} lacks {message:?}");
        // A success clears the message.
        fit_ok(&ctx);
        assert_eq!(ctx.error(), "", "{what}: message cleared by a successful call");
    }
}

#[test]
fn short_map_buffers_are_not_written_and_get_the_count() {
    let ctx = Ctx::new();
    let (cam, light, box_, s) = (camera(5), sun(), scene(), settings(SfMethod::SF_METHOD_LISPSM, 4));
    let mut n = 0;
    // SAFETY: NULL maps with capacity 0 is the documented size query.
    let rc = unsafe { sf_fit(ctx.0, &cam, &light, &box_, &s, ptr::null_mut(), 0, &mut n) };
    assert_eq!((rc, n), (SMALL, 4));
    assert!(ctx.error().contains("maps holds 0 entries, 4 needed"), "{}", ctx.error());
    for capacity in [1, 3] {
        let mut maps = vec![canary_map(); 6];
        // SAFETY: `maps` holds 6 >= capacity maps.
        let rc = unsafe { sf_fit(ctx.0, &cam, &light, &box_, &s, maps.as_mut_ptr(), capacity, &mut n) };
        assert_eq!((rc, n), (SMALL, 4), "capacity {capacity}");
        assert!(maps.iter().all(|m| bytes(m) == bytes(&canary_map())), "capacity {capacity}: a map was written");
    }
    // The fit itself was kept: its bodies are there.
    assert!(!ctx.body(0).is_empty());
}

#[test]
fn short_body_and_index_buffers_are_not_written_and_get_the_count() {
    let ctx = Ctx::new();
    fit_ok(&ctx);
    let need = ctx.body(0).len();
    assert!(need > 4);
    let canary = f64::from_bits(0x7ff4_dead_beef_0001);
    let mut v = vec![canary; 3 * need];
    let mut n = 0;
    for capacity in [0, 1, need - 1] {
        // SAFETY: `v` holds `need` >= capacity vertices.
        let rc = unsafe { sf_body(ctx.0, 0, v.as_mut_ptr(), capacity, &mut n) };
        assert_eq!((rc, n), (SMALL, need), "capacity {capacity}");
        assert!(v.iter().all(|x| x.to_bits() == canary.to_bits()), "capacity {capacity}: a vertex was written");
        // SAFETY: as above.
        let rc = unsafe { sf_view_body(ctx.0, v.as_mut_ptr(), capacity.min(1), &mut n) };
        assert_eq!(rc, SMALL);
        assert!(v.iter().all(|x| x.to_bits() == canary.to_bits()));
    }
    let boxes = [scene(), scene(), scene()];
    let mut idx = [u32::MAX; 3];
    for capacity in [0, 2] {
        // SAFETY: `idx` holds 3 >= capacity indices.
        let rc = unsafe { sf_cull_casters(ctx.0, 0, boxes.as_ptr(), 3, idx.as_mut_ptr(), capacity, &mut n) };
        assert_eq!((rc, n), (SMALL, 3), "capacity {capacity}");
        assert_eq!(idx, [u32::MAX; 3]);
    }
}

#[test]
fn bad_map_indices_boxes_and_missing_fits_are_invalid_input() {
    let ctx = Ctx::new();
    let mut n = 0;
    let mut v = [0.0; 3 * SF_MAX_BODY_VERTICES as usize];
    // SAFETY: `v` holds SF_MAX_BODY_VERTICES vertices.
    unsafe {
        assert_eq!(sf_body(ctx.0, 0, v.as_mut_ptr(), SF_MAX_BODY_VERTICES as usize, &mut n), INVALID);
        assert!(ctx.error().contains("no successful fit"), "{}", ctx.error());
        let mut m = [canary_map()];
        assert_eq!(sf_fit_light(ctx.0, &sun(), &scene(), m.as_mut_ptr(), 1, &mut n), INVALID);
        assert!(ctx.error().contains("no view prepared"), "{}", ctx.error());
    }
    fit_ok(&ctx);
    // SAFETY: as above; `idx` holds 2 indices.
    unsafe {
        assert_eq!(sf_body(ctx.0, 4, v.as_mut_ptr(), SF_MAX_BODY_VERTICES as usize, &mut n), INVALID);
        assert!(ctx.error().contains("map_index 4 is out of range: the last fit has 4 maps"), "{}", ctx.error());
        let mut idx = [0u32; 2];
        let boxes = [scene(), SfAabb { min: [0.0, f64::NAN, 0.0], max: [1.0; 3] }];
        assert_eq!(sf_cull_casters(ctx.0, 0, boxes.as_ptr(), 2, idx.as_mut_ptr(), 2, &mut n), INVALID);
        assert!(ctx.error().starts_with("boxes[1]: scene box min is not finite"), "{}", ctx.error());
        assert_eq!(sf_cull_casters(ctx.0, 9, boxes.as_ptr(), 1, idx.as_mut_ptr(), 2, &mut n), INVALID);
        // A failed fit forgets the last one.
        let mut m = [canary_map(); 4];
        let bad = SfLight { kind: 7, ..sun() };
        assert_eq!(sf_fit_light(ctx.0, &bad, &scene(), m.as_mut_ptr(), 4, &mut n), INVALID);
        assert_eq!(sf_body(ctx.0, 0, v.as_mut_ptr(), SF_MAX_BODY_VERTICES as usize, &mut n), INVALID);
        // Zero boxes: nothing kept, NULL arrays allowed.
        fit_ok(&ctx);
        assert_eq!(sf_cull_casters(ctx.0, 0, ptr::null(), 0, ptr::null_mut(), 0, &mut n), OK);
        assert_eq!(n, 0);
    }
}

/// No input this API builds reaches `NoSingleProjection` (a spot's frustum
/// is always built around its position); its mapping is checked directly.
#[test]
fn library_errors_map_to_their_codes() {
    let e = FocusError::NoSingleProjection { reason: "r" };
    let f = Failure::focus(&e);
    assert_eq!(f.status, SfStatus::SF_ERR_NO_SINGLE_PROJECTION);
    assert_eq!(f.message, e.to_string());
    assert_eq!(focus_status(&FocusError::Capacity { what: "x" }), SfStatus::SF_ERR_BUFFER_TOO_SMALL);
    assert_eq!(focus_status(&FocusError::InvalidCorners { reason: "x" }), SfStatus::SF_ERR_INVALID_INPUT);
    assert_eq!(focus_status(&FocusError::Geom(GeomError::CapacityExceeded { what: "x" })), SfStatus::SF_ERR_INTERNAL);
    assert_eq!(focus_status(&FocusError::Geom(GeomError::Unsupported { reason: "x" })), SfStatus::SF_ERR_INTERNAL);
    assert_eq!(focus_status(&FocusError::Geom(GeomError::DegenerateFrustum { what: "x", reason: "y" })), SfStatus::SF_ERR_INVALID_INPUT);
}

/// The guard every entry point runs in turns a panic into SF_ERR_INTERNAL
/// with the panic's message, and the context stays usable.
#[test]
fn a_panic_is_caught_and_reported() {
    let ctx = Ctx::new();
    fit_ok(&ctx);
    // SAFETY: a live context.
    let rc = unsafe { crate::api::guard(ctx.0, |_| panic!("boom {}", 42)) };
    assert_eq!(rc, SfStatus::SF_ERR_INTERNAL as c_int);
    assert_eq!(ctx.error(), "internal error (caught panic): boom 42");
    let mut v = [0.0; 3 * SF_MAX_BODY_VERTICES as usize];
    let mut n = 0;
    // SAFETY: `v` holds SF_MAX_BODY_VERTICES vertices.
    let rc = unsafe { sf_body(ctx.0, 0, v.as_mut_ptr(), SF_MAX_BODY_VERTICES as usize, &mut n) };
    assert_eq!(rc, INVALID, "the half-written fit is forgotten");
    fit_ok(&ctx);
    assert_eq!(ctx.error(), "");
    // SAFETY: NULL is allowed.
    assert_eq!(unsafe { crate::api::guard(ptr::null_mut(), |_| Ok(())) }, NULL);
}

/// `sf_visible_receivers` refuses NULL pointers, a bad camera, a zero
/// height, a point that is not finite, a zero normal and a bad margin, with
/// messages.
#[test]
fn visible_receivers_refuse_bad_input() {
    let ctx = Ctx::new();
    let pts = [1.0f32, -1.0, 5.0, 2.0, -1.0, 9.0];
    let nan = [1.0f32, f32::NAN, 5.0];
    let zero = [0.0f32, 1.0, 0.0, 0.0, 0.0, 0.0];
    let mut out = [SfAabb { min: [0.0; 3], max: [0.0; 3] }; SF_MAX_RECEIVER_BOXES as usize];
    let mut n = 0;
    let cam = camera(0);
    let bad_cam = SfCamera { near_dist: 500.0, ..cam };
    unsafe {
        let o = out.as_mut_ptr();
        assert_eq!(sf_visible_receivers(ptr::null_mut(), &cam, 64, pts.as_ptr(), ptr::null(), 2, 0.0, o, 16, &mut n), NULL);
        assert_eq!(sf_visible_receivers(ctx.0, ptr::null(), 64, pts.as_ptr(), ptr::null(), 2, 0.0, o, 16, &mut n), NULL);
        assert!(ctx.error().contains("camera"), "{}", ctx.error());
        assert_eq!(sf_visible_receivers(ctx.0, &cam, 64, ptr::null(), ptr::null(), 2, 0.0, o, 16, &mut n), NULL);
        assert!(ctx.error().contains("points"), "{}", ctx.error());
        assert_eq!(sf_visible_receivers(ctx.0, &cam, 64, pts.as_ptr(), ptr::null(), 2, 0.0, ptr::null_mut(), 16, &mut n), NULL);
        assert_eq!(sf_visible_receivers(ctx.0, &cam, 64, pts.as_ptr(), ptr::null(), 2, 0.0, o, 16, ptr::null_mut()), NULL);
        let cases = [
            (sf_visible_receivers(ctx.0, &bad_cam, 64, pts.as_ptr(), ptr::null(), 2, 0.0, o, 16, &mut n), "near must be smaller than far"),
            (sf_visible_receivers(ctx.0, &cam, 0, pts.as_ptr(), ptr::null(), 2, 0.0, o, 16, &mut n), "height"),
            (sf_visible_receivers(ctx.0, &cam, 64, nan.as_ptr(), ptr::null(), 1, 0.0, o, 16, &mut n), "not finite"),
            (sf_visible_receivers(ctx.0, &cam, 64, pts.as_ptr(), zero.as_ptr(), 2, 0.0, o, 16, &mut n), "not finite"),
            (sf_visible_receivers(ctx.0, &cam, 64, pts.as_ptr(), ptr::null(), 2, -1.0, o, 16, &mut n), "margin"),
            (sf_visible_receivers(ctx.0, &cam, 64, pts.as_ptr(), ptr::null(), 2, f64::NAN, o, 16, &mut n), "margin"),
        ];
        for (rc, what) in cases {
            assert_eq!(rc, INVALID, "{what}");
            assert_eq!(n, 0, "{what}");
        }
        assert_eq!(sf_visible_receivers(ctx.0, &cam, 64, pts.as_ptr(), ptr::null(), 2, 0.0, o, 16, &mut n), OK, "{}", ctx.error());
        assert_eq!(n, 1);
    }
}
