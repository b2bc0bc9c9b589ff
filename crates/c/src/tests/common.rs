//! Inputs shared by the tests, in C and Rust form, and call helpers.

use crate::*;
use glam::DVec3;
use shadowfocus_focus::FocusSettings;
use shadowfocus_geom::{Aabb, Camera, Frustum, Light};
use std::ffi::{c_int, CStr};
use std::ptr;

/// A camera walking and turning through the scene, frame `k`.
pub fn camera(k: usize) -> SfCamera {
    let t = k as f64 * 0.05;
    SfCamera {
        eye: [40.0 * t.sin(), 2.0 + 0.5 * t.cos(), 60.0 - 4.0 * t],
        forward: [(0.7 * t).sin(), -0.15, -(0.7 * t).cos()],
        up: [0.0, 1.0, 0.0],
        fovy_rad: 60f64.to_radians(),
        aspect: 16.0 / 9.0,
        near_dist: 0.5,
        far_dist: 150.0,
    }
}

/// The same camera for Rust.
pub fn rust_camera(c: &SfCamera) -> Camera {
    Camera {
        eye: DVec3::from_array(c.eye),
        forward: DVec3::from_array(c.forward),
        up: DVec3::from_array(c.up),
        fovy: c.fovy_rad,
        aspect: c.aspect,
        near: c.near_dist,
        far: c.far_dist,
    }
}

/// The 200 m scene box.
pub fn scene() -> SfAabb {
    SfAabb { min: [-100.0, 0.0, -100.0], max: [100.0, 30.0, 100.0] }
}

/// The same box for Rust.
pub fn rust_scene() -> Aabb {
    Aabb::new(DVec3::new(-100.0, 0.0, -100.0), DVec3::new(100.0, 30.0, 100.0)).unwrap()
}

/// A light of each kind: sun, point, spot.
pub fn lights() -> [SfLight; 3] {
    let base = SfLight {
        kind: SfLightKind::SF_LIGHT_DIRECTIONAL as c_int,
        position: [0.0; 3],
        direction: [0.4, -1.0, 0.3],
        up: [0.0, 1.0, 0.0],
        fovy_rad: 0.0,
        aspect: 0.0,
        near_dist: 0.0,
        far_dist: 0.0,
    };
    let point = SfLight { kind: SfLightKind::SF_LIGHT_POINT as c_int, position: [10.0, 25.0, -20.0], ..base };
    let spot = SfLight {
        kind: SfLightKind::SF_LIGHT_SPOT as c_int,
        position: [-30.0, 40.0, 20.0],
        direction: [0.5, -1.0, -0.4],
        up: [0.0, 1.0, 0.0],
        fovy_rad: 80f64.to_radians(),
        aspect: 1.0,
        near_dist: 1.0,
        far_dist: 150.0,
    };
    [base, point, spot]
}

/// The same light for Rust.
pub fn rust_light(l: &SfLight) -> Light {
    let v = DVec3::from_array;
    match l.kind {
        0 => Light::directional(v(l.direction)).unwrap(),
        1 => Light::point(v(l.position)).unwrap(),
        _ => {
            let cam = Camera {
                eye: v(l.position),
                forward: v(l.direction),
                up: v(l.up),
                fovy: l.fovy_rad,
                aspect: l.aspect,
                near: l.near_dist,
                far: l.far_dist,
            };
            Light::spot(cam.eye, Frustum::from_camera(&cam).unwrap()).unwrap()
        }
    }
}

/// Default C settings with `method` and `splits`.
pub fn settings(method: SfMethod, splits: u32) -> SfSettings {
    let mut s = std::mem::MaybeUninit::<SfSettings>::uninit();
    // SAFETY: the pointer is valid for writes; sf_settings_default writes the whole struct.
    let mut s = unsafe {
        sf_settings_default(s.as_mut_ptr());
        s.assume_init()
    };
    s.method = method as c_int;
    s.splits = splits;
    s
}

/// The Rust settings `settings(method, splits)` stands for.
pub fn rust_settings(method: SfMethod, splits: u32) -> FocusSettings {
    let method = [
        shadowfocus_focus::Method::Uniform,
        shadowfocus_focus::Method::Psm,
        shadowfocus_focus::Method::Lispsm,
        shadowfocus_focus::Method::Tsm,
        shadowfocus_focus::Method::Auto,
    ][method as usize];
    let mut s = FocusSettings { method, ..FocusSettings::default() };
    s.splits.count = splits as usize;
    s
}

/// A context freed on drop.
pub struct Ctx(pub *mut SfContext);

impl Ctx {
    pub fn new() -> Ctx {
        let p = sf_context_new();
        assert!(!p.is_null());
        Ctx(p)
    }

    /// The last error message.
    pub fn error(&self) -> String {
        // SAFETY: the context is live; sf_last_error returns a NUL-terminated string.
        unsafe { CStr::from_ptr(sf_last_error(self.0)) }.to_str().unwrap().to_owned()
    }

    /// sf_fit into `maps`; returns the status and count.
    pub fn fit(&self, cam: &SfCamera, light: &SfLight, scene: &SfAabb, s: &SfSettings, maps: &mut [SfMap]) -> (c_int, usize) {
        let mut n = usize::MAX;
        // SAFETY: every pointer is valid; `maps` holds `maps.len()` maps.
        let rc = unsafe { sf_fit(self.0, cam, light, scene, s, maps.as_mut_ptr(), maps.len(), &mut n) };
        (rc, n)
    }

    /// sf_body of map `i` into a fresh vector.
    pub fn body(&self, i: usize) -> Vec<[f64; 3]> {
        let mut v = vec![[f64::NAN; 3]; SF_MAX_BODY_VERTICES as usize];
        let mut n = 0;
        // SAFETY: `v` holds SF_MAX_BODY_VERTICES vertices.
        let rc = unsafe { sf_body(self.0, i, v.as_mut_ptr().cast(), v.len(), &mut n) };
        assert_eq!(rc, 0, "{}", self.error());
        v.truncate(n);
        v
    }
}

impl Drop for Ctx {
    fn drop(&mut self) {
        // SAFETY: the context came from sf_context_new and is freed once.
        unsafe { sf_context_free(self.0) };
    }
}

/// A map filled with a recognisable pattern.
pub fn canary_map() -> SfMap {
    let mut m = std::mem::MaybeUninit::<SfMap>::uninit();
    // SAFETY: every byte pattern is a valid SfMap (integers and floats only).
    unsafe {
        ptr::write_bytes(m.as_mut_ptr().cast::<u8>(), 0xA5, std::mem::size_of::<SfMap>());
        m.assume_init()
    }
}

/// The bytes of a map, for comparisons that NaN does not spoil.
pub fn bytes(m: &SfMap) -> Vec<u8> {
    // SAFETY: SfMap is plain data; reading its bytes (padding included, which
    // the canary and every write fill) is reading initialised memory.
    unsafe { std::slice::from_raw_parts((m as *const SfMap).cast::<u8>(), std::mem::size_of::<SfMap>()) }.to_vec()
}
