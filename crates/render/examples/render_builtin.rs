//! Renders built-in scenes with the plain test-only fits and writes images and metrics.
//!
//! cargo run --release -p shadowfocus-render --example render_builtin -- [OUT_DIR] [SCENE...]
//!
//! Options through the environment: SF_SIZE=WxH (default 640x360), SF_RES=1024, SF_SPLITS=N
//! (directional scenes: N parallel-split maps instead of one scene-box map), SF_PCF=off|hw|R
//! (kernel radius R), SF_BAND=fraction (split blend band), SF_BLUR=world radius (eye-space
//! blur, 2 iterations), SF_LINEAR=1 (linear light depth).

use std::path::PathBuf;

use shadowfocus_render::*;

fn main() -> Result<(), RenderError> {
    let mut args = std::env::args().skip(1);
    let out_dir = PathBuf::from(args.next().unwrap_or_else(|| "out/render-builtin".into()));
    let mut names: Vec<String> = args.collect();
    if names.is_empty() {
        names = BUILTIN_SCENES.iter().map(|s| s.to_string()).collect();
    }
    let size = std::env::var("SF_SIZE").unwrap_or_else(|_| "640x360".into());
    let (w, h) = size.split_once('x').and_then(|(a, b)| Some((a.parse().ok()?, b.parse().ok()?))).unwrap_or((640, 360));
    let res: u32 = std::env::var("SF_RES").ok().and_then(|v| v.parse().ok()).unwrap_or(1024);
    let splits: usize = std::env::var("SF_SPLITS").ok().and_then(|v| v.parse().ok()).unwrap_or(1);
    let mut renderer = Renderer::from_env()?;
    eprintln!("adapter: {:?}", renderer.adapter());
    let mut tiles = Vec::new();
    for name in &names {
        let t0 = std::time::Instant::now();
        let scene = load_scene(name)?;
        let build_ms = t0.elapsed().as_secs_f64() * 1e3;
        let aspect = w as f64 / h as f64;
        let maps = match (splits > 1, scene.light) {
            (true, LightSpec::Directional { .. }) => testfit::split_maps(&scene, &scene.camera, &scene.light, aspect, splits)?,
            _ => vec![testfit::scene_box_map(&scene, &scene.camera, &scene.light, aspect)?],
        };
        let mut req = RenderRequest::new(&scene, &maps);
        req.settings.width = w;
        req.settings.height = h;
        req.settings.shadow_resolution = res;
        req.settings.timing_repeats = 3;
        let env = |k: &str| std::env::var(k).ok();
        if let Some(p) = env("SF_PCF") {
            req.settings.pcf = match p.as_str() {
                "off" => Pcf::Off,
                "hw" => Pcf::Hardware2x2,
                r => Pcf::Kernel { radius: r.parse().unwrap_or(1) },
            };
        }
        if let Some(b) = env("SF_BAND").and_then(|v| v.parse().ok()) {
            req.settings.blend_band = b;
        }
        if let Some(r) = env("SF_BLUR").and_then(|v| v.parse().ok()) {
            req.settings.blur = Some(EyeBlur { world_radius: r, max_radius_px: 8.0, iterations: 2 });
        }
        if env("SF_LINEAR").as_deref() == Some("1") {
            req.settings.depth = DepthMode::Linear { constant: 2e-5, slope_scale: 2.0 };
        }
        let out = renderer.render(&req)?;
        let dir = out_dir.join(name.replace(['/', '.'], "_"));
        write_outputs(&dir, &out, Some(&serde_json::json!({ "method": "test-fit", "scene_build_ms": build_ms })))?;
        let m = &out.metrics;
        let mm = m.mismatch.unwrap_or_default();
        println!(
            "{name:16} tris {:7} build {:7.1} ms  render {:8.1} ms (shadow {:7.1}, main {:7.1})  gt {:8.1} ms  e max {:9.3} p95 {:7.3} mean {:7.3}  mismatch {:.4} off-edge {:.5}  coverage {}/{}  casters {}/{}",
            scene.triangle_count(),
            build_ms,
            m.render_ms,
            m.shadow_pass_ms,
            m.main_pass_ms,
            m.ground_truth_ms,
            m.aliasing.max,
            m.aliasing.p95,
            m.aliasing.mean,
            mm.rate,
            mm.rate_off_edges,
            m.coverage.covered,
            m.coverage.required,
            m.casters.drawn,
            m.casters.total
        );
        tiles.push((out.color.downscale(2), format!("{name}  e p95 {:.2}  mismatch {:.3}", m.aliasing.p95, mm.rate_off_edges)));
    }
    let refs: Vec<(&Image, &str)> = tiles.iter().map(|(i, l)| (i, l.as_str())).collect();
    contact_sheet(&refs, 3).save_png(&out_dir.join("contact_sheet.png"))?;
    Ok(())
}
