//! `shadowfocus bench`: run time against error over the built-in scenes,
//! methods, splits and resolutions; the skip plan on and off; the numerical
//! stress report. Writes `results.csv`, `results.md`, Pareto plots (SVG and PNG) and
//! `stress.md` into the output folder.

use super::fit::FitOptions;
use super::render::fit_scene;
use render::{RenderRequest, Renderer, Scene, ShadowMapSpec};
use serde_json::{json, Value};
use shadowfocus_eval::{fixtures, plot, raster, stress, svg, table};
use shadowfocus_focus::Method;
use shadowfocus_render as render;
use std::path::{Path, PathBuf};
use std::time::Instant;
use table::Row;

/// Options of `shadowfocus bench`.
#[derive(Clone, Debug, clap::Args)]
pub struct BenchOptions {
    /// Small sweep for CI: two scenes, a few configurations, 512 and 1024
    /// texels, 320×180 images.
    #[arg(long)]
    pub quick: bool,
    /// Output folder.
    #[arg(long, default_value = "out/bench")]
    pub out: PathBuf,
    /// Scenes (default: all built-in scenes; two with --quick).
    #[arg(long, value_delimiter = ',')]
    pub scenes: Vec<String>,
    /// Shadow-map resolutions per map (default 512,1024,2048,4096; 512,1024 with --quick).
    #[arg(long, value_delimiter = ',')]
    pub resolutions: Vec<u32>,
    /// Image size, WxH (default 640x360; 320x180 with --quick).
    #[arg(long, value_parser = super::render::parse_size)]
    pub size: Option<(u32, u32)>,
    /// Every split count 1–8 with every scheme and method (long).
    #[arg(long)]
    pub full: bool,
    /// Skip the numerical stress and fixture report.
    #[arg(long)]
    pub no_stress: bool,
    /// Folder with the CGAL fixtures (cases/, expected/).
    #[arg(long, default_value = "fixtures")]
    pub fixtures: PathBuf,
}

const METHODS: [Method; 4] = [Method::Uniform, Method::Psm, Method::Lispsm, Method::Tsm];

fn opts(method: Method, splits: usize, scheme: &str, resolution: u32) -> FitOptions {
    FitOptions { method, splits, scheme: Some(scheme.into()), resolution, ..FitOptions::default() }
}

/// Configuration name: `lispsm`, `pssm4-log-lispsm`.
pub fn label(o: &FitOptions) -> String {
    if o.splits == 1 {
        o.method.name().to_string()
    } else {
        format!("pssm{}-{}-{}", o.splits, o.scheme_name(), o.method.name())
    }
}

/// The configurations of a sweep at one resolution (also benchmarked by
/// criterion: `cargo bench --bench scenes`).
pub fn configs(quick: bool, full: bool, res: u32) -> Vec<FitOptions> {
    let mut v: Vec<FitOptions> = METHODS.iter().map(|&m| opts(m, 1, "practical", res)).collect();
    if quick {
        v.push(opts(Method::Lispsm, 4, "practical", res));
        return v;
    }
    let (counts, schemes): (&[usize], &[&str]) =
        if full { (&[2, 3, 4, 5, 6, 7, 8], &["uniform", "log", "practical", "optimal"]) } else { (&[2, 4, 8], &["practical", "optimal"]) };
    for &m in &METHODS {
        for &k in counts {
            for s in schemes {
                v.push(opts(m, k, s, res));
            }
        }
    }
    if !full {
        // The schemes compared on the default warp.
        for s in ["uniform", "log"] {
            v.push(opts(Method::Lispsm, 4, s, res));
        }
        // Auto, one map and the same splits, beside the methods it chooses
        // among (`--full` keeps to the four methods).
        v.push(opts(Method::Auto, 1, "practical", res));
        for &k in counts {
            for s in schemes {
                v.push(opts(Method::Auto, k, s, res));
            }
        }
    }
    v
}

fn progress(done: usize, total: usize, what: &str) {
    let width = 30;
    let filled = done * width / total.max(1);
    eprint!("\r[{}{}] {done}/{total} {what:<48}", "#".repeat(filled), "-".repeat(width - filled));
    if done == total {
        eprintln!();
    }
}

/// Renders one configuration; `plan` false draws every object into every
/// active map (no caster culling) and skips the ground truth.
fn measure(renderer: &mut Renderer, scene: &Scene, o: &FitOptions, size: (u32, u32), plan: bool) -> Result<Row, String> {
    let settings = o.settings()?;
    let aspect = size.0 as f64 / size.1 as f64;
    let (mut maps, focusing_us, summary): (Vec<ShadowMapSpec>, f64, Value) = fit_scene(scene, aspect, &settings)?;
    if !plan {
        let all: Vec<u32> = (0..scene.objects.len() as u32).collect();
        for m in &mut maps {
            m.casters = all.clone();
        }
    }
    let mut req = RenderRequest::new(scene, &maps);
    req.settings.width = size.0;
    req.settings.height = size.1;
    req.settings.shadow_resolution = o.resolution;
    req.settings.save_shadow_maps = false;
    req.settings.ground_truth = plan;
    req.settings.timing_repeats = 2;
    let out = renderer.render(&req).map_err(|e| format!("{} {}: {e}", scene.name, label(o)))?;
    let m = &out.metrics;
    let active = maps.len();
    let fitted = summary["maps_fitted"].as_u64().unwrap_or(active as u64) as usize;
    let texels = active as f64 * (o.resolution as f64).powi(2);
    // The render's own bound: the same texels, image and camera.
    let bound = m.aliasing.bound;
    let (rate, off) = m.mismatch.map_or((f64::NAN, f64::NAN), |x| (x.rate, x.rate_off_edges));
    Ok(Row {
        scene: scene.name.clone(),
        config: label(o),
        method: o.method.name().into(),
        splits: o.splits,
        scheme: if o.splits == 1 { "-".into() } else { o.scheme_name().to_string() },
        resolution: o.resolution,
        plan,
        focusing_us,
        render_ms: m.render_ms,
        shadow_pass_ms: m.shadow_pass_ms,
        gpu_render_ms: match (m.shadow_gpu_ms, m.main_gpu_ms) {
            (Some(s), Some(main)) => s + main,
            (None, Some(main)) if active == 0 => main,
            _ => f64::NAN,
        },
        gpu_shadow_ms: m.shadow_gpu_ms.unwrap_or(if active == 0 { 0.0 } else { f64::NAN }),
        backend: format!("{} / {}", m.adapter.name, m.adapter.backend),
        maps_active: active,
        maps_skipped: fitted.saturating_sub(active),
        texture_bytes: (texels * 4.0) as u64,
        casters_drawn: m.casters.per_map.iter().map(|&x| x as u64).sum(),
        casters_total: (m.casters.total as u64) * active as u64,
        aliasing_max: m.aliasing.max,
        aliasing_p95: m.aliasing.p95,
        aliasing_mean: m.aliasing.mean,
        mismatch_rate: rate,
        mismatch_off_edges: off,
        bound,
        ratio: m.aliasing.max / bound,
    })
}

fn family(r: &Row) -> String {
    if r.splits == 1 {
        r.method.clone()
    } else {
        format!("pssm-{}", r.method)
    }
}

fn plots(dir: &Path, rows: &[Row]) -> Result<Vec<String>, String> {
    let mut written = Vec::new();
    let mut scenes: Vec<&str> = rows.iter().map(|r| r.scene.as_str()).collect();
    scenes.dedup();
    for scene in scenes {
        let sel: Vec<&Row> = rows.iter().filter(|r| r.plan && r.scene == scene).collect();
        let pts = |x: &dyn Fn(&Row) -> f64, keep: &dyn Fn(&Row) -> bool| -> Vec<plot::Point> {
            sel.iter()
                .filter(|r| keep(r))
                .map(|r| plot::Point { x: x(r), y: r.aliasing_p95, series: family(r), label: format!("{} @{}", r.config, r.resolution) })
                .collect()
        };
        // Focusing time does not depend on the resolution: plot one
        // resolution per map (1024, or the nearest below it) so that each
        // configuration appears once.
        let res =
            sel.iter().map(|r| r.resolution).filter(|&r| r <= 1024).max().or_else(|| sel.iter().map(|r| r.resolution).min()).unwrap_or(0);
        let time_title = format!("{scene}: aliasing p95 vs focusing time ({res}² per map)");
        let mem_title = format!("{scene}: aliasing p95 vs texture memory");
        let (time_x, mem_x, y) =
            ("focusing time per frame (µs, one thread)", "shadow-map memory (MiB)", "aliasing p95 (screen px per texel)");
        let time_pts = pts(&|r| r.focusing_us, &|r| r.resolution == res);
        let mem_pts = pts(&|r| r.texture_bytes as f64 / 1048576.0, &|_| true);
        for (kind, title, x, points) in [("time", &time_title, time_x, &time_pts), ("memory", &mem_title, mem_x, &mem_pts)] {
            let stem = format!("pareto_{kind}_{scene}");
            let png = raster::scatter_png(title, x, y, points).map_err(|e| format!("{stem}.png: {e}"))?;
            for (name, body) in [(format!("{stem}.svg"), svg::scatter(title, x, y, points).into_bytes()), (format!("{stem}.png"), png)] {
                std::fs::write(dir.join(&name), body).map_err(|e| format!("{name}: {e}"))?;
                written.push(name);
            }
        }
    }
    Ok(written)
}

fn stress_section(fixtures_dir: &Path) -> String {
    let mut s = String::from("## Numerical stress\n\nEvery case is checked exactly (see `crates/eval/src/stress.rs`). \"oracle\": the exact body computed independently with big integers (`crates/eval/src/oracle.rs`: every halfspace of M, S and L, every vertex by exact three-plane intersection); its dimension and vertex count, marked ≠ where ours differ. \"vertex error\": the distance between our rounded vertices and the exact ones (both ways), relative to the input magnitude. \"violations\": corners of V ∩ S outside the exact body (decided exactly by the oracle). \"rounded excess\": how far a corner of V ∩ S or an exact vertex lies outside the reported (rounded) body's planes, relative to the input magnitude. \"maps ok\": fitted maps (uniform, PSM, LiSPSM, TSM, 4-split LiSPSM) whose clip volume contains their body. \"naive\": the f64 hull + ε-clip pipeline; \"naive lost\": corners of V ∩ S it excludes (decided exactly).\n\n");
    s.push_str(&stress::report_markdown(&stress::run_all()));
    s.push_str("\n## Against the exact (CGAL) fixtures\n\n");
    match fixtures::compare_all(fixtures_dir) {
        Ok(rows) => {
            s.push_str(&format!("Vertex error: distance from each of our vertices to the nearest exact vertex, relative to the case's magnitude. The naive pipeline \"lost part of H\" when an exact vertex lies more than {:e} (relative) outside its result; spot lights are not run through it.\n\n", fixtures::LOSS_TOLERANCE));
            s.push_str(&fixtures::report_markdown(&rows));
        }
        Err(e) => s.push_str(&format!("(fixtures not read: {e})\n")),
    }
    s
}

/// Runs the sweep and writes its outputs; returns a JSON summary.
pub fn run(o: &BenchOptions) -> Result<Value, String> {
    let started = Instant::now();
    std::fs::create_dir_all(&o.out).map_err(|e| format!("{}: {e}", o.out.display()))?;
    let scenes: Vec<String> = if !o.scenes.is_empty() {
        o.scenes.clone()
    } else if o.quick {
        vec!["chessboard".into(), "forest".into()]
    } else {
        render::BUILTIN_SCENES.iter().map(|s| s.to_string()).collect()
    };
    let resolutions: Vec<u32> = if !o.resolutions.is_empty() {
        o.resolutions.clone()
    } else if o.quick {
        vec![512, 1024]
    } else {
        vec![512, 1024, 2048, 4096]
    };
    let size = o.size.unwrap_or(if o.quick { (320, 180) } else { (640, 360) });
    let mut renderer = Renderer::from_env().map_err(|e| e.to_string())?;
    // Plan off only at the smallest resolution: it measures caster culling.
    let mut jobs: Vec<(String, FitOptions, bool)> = Vec::new();
    for s in &scenes {
        for &r in &resolutions {
            for c in configs(o.quick, o.full, r) {
                jobs.push((s.clone(), c.clone(), true));
                if r == resolutions[0] {
                    jobs.push((s.clone(), c, false));
                }
            }
        }
    }
    let mut rows = Vec::new();
    let mut loaded: Option<Scene> = None;
    for (i, (name, c, plan)) in jobs.iter().enumerate() {
        progress(i, jobs.len(), &format!("{name} {} @{}{}", label(c), c.resolution, if *plan { "" } else { " (plan off)" }));
        if loaded.as_ref().is_none_or(|s| &s.name != name) {
            loaded = Some(render::load_scene(name).map_err(|e| e.to_string())?);
        }
        let scene = loaded.as_ref().ok_or("scene not loaded")?;
        rows.push(measure(&mut renderer, scene, c, size, *plan)?);
    }
    progress(jobs.len(), jobs.len(), "done");
    let adapter = renderer.adapter().clone();
    std::fs::write(o.out.join("results.csv"), table::to_csv(&rows)).map_err(|e| e.to_string())?;
    let svgs = plots(&o.out, &rows)?;
    let mut md = format!(
        "# Run time against error\n\nAdapter: {} ({}, {}). Images {}×{}. Focusing time: median of 7 fits, one thread. Render time: shadow + main pass on this adapter{}. Memory: Depth32Float texels of the active maps. \"×bound\": max aliasing over the least possible max aliasing for the same texel budget (logarithmic parameterisation; `crates/render/src/bound.rs`).\n\n",
        adapter.name,
        adapter.backend,
        adapter.device_type,
        size.0,
        size.1,
        if adapter.device_type.to_lowercase().contains("cpu") { " (a CPU rasteriser: relative numbers only)" } else { "" }
    );
    // Equal configured budget: one map at the second resolution, or four
    // splits at half of it (1024² texels by default).
    let budget_res = resolutions.get(1).copied().unwrap_or(resolutions[0]) as u64;
    md.push_str(&format!("## Equal texel budget ({budget_res}² texels: one {budget_res}² map or four {}² splits)\n\n", budget_res / 2));
    md.push_str(&table::budget_markdown(&rows, budget_res * budget_res));
    md.push_str("\n## Every configuration\n\n");
    md.push_str(&table::to_markdown(&rows));
    md.push_str(&format!("\n## Skip plan on and off (resolution {})\n\nOff: every object drawn into every active map (no caster culling). Empty maps are never rendered either way; \"maps skipped\" per configuration is in results.csv.\n\n", resolutions[0]));
    md.push_str(&table::skips_markdown(&rows));
    md.push_str("\n## Plots\n\n");
    for s in &svgs {
        md.push_str(&format!("- [{s}]({s})\n"));
    }
    if !o.no_stress {
        eprintln!("stress suite …");
        let section = stress_section(&o.fixtures);
        std::fs::write(o.out.join("stress.md"), &section).map_err(|e| e.to_string())?;
        md.push('\n');
        md.push_str(&section);
    }
    std::fs::write(o.out.join("results.md"), &md).map_err(|e| e.to_string())?;
    Ok(json!({
        "rows": rows.len(),
        "adapter": adapter,
        "size": [size.0, size.1],
        "out": o.out.display().to_string(),
        "plots": svgs,
        "seconds": started.elapsed().as_secs_f64(),
    }))
}
