use glam::DVec3;
use shadowfocus_geom::*;
use std::time::Instant;

fn main() {
    let cam = Camera { eye: DVec3::new(0.0, 2.0, 10.0), forward: DVec3::new(0.2, -0.1, -1.0), up: DVec3::Y, fovy: 1.0, aspect: 1.5, near: 0.5, far: 80.0 };
    let scene = Aabb::new(DVec3::new(-50.0, 0.0, -90.0), DVec3::new(50.0, 15.0, 20.0)).unwrap();
    let lights = [
        ("dir", Light::directional(DVec3::new(0.3, -1.0, 0.2)).unwrap()),
        ("point", Light::point(DVec3::new(5.0, 12.0, -10.0)).unwrap()),
        ("spot", Light::spot(DVec3::new(5.0, 14.0, -10.0), Frustum::from_camera(&Camera { eye: DVec3::new(5.0, 14.0, -10.0), forward: DVec3::new(0.0, -1.0, -0.2), up: DVec3::Z, fovy: 1.2, aspect: 1.0, near: 1.0, far: 40.0 }).unwrap()).unwrap()),
    ];
    let mut body = Body::new();
    for (name, light) in lights {
        let n = 200_000;
        let t = Instant::now();
        for _ in 0..n {
            let view = Frustum::from_camera(std::hint::black_box(&cam)).unwrap();
            focus_body_into(&mut body, &view, std::hint::black_box(&light), &scene).unwrap();
        }
        let dt = t.elapsed().as_nanos() as f64 / n as f64;
        println!("{name}: {dt:.0} ns/body  dim {:?} verts {} faces {} exact {} stats {:?}", body.dimension(), body.vertices().len(), body.face_count(), body.stats().exact_evaluations, body.stats());
    }
    let t = Instant::now();
    for _ in 0..200_000 { std::hint::black_box(Frustum::from_camera(std::hint::black_box(&cam)).unwrap()); }
    println!("frustum only: {:.0} ns", t.elapsed().as_nanos() as f64 / 200_000.0);
}
