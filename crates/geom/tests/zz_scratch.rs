use shadowfocus_geom::*;
#[test]
fn scratch() {
    let c = [
DVec3::new(-3957.0,63022.5,94269.0,),
DVec3::new(-3957.0,63022.5,94243.0,),
DVec3::new(-3957.0,63053.5,94243.0,),
DVec3::new(-3957.0,63053.5,94269.0,),
DVec3::new(-12145.0,31294.0,120880.0,),
DVec3::new(-12145.0,31294.0,67632.0,),
DVec3::new(-12145.0,94782.0,67632.0,),
DVec3::new(-12145.0,94782.0,120880.0,)];
    let f = Frustum::from_corners(c).unwrap();
    let lp = DVec3::new(6952521159707.724,-5029296471556.252,-7324650991975.916,);
    let l = Light::point(lp).unwrap();
    for p in f.hull_with(l.apex()).as_slice() { println!("hull plane {:?} -> {:?}", p, p.approximate()); }
    let s = Aabb::new(DVec3::new(-12145.0,-5029296471556.252,-7324650991975.916,), DVec3::new(6952521159707.724,94782.0,120880.0,)).unwrap();
    let b = focus_body(&f, &l, &s).unwrap();
    println!("{:?}", b.stats());
    for (i, v) in b.vertices().iter().enumerate() { println!("v{i} {v:?}"); }
    for (fc, p) in b.faces().zip(b.face_planes()) {
        let d: Vec<f64> = fc.iter().map(|&i| p.truncate().dot(b.vertices()[i as usize]) + p.w).collect();
        println!("face {fc:?} plane {p:?} dists {d:?}");
    }
    println!("volume {}", b.volume());
    // volume with origin at centroid
    let cen = b.vertices().iter().copied().sum::<DVec3>() / b.vertices().len() as f64;
    let mut v6 = 0.0;
    for fc in b.faces() { let a = b.vertices()[fc[0] as usize]-cen; for k in 1..fc.len()-1 { v6 += a.dot((b.vertices()[fc[k] as usize]-cen).cross(b.vertices()[fc[k+1] as usize]-cen)); } }
    println!("centroid volume {}", v6/6.0);
}
