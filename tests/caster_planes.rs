//! Caster planes on the built-in scenes: an engine testing its bounding
//! boxes against `caster_planes` alone, in plain f64, keeps exactly the
//! casters `cull_casters` keeps, never a box that meets the map's body, and
//! rejects more than the axis-aligned planes alone (the bounding box of
//! the body swept toward the light).

use glam::DVec4;
use shadowfocus_cli::cli::render::{demo_configs, scene_inputs, scene_settings};
use shadowfocus_cli::focus::{caster_planes, cull_casters, fit, FocusResult, MAX_REGION_PLANES};
use shadowfocus_cli::geom::Aabb;
use shadowfocus_cli::render::{builtin_scene, BUILTIN_SCENES};

/// The engine's side: outside one plane by more than the box's rounding.
fn outside(planes: &[DVec4], b: &Aabb) -> bool {
    let (c, e) = ((b.min + b.max) * 0.5, (b.max - b.min) * 0.5);
    let slack = b.min.abs().max(b.max.abs()).max_element() * (1.0 / (1u64 << 36) as f64);
    planes.iter().any(|p| p.truncate().dot(c) - p.truncate().abs().dot(e) + p.w > slack)
}

#[test]
fn caster_planes_cull_what_cull_casters_culls_on_every_builtin_scene() {
    let mut planes = [DVec4::ZERO; MAX_REGION_PLANES];
    let (mut tested, mut rejected, mut box_rejected) = (0usize, 0usize, 0usize);
    for name in BUILTIN_SCENES {
        let scene = builtin_scene(name).unwrap();
        let (camera, light, bounds) = scene_inputs(&scene, 16.0 / 9.0).unwrap();
        let boxes: Vec<Aabb> = scene.objects.iter().map(|o| Aabb::new(o.aabb.min, o.aabb.max).unwrap()).collect();
        let mut kept = vec![0u32; boxes.len()];
        for (label, opts) in demo_configs(1024) {
            let mut out = FocusResult::new();
            fit(&camera, &light, &bounds, &scene_settings(&scene, &opts).unwrap(), &mut out).unwrap();
            for map in out.maps().iter().filter(|m| m.is_active()) {
                let n = caster_planes(map, &mut planes).unwrap();
                let k = cull_casters(map, &boxes, &mut kept).unwrap();
                let by_planes: Vec<u32> = (0..boxes.len() as u32).filter(|&i| !outside(&planes[..n], &boxes[i as usize])).collect();
                assert_eq!(by_planes, kept[..k], "{name}/{label}: planes and cull_casters disagree");
                // A box around a body vertex is never rejected.
                let r = (bounds.max - bounds.min).max_element() * 1e-6;
                for v in map.body().vertices() {
                    let b = Aabb::new(*v - r, *v + r).unwrap();
                    assert!(!outside(&planes[..n], &b), "{name}/{label}: box at body vertex {v} rejected");
                }
                // The axis-aligned planes alone (the sweep's bounding box, and
                // faces of H on the scene box) keep more.
                let axis: Vec<DVec4> = planes[..n]
                    .iter()
                    .copied()
                    .filter(|p| p.truncate().abs().max_element() == 1.0 && p.truncate().abs().element_sum() == 1.0)
                    .collect();
                tested += boxes.len();
                rejected += boxes.len() - k;
                box_rejected += boxes.iter().filter(|b| outside(&axis, b)).count();
            }
        }
    }
    eprintln!("{tested} box tests: planes reject {rejected}, the axis-aligned planes alone {box_rejected}");
    assert!(rejected > box_rejected, "the planes reject no more than a bounding box: {rejected} vs {box_rejected}");
}
