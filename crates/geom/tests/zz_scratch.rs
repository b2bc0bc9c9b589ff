use shadowfocus_geom::*;
#[test]
fn scratch() {
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
    let f = Frustum::from_corners(c).unwrap();
    println!("frustum faces {}", f.face_count());
    for p in f.planes().as_slice() { println!("view plane {:?} -> {:?}", p, p.approximate()); }
    let l = Light::point(DVec3::ZERO).unwrap();
    for p in f.hull_with(l.apex()).as_slice() { println!("hull plane {:?} -> {:?}", p, p.approximate()); }
    let s = Aabb::new(DVec3::new(4.071751446695598, -352098.12469665974, -412657.99840040255), DVec3::new(308252.3173589797, 352098.12469665974, 412657.99840040255)).unwrap();
    let b = focus_body(&f, &l, &s).unwrap();
    println!("{:?}", b.stats());
    for (i, v) in b.vertices().iter().enumerate() { println!("v{i} {v:?}"); }
    for (fc, p) in b.faces().zip(b.face_planes()) {
        let d: Vec<f64> = fc.iter().map(|&i| p.truncate().dot(b.vertices()[i as usize]) + p.w).collect();
        println!("face {fc:?} plane {p:?} dists {d:?}");
    }
}
#[test]
fn scratch_up() {
    let mut n = 0;
    for i in 0..1000 {
        let t = i as f64 * 0.01;
        let fwd = DVec3::new(t.sin(), (1.3*t).cos(), 0.7 + t);
        for k in [-2.0, 0.5] {
            let cam = Camera { eye: DVec3::ZERO, forward: fwd, up: fwd * k, fovy: 1.0, aspect: 1.0, near: 1.0, far: 10.0 };
            if cam.basis().is_ok() { n += 1; if n < 3 { println!("accepted {:?} {:?}", cam, cam.basis()); } }
        }
    }
    println!("accepted {n} of 2000");
}
