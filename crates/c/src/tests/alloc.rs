//! After the first frame, a context's successful calls allocate nothing.

use super::common::*;
use crate::*;
#[path = "../../../../tests/support/counting_alloc.rs"]
mod counting_alloc;
use counting_alloc::{allocations, Counting};

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// One frame: fit each light, read every body, cull a grid of boxes.
fn frame(ctx: &Ctx, k: usize, maps: &mut [SfMap], vertices: &mut [[f64; 3]], boxes: &[SfAabb], kept: &mut [u32]) {
    let s = settings(SfMethod::SF_METHOD_LISPSM, 4);
    for light in lights() {
        let (rc, n) = ctx.fit(&camera(k), &light, &scene(), &s, maps);
        assert_eq!(rc, 0);
        for i in 0..n {
            let mut count = 0;
            // SAFETY: the buffers hold their lengths.
            unsafe {
                assert_eq!(sf_body(ctx.0, i, vertices.as_mut_ptr().cast(), vertices.len(), &mut count), 0);
                let rc = sf_cull_casters(ctx.0, i, boxes.as_ptr(), boxes.len(), kept.as_mut_ptr(), kept.len(), &mut count);
                assert_eq!(rc, 0);
            }
        }
        let mut count = 0;
        // SAFETY: as above.
        assert_eq!(unsafe { sf_view_body(ctx.0, vertices.as_mut_ptr().cast(), vertices.len(), &mut count) }, 0);
    }
}

#[test]
fn steady_state_calls_do_not_allocate() {
    let ctx = Ctx::new();
    let mut maps = vec![canary_map(); SF_MAX_MAPS as usize];
    let mut vertices = vec![[0.0; 3]; SF_MAX_BODY_VERTICES as usize];
    let boxes: Vec<SfAabb> =
        (0..64).map(|i| SfAabb { min: [i as f64 * 3.0 - 96.0, 0.0, -10.0], max: [i as f64 * 3.0 - 94.0, 5.0, -8.0] }).collect();
    let mut kept = vec![0u32; boxes.len()];
    frame(&ctx, 0, &mut maps, &mut vertices, &boxes, &mut kept);
    let before = allocations();
    for k in 1..20 {
        frame(&ctx, k, &mut maps, &mut vertices, &boxes, &mut kept);
    }
    assert_eq!(allocations() - before, 0, "allocations in 19 steady-state frames");
    // The counter counts: an error message is allocated.
    let (rc, _) =
        ctx.fit(&camera(0), &lights()[0], &scene(), &SfSettings { splits: 0, ..settings(SfMethod::SF_METHOD_UNIFORM, 1) }, &mut maps);
    assert_ne!(rc, 0);
    assert!(allocations() > before);
}
