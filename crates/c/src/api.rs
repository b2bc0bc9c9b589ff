//! The exported functions. Each checks its pointers, runs inside
//! `catch_unwind` and records its outcome in the context.

use crate::context::SfContext;
use crate::convert;
use crate::error::Failure;
use crate::types::*;
use shadowfocus_focus::FitState;
use shadowfocus_geom::Body;
use std::any::Any;
use std::ffi::{c_char, c_int};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::ptr;

/// Runs `f` on the context behind `ctx`, catching panics; records the
/// message and returns the status code.
///
/// # Safety
/// `ctx` is NULL or a live context from `sf_context_new` that no other
/// thread uses during the call.
pub(crate) unsafe fn guard(ctx: *mut SfContext, f: impl FnOnce(&mut SfContext) -> Result<(), Failure>) -> c_int {
    // SAFETY: the caller passes NULL or a live, unshared context.
    let Some(ctx) = (unsafe { ctx.as_mut() }) else {
        return SfStatus::SF_ERR_NULL_POINTER as c_int;
    };
    let outcome = match catch_unwind(AssertUnwindSafe(|| f(ctx))) {
        Ok(outcome) => outcome,
        Err(payload) => {
            ctx.forget_fit();
            Err(Failure::new(SfStatus::SF_ERR_INTERNAL, format!("internal error (caught panic): {}", panic_message(&*payload))))
        }
    };
    ctx.finish(outcome) as c_int
}

fn panic_message(payload: &(dyn Any + Send)) -> &str {
    if let Some(s) = payload.downcast_ref::<&str>() {
        s
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s
    } else {
        "unknown panic payload"
    }
}

/// The value behind an input pointer.
///
/// # Safety
/// `p` is NULL or points to a readable, aligned `T` (any bit pattern of
/// the C input structs is a valid `T`).
unsafe fn input<'a, T>(p: *const T, what: &str) -> Result<&'a T, Failure> {
    // SAFETY: see above.
    unsafe { p.as_ref() }.ok_or_else(|| Failure::null(what))
}

/// Checks an output array: NULL is allowed only with capacity 0.
fn output<T>(p: *mut T, capacity: usize, what: &str) -> Result<(), Failure> {
    if p.is_null() && capacity > 0 {
        return Err(Failure::null(what));
    }
    Ok(())
}

/// Sets `*count` (checked non-NULL by `reset_count`).
///
/// # Safety
/// `count` points to a writable `size_t`.
unsafe fn set_count(count: *mut usize, n: usize) {
    // SAFETY: see above.
    unsafe { count.write(n) }
}

/// Checks `count` and sets it to 0, so that a failure leaves 0 there unless
/// it says how many entries were needed.
///
/// # Safety
/// `count` is NULL or points to a writable `size_t`.
unsafe fn reset_count(count: *mut usize) -> Result<*mut usize, Failure> {
    if count.is_null() {
        return Err(Failure::null("count"));
    }
    // SAFETY: non-NULL and writable (caller).
    unsafe { set_count(count, 0) };
    Ok(count)
}

/// Writes `n` values made by `value(i)` to `out`, if `n <= capacity`;
/// `*count = n` either way.
///
/// # Safety
/// `out` holds `capacity` writable `T`s (or is NULL with capacity 0) and
/// `count` is a writable `size_t`.
unsafe fn write_all<T>(
    out: *mut T,
    capacity: usize,
    count: *mut usize,
    n: usize,
    what: &str,
    value: impl Fn(usize) -> T,
) -> Result<(), Failure> {
    // SAFETY: `count` is writable (caller).
    unsafe { set_count(count, n) };
    if n > capacity {
        return Err(Failure::too_small(what, capacity, n));
    }
    for i in 0..n {
        // SAFETY: i < n <= capacity entries of `out` are writable (caller).
        unsafe { out.add(i).write(value(i)) };
    }
    Ok(())
}

/// Creates a context: the fit result, work spaces and message buffer, all
/// allocated here. Returns NULL only if that fails. Free it with
/// `sf_context_free`. A context is used by one thread at a time.
#[no_mangle]
pub extern "C" fn sf_context_new() -> *mut SfContext {
    catch_unwind(|| Box::into_raw(Box::new(SfContext::new()))).unwrap_or(ptr::null_mut())
}

/// Frees a context from `sf_context_new`; NULL is a no-op.
///
/// # Safety
/// `ctx` is NULL or a context from `sf_context_new` not freed yet; it is
/// not used afterwards.
#[no_mangle]
pub unsafe extern "C" fn sf_context_free(ctx: *mut SfContext) {
    if ctx.is_null() {
        return;
    }
    // SAFETY: `ctx` came from `Box::into_raw` in `sf_context_new` and is freed once.
    let ctx = unsafe { Box::from_raw(ctx) };
    let _ = catch_unwind(AssertUnwindSafe(move || drop(ctx)));
}

/// The message of the last failed call with `ctx`, "" after a successful
/// one (and for NULL). Valid until the next call with `ctx`.
///
/// # Safety
/// `ctx` is NULL or a live context.
#[no_mangle]
pub unsafe extern "C" fn sf_last_error(ctx: *const SfContext) -> *const c_char {
    // SAFETY: the caller passes NULL or a live context.
    match unsafe { ctx.as_ref() } {
        Some(ctx) => ctx.last_error(),
        None => c"".as_ptr(),
    }
}

/// The library version, e.g. "0.1.0" (a static string).
#[no_mangle]
pub extern "C" fn sf_version() -> *const c_char {
    const VERSION: &std::ffi::CStr = match std::ffi::CStr::from_bytes_with_nul(concat!(env!("CARGO_PKG_VERSION"), "\0").as_bytes()) {
        Ok(v) => v,
        Err(_) => c"",
    };
    VERSION.as_ptr()
}

/// Fills `settings` with the defaults (uniform, one split, 2048 texels,
/// depth in [0, 1], warp guard on); NULL is a no-op.
///
/// # Safety
/// `settings` is NULL or points to a writable `SfSettings`.
#[no_mangle]
pub unsafe extern "C" fn sf_settings_default(settings: *mut SfSettings) {
    if settings.is_null() {
        return;
    }
    // SAFETY: non-NULL and writable (caller); the write does not read the old value.
    unsafe { settings.write(convert::default_settings()) };
}

/// Fits every map of one light: `sf_prepare_view` then `sf_fit_light`.
///
/// Writes at most `capacity` maps to `maps` (NULL allowed with capacity 0)
/// and sets `*count` to the number of maps of the fit (at most
/// `SF_MAX_MAPS`). Returns `SF_OK`, or a negative `SF_ERR_*` code with the
/// message in `sf_last_error`: `SF_ERR_BUFFER_TOO_SMALL` when `capacity <
/// *count` (nothing written; the fit is kept for `sf_body` and
/// `sf_cull_casters`), `SF_ERR_INVALID_INPUT` for NaN, infinity, near >=
/// far, a zero direction, an inverted box, a bad enum value or a setting
/// out of range. Any other failure forgets the context's last fit. No
/// allocation after the first call with the context.
///
/// # Safety
/// Every pointer is NULL or valid for its type (`maps` for `capacity`
/// maps); `ctx` is not used by another thread during the call.
#[no_mangle]
pub unsafe extern "C" fn sf_fit(
    ctx: *mut SfContext,
    camera: *const SfCamera,
    light: *const SfLight,
    scene: *const SfAabb,
    settings: *const SfSettings,
    maps: *mut SfMap,
    capacity: usize,
    count: *mut usize,
) -> c_int {
    // SAFETY: the pointers are valid or NULL (caller); each is checked before use.
    unsafe {
        guard(ctx, |ctx| {
            ctx.forget_fit();
            let count = reset_count(count)?;
            let (camera, settings) = (input(camera, "camera")?, input(settings, "settings")?);
            ctx.prepare(&convert::camera(camera), &convert::settings(settings)?)?;
            fit_light(ctx, light, scene, None, maps, capacity, count)
        })
    }
}

/// Prepares the view for `sf_fit_light`: checks the camera and settings and
/// builds every split's frustum once, for all the lights the camera sees.
///
/// # Safety
/// Every pointer is NULL or valid for its type.
#[no_mangle]
pub unsafe extern "C" fn sf_prepare_view(ctx: *mut SfContext, camera: *const SfCamera, settings: *const SfSettings) -> c_int {
    // SAFETY: the pointers are valid or NULL (caller); each is checked before use.
    unsafe {
        guard(ctx, |ctx| {
            let (camera, settings) = (input(camera, "camera")?, input(settings, "settings")?);
            ctx.prepare(&convert::camera(camera), &convert::settings(settings)?)
        })
    }
}

/// Fits every map of one light from the view of the last `sf_prepare_view`
/// (or `sf_fit`): the same maps, bit for bit, as `sf_fit` with that camera
/// and those settings. Outputs and errors as `sf_fit`.
///
/// # Safety
/// Every pointer is NULL or valid for its type (`maps` for `capacity` maps).
#[no_mangle]
pub unsafe extern "C" fn sf_fit_light(
    ctx: *mut SfContext,
    light: *const SfLight,
    scene: *const SfAabb,
    maps: *mut SfMap,
    capacity: usize,
    count: *mut usize,
) -> c_int {
    // SAFETY: the pointers are valid or NULL (caller); each is checked before use.
    unsafe {
        guard(ctx, |ctx| {
            ctx.forget_fit();
            let count = reset_count(count)?;
            fit_light(ctx, light, scene, None, maps, capacity, count)
        })
    }
}

/// `sf_fit_light` carrying `state` from the previous frame: with stable
/// settings, a spot map or cube face whose body hovers at an extent step's
/// boundary keeps its step, and a LiSPSM or TSM map its warp's lattice
/// steps, instead of switching its texel grid every frame.
/// `state` is updated with this frame's steps (cleared on an error).
/// Without stable settings the maps are `sf_fit_light`'s, bit for bit.
/// A NULL `state` is `SF_ERR_NULL_POINTER`.
///
/// # Safety
/// Every pointer is NULL or valid for its type (`maps` for `capacity` maps).
#[no_mangle]
pub unsafe extern "C" fn sf_fit_light_held(
    ctx: *mut SfContext,
    light: *const SfLight,
    scene: *const SfAabb,
    state: *mut SfFitState,
    maps: *mut SfMap,
    capacity: usize,
    count: *mut usize,
) -> c_int {
    // SAFETY: the pointers are valid or NULL (caller); each is checked before use.
    unsafe {
        guard(ctx, |ctx| {
            ctx.forget_fit();
            let count = reset_count(count)?;
            // SAFETY: NULL or writable (caller).
            let state = state.as_mut().ok_or_else(|| Failure::null("state"))?;
            let fitted = fit_light(ctx, light, scene, Some(&mut *state), maps, capacity, count);
            if fitted.is_err() {
                convert::store_state(state, &FitState::default());
            }
            fitted
        })
    }
}

/// Sets `state` to hold nothing (the next held fit is the plain one); NULL
/// is a no-op.
///
/// # Safety
/// `state` is NULL or points to a writable `SfFitState`.
#[no_mangle]
pub unsafe extern "C" fn sf_fit_state_init(state: *mut SfFitState) {
    // SAFETY: NULL or writable (caller).
    if let Some(s) = unsafe { state.as_mut() } {
        convert::store_state(s, &FitState::default());
    }
}

/// Checks, converts and fits one light from the prepared view (carrying
/// `state` where given), then writes the maps.
///
/// # Safety
/// `light` and `scene` are NULL or readable; `maps` holds `capacity`
/// writable maps (or is NULL); `count` is writable.
unsafe fn fit_light(
    ctx: &mut SfContext,
    light: *const SfLight,
    scene: *const SfAabb,
    state: Option<&mut SfFitState>,
    maps: *mut SfMap,
    capacity: usize,
    count: *mut usize,
) -> Result<(), Failure> {
    // SAFETY: NULL or readable (caller).
    let (light, scene) = unsafe { (input(light, "light")?, input(scene, "scene")?) };
    output(maps, capacity, "maps")?;
    let light = convert::light(light)?;
    let scene = convert::aabb(scene).map_err(|e| Failure::geom(&e, ""))?;
    match state {
        Some(s) => {
            let mut held = convert::load_state(s);
            let fitted = ctx.fit_light(&light, &scene, Some(&mut held));
            convert::store_state(s, &held);
            fitted?;
        }
        None => ctx.fit_light(&light, &scene, None)?,
    }
    let fitted = ctx.result()?.maps();
    // SAFETY: `maps` and `count` as promised by the caller.
    unsafe { write_all(maps, capacity, count, fitted.len(), "maps", |i| convert::map(&fitted[i])) }
}

/// Writes the vertices of the focus body of map `map_index` of the last
/// successful fit to `vertices` (x, y, z per vertex; room for `capacity`
/// vertices, at most `SF_MAX_BODY_VERTICES` are needed) and sets `*count`
/// to their number. `SF_ERR_BUFFER_TOO_SMALL` (nothing written) when
/// `capacity < *count`.
///
/// # Safety
/// `vertices` holds `3 * capacity` writable doubles (or is NULL with
/// capacity 0); the other pointers are NULL or valid.
#[no_mangle]
pub unsafe extern "C" fn sf_body(ctx: *mut SfContext, map_index: usize, vertices: *mut f64, capacity: usize, count: *mut usize) -> c_int {
    // SAFETY: the pointers are valid or NULL (caller); each is checked before use.
    unsafe {
        guard(ctx, |ctx| {
            let count = reset_count(count)?;
            output(vertices, capacity, "vertices")?;
            write_body(ctx.map_body(map_index)?, vertices, capacity, count)
        })
    }
}

/// Writes the vertices of the focus body of the whole view of the last
/// successful fit (its camera with the fitted depth range, its light and
/// scene; computed on each call) as `sf_body` does.
///
/// # Safety
/// As `sf_body`.
#[no_mangle]
pub unsafe extern "C" fn sf_view_body(ctx: *mut SfContext, vertices: *mut f64, capacity: usize, count: *mut usize) -> c_int {
    // SAFETY: the pointers are valid or NULL (caller); each is checked before use.
    unsafe {
        guard(ctx, |ctx| {
            let count = reset_count(count)?;
            output(vertices, capacity, "vertices")?;
            write_body(ctx.view_body()?, vertices, capacity, count)
        })
    }
}

/// # Safety
/// `vertices` holds `3 * capacity` writable doubles; `count` is writable.
unsafe fn write_body(body: &Body, vertices: *mut f64, capacity: usize, count: *mut usize) -> Result<(), Failure> {
    let v = body.vertices();
    // SAFETY: each vertex is 3 doubles; `vertices` as promised by the caller.
    unsafe { write_all(vertices.cast::<[f64; 3]>(), capacity, count, v.len(), "vertices", |i| v[i].to_array()) }
}

/// Writes the planes of the region whose casters can shadow map
/// `map_index` of the last successful fit to `planes` (a, b, c, d per plane,
/// inside `a x + b y + c z + d <= 0`; room for `capacity` planes, at most
/// `SF_MAX_CASTER_PLANES` are needed) and sets `*count` to their number. A
/// box with centre `c` and half-size `e` outside one plane, `n.c - |n|.e +
/// d > 0` by more than its rounding (in double: 2^-36 of its largest
/// coordinate), casts no shadow into the map; `sf_cull_casters` tests
/// exactly these planes. The planes already include the rounding of the
/// body. `SF_ERR_BUFFER_TOO_SMALL` (nothing written) when `capacity <
/// *count`.
///
/// # Safety
/// `planes` holds `4 * capacity` writable doubles (or is NULL with
/// capacity 0); the other pointers are NULL or valid.
#[no_mangle]
pub unsafe extern "C" fn sf_caster_planes(
    ctx: *mut SfContext,
    map_index: usize,
    planes: *mut f64,
    capacity: usize,
    count: *mut usize,
) -> c_int {
    // SAFETY: the pointers are valid or NULL (caller); each is checked before use.
    unsafe {
        guard(ctx, |ctx| {
            let count = reset_count(count)?;
            output(planes, capacity, "planes")?;
            let region = ctx.caster_region(map_index)?;
            let all = region.planes();
            write_all(planes.cast::<[f64; 4]>(), capacity, count, all.len(), "planes", |i| all[i].to_array())
        })
    }
}

/// Keeps the caster boxes that may shadow what map `map_index` of the last
/// successful fit covers: writes their indices into `boxes`, in increasing
/// order, to `out_indices` and sets `*count` to how many. Conservative:
/// a box is dropped only when it provably casts no shadow into the map.
/// `out_indices` must hold one index per box (`capacity >= n`), checked
/// first: otherwise `SF_ERR_BUFFER_TOO_SMALL`, nothing written, `*count =
/// n`. `boxes` may be NULL when `n` is 0.
///
/// # Safety
/// `boxes` holds `n` readable boxes, `out_indices` `capacity` writable
/// indices; the other pointers are NULL or valid.
#[no_mangle]
pub unsafe extern "C" fn sf_cull_casters(
    ctx: *mut SfContext,
    map_index: usize,
    boxes: *const SfAabb,
    n: usize,
    out_indices: *mut u32,
    capacity: usize,
    count: *mut usize,
) -> c_int {
    // SAFETY: the pointers are valid or NULL (caller); each is checked before use.
    unsafe {
        guard(ctx, |ctx| {
            let count = reset_count(count)?;
            if boxes.is_null() && n > 0 {
                return Err(Failure::null("boxes"));
            }
            output(out_indices, capacity, "out_indices")?;
            if capacity < n {
                set_count(count, n);
                return Err(Failure::too_small("out_indices (one index per box)", capacity, n));
            }
            let boxes = if n == 0 { &[][..] } else { std::slice::from_raw_parts(boxes, n) };
            let out = if n == 0 {
                &mut [][..]
            } else {
                // NOTE: zeroed first, so that the slice holds initialised integers.
                out_indices.write_bytes(0, n);
                std::slice::from_raw_parts_mut(out_indices, n)
            };
            let kept = ctx.cull(map_index, boxes, out)?;
            set_count(count, kept);
            Ok(())
        })
    }
}

/// Gathers the points a depth pre-pass of `camera`'s view saw into receiver
/// boxes for `SfSettings::receivers` (with `receivers_seen` set): slices of the view in log depth,
/// apart by the world axis each point's normal lies closest to where `normals` is given, a
/// ground seen over several slices as one box, each widened by a pixel at
/// its far end (the buffer is `height_px` pixels high) and by `margin` (the
/// points' rounding: 2^-20 of their magnitude for positions computed and
/// stored in float; for points a frame old, add the most a receiver moved
/// since). `points` holds `n` positions as x, y, z floats (`n` may be 0:
/// no hint, `*count = 0`), `normals` their surface normals the same way
/// (either way round, any length) or is NULL (unknown: a slice that sees a
/// slab's top and side then gets one box as deep as the side). Writes at
/// most `SF_MAX_RECEIVER_BOXES` boxes to `out` and sets `*count`;
/// `SF_ERR_BUFFER_TOO_SMALL` (nothing written) when `capacity < *count`. A
/// point that is not finite, or a normal that is not finite or zero, fails
/// the call.
///
/// # Safety
/// `points` holds `3 * n` readable floats (or is NULL with `n` 0), so does
/// `normals` unless it is NULL, `out` `capacity` writable boxes (or is NULL
/// with capacity 0); the other pointers are NULL or valid.
#[no_mangle]
pub unsafe extern "C" fn sf_visible_receivers(
    ctx: *mut SfContext,
    camera: *const SfCamera,
    height_px: u32,
    points: *const f32,
    normals: *const f32,
    n: usize,
    margin: f64,
    out: *mut SfAabb,
    capacity: usize,
    count: *mut usize,
) -> c_int {
    // SAFETY: the pointers are valid or NULL (caller); each is checked before use.
    unsafe {
        guard(ctx, |_| {
            let count = reset_count(count)?;
            let camera = convert::camera(input(camera, "camera")?);
            output(out, capacity, "out")?;
            if points.is_null() && n > 0 {
                return Err(Failure::null("points"));
            }
            let mut v = shadowfocus_focus::VisibleReceivers::new(&camera, height_px)?;
            if n > 0 {
                let dvec = |p: &[f32; 3]| glam::DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64);
                let points = std::slice::from_raw_parts(points.cast::<[f32; 3]>(), n);
                if normals.is_null() {
                    points.iter().for_each(|p| v.add(dvec(p)));
                } else {
                    let normals = std::slice::from_raw_parts(normals.cast::<[f32; 3]>(), n);
                    points.iter().zip(normals).for_each(|(p, m)| v.add_facing(dvec(p), dvec(m)));
                }
            }
            let boxes = v.boxes(margin)?;
            let b = boxes.as_slice();
            write_all(out, capacity, count, b.len(), "out (receiver boxes)", |i| SfAabb {
                min: b[i].min.to_array(),
                max: b[i].max.to_array(),
            })
        })
    }
}
