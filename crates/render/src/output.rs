//! Writing a render's images and metrics to a directory.

use std::path::{Path, PathBuf};

use crate::error::RenderError;
use crate::frame::RenderOutput;
use crate::image::{aliasing_heatmap, depth_image, mismatch_image, Image};
use crate::metrics::pixel_matches;
use crate::stats::RenderMetrics;

/// The aliasing heatmap of a render, with its legend. Pixels outside a spot light's pyramid need
/// no shadow map and are drawn as unlit.
pub fn aliasing_image(out: &RenderOutput) -> Image {
    let e: Vec<f32> = out
        .aliasing
        .iter()
        .zip(&out.world)
        .map(|(&e, w)| {
            let p = glam::DVec3::new(w[0] as f64, w[1] as f64, w[2] as f64);
            if w[3] != 0.0 && !out.light.in_spot(p) {
                crate::image::HEAT_UNLIT_VALUE
            } else {
                e
            }
        })
        .collect();
    let receiver: Vec<bool> = out.world.iter().map(|w| w[3] == 1.0).collect();
    aliasing_heatmap(out.width, out.height, &e, Some(&receiver), &caption(&out.metrics))
}

/// The scene name with the maps' mean utilisation, where known ("forest  util 43%").
pub fn caption(m: &RenderMetrics) -> String {
    match m.utilisation_mean {
        Some(u) => format!("{}  util {:.0}%", m.scene, 100.0 * u),
        None => m.scene.clone(),
    }
}

/// The mismatch image, when the render has ground truth.
pub fn mismatch_view(out: &RenderOutput) -> Option<Image> {
    let truth = out.truth.as_ref()?;
    Some(mismatch_image(&out.color, &pixel_matches(out, truth, out.metrics.settings.edge_radius)))
}

/// Depth views of the shadow maps that were read back.
pub fn shadow_map_images(out: &RenderOutput) -> Vec<Image> {
    out.shadow_maps.iter().map(|m| depth_image(m.resolution, &m.depth)).collect()
}

/// `metrics` as a JSON object, with the top-level fields of `extra` (an object) merged in front
/// (e.g. method, focusing µs).
pub fn metrics_json(metrics: &RenderMetrics, extra: Option<&serde_json::Value>) -> serde_json::Value {
    let mut obj = serde_json::Map::new();
    if let Some(serde_json::Value::Object(e)) = extra {
        for (k, v) in e {
            obj.insert(k.clone(), v.clone());
        }
    }
    if let Ok(serde_json::Value::Object(m)) = serde_json::to_value(metrics) {
        for (k, v) in m {
            obj.entry(k).or_insert(v);
        }
    }
    serde_json::Value::Object(obj)
}

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> RenderError + '_ {
    move |source| RenderError::Io { path: path.to_path_buf(), source }
}

/// Writes `image.png`, `shadow_map_K.png`, `aliasing.png`, `mismatch.png` (with ground truth) and
/// `metrics.json` into `dir` (created if needed). Returns the files written.
pub fn write_outputs(dir: &Path, out: &RenderOutput, extra: Option<&serde_json::Value>) -> Result<Vec<PathBuf>, RenderError> {
    std::fs::create_dir_all(dir).map_err(io_err(dir))?;
    let mut written = Vec::new();
    let mut save = |name: String, img: &Image| -> Result<(), RenderError> {
        let p = dir.join(name);
        img.save_png(&p)?;
        written.push(p);
        Ok(())
    };
    save("image.png".into(), &out.color)?;
    for (k, img) in shadow_map_images(out).iter().enumerate() {
        save(format!("shadow_map_{k}.png"), img)?;
    }
    save("aliasing.png".into(), &aliasing_image(out))?;
    if let Some(m) = mismatch_view(out) {
        save("mismatch.png".into(), &m)?;
    }
    let p = dir.join("metrics.json");
    let text =
        serde_json::to_string_pretty(&metrics_json(&out.metrics, extra)).map_err(|e| RenderError::invalid("metrics", e.to_string()))?;
    std::fs::write(&p, text + "\n").map_err(io_err(&p))?;
    written.push(p);
    Ok(written)
}
