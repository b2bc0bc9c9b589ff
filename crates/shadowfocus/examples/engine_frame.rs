//! How an engine uses Shadowfocus each frame: four stable cascades for the
//! sun, one PSM map for a spot light, and per-map caster lists.
//!
//! `cargo run --release -p shadowfocus --example engine_frame`
//!
//! Everything a frame needs is allocated once, before the loop: the results
//! and the caster index buffers are reused, so the per-frame work does not
//! touch the heap (except the exact geometry's rare big-integer fallback).

use glam::DVec3;
use shadowfocus::focus::{cull_casters, fit, ClipConvention, FocusResult, FocusSettings, Method, SplitScheme, SplitSettings};
use shadowfocus::geom::{Aabb, Camera, Frustum, Light};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // The level: a 200 m square with a grid of crates (the shadow casters).
    let scene = Aabb::new(DVec3::new(-100.0, 0.0, -100.0), DVec3::new(100.0, 30.0, 100.0))?;
    let casters: Vec<Aabb> = (0..400)
        .map(|i| {
            let c = DVec3::new((i % 20) as f64 * 10.0 - 95.0, 0.0, (i / 20) as f64 * 10.0 - 95.0);
            Aabb { min: c, max: c + DVec3::new(2.0, 2.0 + (i % 7) as f64, 2.0) }
        })
        .collect();

    let sun = Light::directional(DVec3::new(0.4, -1.0, 0.3))?;
    let spot_pos = DVec3::new(0.0, 25.0, -40.0);
    let spot = Light::spot(
        spot_pos,
        Frustum::from_camera(&Camera {
            eye: spot_pos,
            forward: DVec3::new(0.0, -1.0, 0.2),
            up: DVec3::Z,
            fovy: 70f64.to_radians(),
            aspect: 1.0,
            near: 0.5,
            far: 60.0,
        })?,
    )?;

    let cascades = FocusSettings {
        method: Method::Uniform,
        splits: SplitSettings { count: 4, scheme: SplitScheme::Practical { lambda: 0.7 }, ..SplitSettings::default() },
        resolution: 2048,
        stable: true,
        // The engine's API: here Vulkan with reversed-Z.
        clip: ClipConvention::VULKAN.reversed(),
        ..FocusSettings::default()
    };
    let spot_settings = FocusSettings { method: Method::Psm, resolution: 1024, clip: cascades.clip, ..FocusSettings::default() };
    cascades.validate()?;
    spot_settings.validate()?;

    // Allocated once, reused every frame.
    let mut sun_maps = FocusResult::new();
    let mut spot_maps = FocusResult::new();
    let mut caster_ids = vec![0u32; casters.len()];

    for frame in 0..3 {
        // The camera walks forward and turns a little each frame.
        let t = frame as f64;
        let camera = Camera {
            eye: DVec3::new(0.0, 1.8, 60.0 - 5.0 * t),
            forward: DVec3::new((0.1 * t).sin(), -0.05, -(0.1 * t).cos()),
            up: DVec3::Y,
            fovy: 60f64.to_radians(),
            aspect: 16.0 / 9.0,
            near: 0.1,
            far: 150.0,
        };
        fit(&camera, &sun, &scene, &cascades, &mut sun_maps)?;
        fit(&camera, &spot, &scene, &spot_settings, &mut spot_maps)?;

        println!("frame {frame}: cascade split depths {:?}", sun_maps.split_depths());
        for (name, result) in [("sun", &sun_maps), ("spot", &spot_maps)] {
            for map in result.maps() {
                if !map.is_active() {
                    // Nothing can cast into this split: skip its shadow pass.
                    println!("  {name} split {}: empty, not rendered", map.split);
                    continue;
                }
                let n = cull_casters(map, &casters, &mut caster_ids)?;
                // An engine uploads `map.fit.clip_from_world_f32` (world → clip in its
                // convention) and sets its depth compare from `map.fit.depth_test`, then
                // draws the casters `caster_ids[..n]` into this map; its lighting shader
                // samples the map through `map.fit.uv_from_world_f32()`.
                let _lookup: [f32; 16] = map.fit.uv_from_world_f32().to_cols_array();
                println!(
                    "  {name} split {} [{:.1}, {:.1}] m: depth test {}, texel {:.3}–{:.3} m, {n}/{} casters",
                    map.split,
                    map.split_range[0],
                    map.split_range[1],
                    map.fit.depth_test.name(),
                    map.fit.texel_size[0],
                    map.fit.texel_size[1],
                    casters.len(),
                );
            }
            let skipped: Vec<_> = result.skipped.names().collect();
            if !skipped.is_empty() {
                println!("  {name}: skipped {skipped:?}");
            }
        }
    }
    Ok(())
}
