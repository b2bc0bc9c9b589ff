//! The C++ client's frames (examples/cpp/shadowfocus_client.cpp) fitted
//! with the Rust API directly: the mean time per `fit`, to set beside the
//! client's mean time per `sf_fit`.
//!
//! `cargo run --release -p shadowfocus-c --example rust_loop`

use glam::DVec3;
use shadowfocus_focus::{fit, ClipConvention, FocusResult, FocusSettings, Method, SplitSettings};
use shadowfocus_geom::{Aabb, Camera, Frustum, GeomError, Light};
use std::f64::consts::PI;
use std::time::Instant;

const FRAMES: usize = 300;

/// The client's walk, frame `k`.
fn camera_at(k: usize) -> Camera {
    let a = 2.0 * PI * k as f64 / FRAMES as f64;
    let yaw = a + PI / 2.0 + 0.5 * (3.0 * a).sin();
    Camera {
        eye: DVec3::new(70.0 * a.cos(), 1.8 + 0.3 * (7.0 * a).sin(), 70.0 * a.sin()),
        forward: DVec3::new(yaw.cos(), -0.1 + 0.05 * (2.0 * a).sin(), yaw.sin()),
        up: DVec3::Y,
        fovy: 60.0 * PI / 180.0,
        aspect: 16.0 / 9.0,
        near: 0.3,
        far: 200.0,
    }
}

/// The client's sun and spot light.
fn lights() -> Result<[Light; 2], GeomError> {
    let sun = Light::directional(DVec3::new(0.4, -1.0, 0.3))?;
    let frame = Camera {
        eye: DVec3::new(0.0, 35.0, 0.0),
        forward: DVec3::new(0.3, -1.0, 0.2),
        up: DVec3::Y,
        fovy: PI / 2.0,
        aspect: 1.0,
        near: 0.5,
        far: 120.0,
    };
    Ok([sun, Light::spot(frame.eye, Frustum::from_camera(&frame)?)?])
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let scene = Aabb::new(DVec3::new(-100.0, 0.0, -100.0), DVec3::new(100.0, 40.0, 100.0))?;
    let settings = FocusSettings {
        method: Method::Lispsm,
        splits: SplitSettings { count: 4, ..SplitSettings::default() },
        resolution: 2048,
        ..FocusSettings::default()
    };
    // Every fourth frame also in OpenGL's convention with reversed-Z, as the client does.
    let gl_reversed = FocusSettings { clip: ClipConvention::OPENGL.reversed(), ..settings };
    let lights = lights()?;
    let mut out = FocusResult::new();
    let (mut total, mut per_light, mut fits, mut active) = (0.0, [0.0; 2], [0usize; 2], 0);
    for k in 0..FRAMES {
        let camera = camera_at(k);
        let conventions: &[&FocusSettings] = if k % 4 == 0 { &[&settings, &gl_reversed] } else { &[&settings] };
        for s in conventions {
            for (i, light) in lights.iter().enumerate() {
                let start = Instant::now();
                fit(&camera, light, &scene, s, &mut out)?;
                let us = start.elapsed().as_secs_f64() * 1e6;
                total += us;
                per_light[i] += us;
                fits[i] += 1;
                active += out.maps().iter().filter(|m| m.is_active()).count();
            }
        }
    }
    let n = (fits[0] + fits[1]) as f64;
    println!("frames {FRAMES}, fits {n}, active maps {active}");
    println!("mean fit: {:.2} us (sun {:.2} us, spot {:.2} us)", total / n, per_light[0] / fits[0] as f64, per_light[1] / fits[1] as f64);
    Ok(())
}
