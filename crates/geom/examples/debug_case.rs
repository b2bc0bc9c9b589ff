use glam::DVec3;
use shadowfocus_geom::*;
fn main() {
    let c = [
        DVec3::new(4.071751446695598, -3.7179286851489897, -5.450861866581199),
        DVec3::new(4.071751446695598, -4.650917342310994, 4.680155624698138),
        DVec3::new(4.071751446695598, 3.7179286851489897, 5.450861866581199),
        DVec3::new(4.071751446695598, 4.650917342310994, -4.680155624698138),
        DVec3::new(308252.3173589797, -281466.1326890859, -412657.99840040255),
        DVec3::new(308252.3173589797, -352098.12469665974, 354311.61155100766),
        DVec3::new(308252.3173589797, 281466.1326890859, 412657.99840040255),
        DVec3::new(308252.3173589797, 352098.12469665974, -354311.61155100766),
    ];
    let view = Frustum::from_corners(c).unwrap();
    let scene = Aabb::new(DVec3::new(4.071751446695598, -352098.12469665974, -412657.99840040255), DVec3::new(308252.3173589797, 352098.12469665974, 412657.99840040255)).unwrap();
    let light = Light::point(DVec3::ZERO).unwrap();
    let planes = view.hull_with(light.apex());
    let mut p = Polytope::from_aabb(&scene);
    for (i, pl) in planes.as_slice().iter().enumerate() {
        let cut = p.clip(pl).unwrap();
        let bad = p.debug_check();
        println!("clip {i} {:?} cut={cut} dim={} bad={bad:?}", pl, p.dimension());
    }
    let b = focus_body(&view, &light, &scene).unwrap();
    println!("{:?}", b.stats());
    for (f, face) in b.faces().enumerate() {
        let pl = b.face_planes()[f];
        let offs: Vec<f64> = face.iter().map(|&i| pl.truncate().dot(b.vertices()[i as usize]) + pl.w).collect();
        println!("face {f} {face:?} plane {pl:?} offsets {offs:?}");
    }
}
#[allow(dead_code)]
fn unused() {}
