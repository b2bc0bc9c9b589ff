//! A frame allocates nothing once the result buffer exists, counted with a
//! global allocator over fits of every method, light kind and split count.
//! The one exception lies in the body engine: its exact engine, taken when
//! the certified float path cannot prove a decision, allocates; so a fit may
//! allocate only when one of its bodies comes from that engine. Fitting and
//! culling themselves never do.

use glam::DVec3;
use shadowfocus_focus::*;
use shadowfocus_geom::{Aabb, Camera, Frustum, Light};
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;
static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn fitting_a_frame_does_not_allocate() {
    let cam = Camera { eye: DVec3::new(0.0, 2.0, 10.0), forward: DVec3::new(0.1, -0.1, -1.0), up: DVec3::Y, fovy: 1.0, aspect: 1.5, near: 0.5, far: 100.0 };
    let scene = Aabb::new(DVec3::new(-50.0, 0.0, -100.0), DVec3::new(50.0, 20.0, 20.0)).unwrap();
    let spot_cam = Camera { eye: DVec3::new(10.0, 30.0, 0.0), forward: DVec3::new(-0.2, -1.0, -0.5), ..cam };
    let lights = [
        Light::directional(DVec3::new(0.4, -1.0, 0.3)).unwrap(),
        Light::directional(DVec3::new(0.1, -0.3, -1.0)).unwrap(),
        Light::point(DVec3::new(30.0, 15.0, 15.0)).unwrap(),
        Light::point(DVec3::new(0.0, 2.0, -20.0)).unwrap(),
        Light::spot(spot_cam.eye, Frustum::from_camera(&spot_cam).unwrap()).unwrap(),
    ];
    let casters = [Aabb::new(DVec3::new(-1.0, 0.0, -5.0), DVec3::new(1.0, 3.0, -3.0)).unwrap(); 8];
    let mut idx = [0u32; 8];
    let mut out = FocusResult::new();
    let mut run = |out: &mut FocusResult, check: bool| {
        for light in &lights {
            for method in [Method::Uniform, Method::Psm, Method::Lispsm, Method::Tsm] {
                for count in [1, 4] {
                    for stable in [false, true] {
                        let s = FocusSettings { method, stable, splits: SplitSettings { count, ..Default::default() }, ..Default::default() };
                        let a0 = ALLOCATIONS.load(Ordering::Relaxed);
                        fit(&cam, light, &scene, &s, out).unwrap();
                        let a1 = ALLOCATIONS.load(Ordering::Relaxed);
                        for m in out.maps() {
                            cull_casters(m, &casters, &mut idx);
                        }
                        let a2 = ALLOCATIONS.load(Ordering::Relaxed);
                        let exact_engine = out.maps().iter().filter(|m| !m.body().stats().float_path).count();
                        if !check {
                            continue;
                        }
                        assert_eq!(a2, a1, "culling allocated");
                        assert!(a1 == a0 || exact_engine > 0, "{light:?} {method:?} {count} {stable}: {} allocations on the float path", a1 - a0);
                    }
                }
            }
        }
    };
    run(&mut out, false); // first use fills the bodies' scratch space
    run(&mut out, true);
}
