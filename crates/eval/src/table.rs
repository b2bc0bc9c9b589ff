//! One row per benchmarked configuration, and the CSV / markdown views of a
//! sweep.

use serde::Serialize;

/// Everything measured for one (scene, method, splits, scheme, resolution,
/// skip plan) configuration.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Row {
    pub scene: String,
    /// e.g. `lispsm`, `pssm4-practical-lispsm`.
    pub config: String,
    pub method: String,
    pub splits: usize,
    pub scheme: String,
    pub resolution: u32,
    /// Whether the caster lists and empty-map skips of the fit were used.
    pub plan: bool,
    /// Median CPU time of one `fit` (one thread), µs.
    pub focusing_us: f64,
    /// Shadow + main pass, ms (see `backend`).
    pub render_ms: f64,
    pub shadow_pass_ms: f64,
    /// The same two figures timed by the GPU (timestamp queries); NaN where
    /// the adapter has no timestamps.
    pub gpu_render_ms: f64,
    pub gpu_shadow_ms: f64,
    /// Adapter name and backend, e.g. `llvmpipe (LLVM 15.0.6) / gl`.
    pub backend: String,
    pub maps_active: usize,
    pub maps_skipped: usize,
    /// Depth32Float texels of the active maps × 4 bytes.
    pub texture_bytes: u64,
    pub casters_drawn: u64,
    pub casters_total: u64,
    pub aliasing_max: f64,
    pub aliasing_p95: f64,
    pub aliasing_mean: f64,
    pub mismatch_rate: f64,
    pub mismatch_off_edges: f64,
    /// Least possible maximum aliasing for the same texel budget.
    pub bound: f64,
    /// `aliasing_max / bound`.
    pub ratio: f64,
}

const COLUMNS: &str = "scene,config,method,splits,scheme,resolution,plan,focusing_us,render_ms,shadow_pass_ms,gpu_render_ms,gpu_shadow_ms,backend,maps_active,maps_skipped,texture_bytes,casters_drawn,casters_total,aliasing_max,aliasing_p95,aliasing_mean,mismatch_rate,mismatch_off_edges,bound,ratio";

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// RFC 4180 CSV with a header line.
pub fn to_csv(rows: &[Row]) -> String {
    let mut out = String::from(COLUMNS);
    out.push('\n');
    for r in rows {
        let cells = [
            csv_field(&r.scene),
            csv_field(&r.config),
            r.method.clone(),
            r.splits.to_string(),
            r.scheme.clone(),
            r.resolution.to_string(),
            r.plan.to_string(),
            format!("{:.3}", r.focusing_us),
            format!("{:.3}", r.render_ms),
            format!("{:.3}", r.shadow_pass_ms),
            format!("{:.3}", r.gpu_render_ms),
            format!("{:.3}", r.gpu_shadow_ms),
            csv_field(&r.backend),
            r.maps_active.to_string(),
            r.maps_skipped.to_string(),
            r.texture_bytes.to_string(),
            r.casters_drawn.to_string(),
            r.casters_total.to_string(),
            format!("{:.4}", r.aliasing_max),
            format!("{:.4}", r.aliasing_p95),
            format!("{:.4}", r.aliasing_mean),
            format!("{:.6}", r.mismatch_rate),
            format!("{:.6}", r.mismatch_off_edges),
            format!("{:.4}", r.bound),
            format!("{:.3}", r.ratio),
        ];
        out.push_str(&cells.join(","));
        out.push('\n');
    }
    out
}

fn mib(bytes: u64) -> String {
    format!("{:.1}", bytes as f64 / (1024.0 * 1024.0))
}

/// The main markdown table (plan on only).
pub fn to_markdown(rows: &[Row]) -> String {
    let mut s = String::from(
        "| scene | config | res | fit µs | render ms | MiB | alias max | p95 | mean | ×bound | mismatch % |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in rows.iter().filter(|r| r.plan) {
        s.push_str(&format!(
            "| {} | {} | {} | {:.1} | {:.1} | {} | {:.2} | {:.2} | {:.2} | {:.1} | {:.3} |\n",
            r.scene,
            r.config,
            r.resolution,
            r.focusing_us,
            r.render_ms,
            mib(r.texture_bytes),
            r.aliasing_max,
            r.aliasing_p95,
            r.aliasing_mean,
            r.ratio,
            100.0 * r.mismatch_rate
        ));
    }
    s
}

/// Configurations with the same configured texel budget (`splits ×
/// resolution² = texels`, e.g. one 1024² map or four 512² splits), per scene
/// best first by p95 aliasing.
pub fn budget_markdown(rows: &[Row], texels: u64) -> String {
    let mut sel: Vec<&Row> = rows.iter().filter(|r| r.plan && r.splits as u64 * (r.resolution as u64).pow(2) == texels).collect();
    sel.sort_by(|a, b| a.scene.cmp(&b.scene).then(a.aliasing_p95.total_cmp(&b.aliasing_p95)));
    let mut s = String::from(
        "| scene | config | res | fit µs | alias max | p95 | mean | ×bound | mismatch % |\n|---|---|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in sel {
        s.push_str(&format!(
            "| {} | {} | {} | {:.0} | {:.2} | {:.2} | {:.2} | {:.2} | {:.3} |\n",
            r.scene,
            r.config,
            r.resolution,
            r.focusing_us,
            r.aliasing_max,
            r.aliasing_p95,
            r.aliasing_mean,
            r.ratio,
            100.0 * r.mismatch_rate
        ));
    }
    s
}

/// Plan on against plan off for the same configuration: render time saved,
/// casters culled, maps skipped.
pub fn skips_markdown(rows: &[Row]) -> String {
    let mut s = String::from(
        "| scene | config | res | maps on/off | casters drawn on/off | shadow pass ms on/off | saved % |\n|---|---|---:|---|---|---|---:|\n",
    );
    for on in rows.iter().filter(|r| r.plan) {
        let off = rows.iter().find(|o| !o.plan && o.scene == on.scene && o.config == on.config && o.resolution == on.resolution);
        if let Some(off) = off {
            let saved = if off.shadow_pass_ms > 0.0 { 100.0 * (1.0 - on.shadow_pass_ms / off.shadow_pass_ms) } else { 0.0 };
            s.push_str(&format!(
                "| {} | {} | {} | {}/{} | {}/{} | {:.2}/{:.2} | {:.0} |\n",
                on.scene,
                on.config,
                on.resolution,
                on.maps_active,
                off.maps_active,
                on.casters_drawn,
                off.casters_drawn,
                on.shadow_pass_ms,
                off.shadow_pass_ms,
                saved
            ));
        }
    }
    s
}

/// Indices of the rows on the lower-left Pareto front of `(cost, error)`:
/// no other row is at least as cheap and at least as accurate, and strictly
/// better in one. Rows with a non-finite coordinate are never on it.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<usize> {
    let ok = |p: &(f64, f64)| p.0.is_finite() && p.1.is_finite();
    (0..points.len())
        .filter(|&i| ok(&points[i]))
        .filter(|&i| {
            let (c, e) = points[i];
            !points.iter().any(|q| ok(q) && q.0 <= c && q.1 <= e && (q.0 < c || q.1 < e))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pareto_front_keeps_only_undominated_points() {
        let pts = [(1.0, 5.0), (2.0, 3.0), (3.0, 4.0), (4.0, 1.0), (2.0, 3.0), (f64::NAN, 0.0)];
        assert_eq!(pareto_front(&pts), vec![0, 1, 3, 4]);
    }

    #[test]
    fn budget_table_keeps_equal_budgets_only() {
        let row = |config: &str, splits, resolution, p95| Row {
            scene: "s".into(),
            config: config.into(),
            splits,
            resolution,
            plan: true,
            aliasing_p95: p95,
            ..Row::default()
        };
        let rows = [row("a", 1, 1024, 2.0), row("b", 4, 512, 1.0), row("c", 1, 512, 0.5), row("d", 8, 512, 0.1)];
        let md = budget_markdown(&rows, 1024 * 1024);
        let lines: Vec<&str> = md.lines().skip(2).collect();
        assert_eq!(lines.len(), 2, "{md}");
        assert!(lines[0].contains("| b |") && lines[1].contains("| a |"), "sorted by p95: {md}");
    }

    #[test]
    fn csv_quotes_fields_with_commas() {
        let r = Row { scene: "a,b".into(), backend: "x \"y\"".into(), ..Row::default() };
        let csv = to_csv(&[r]);
        let line = csv.lines().nth(1).unwrap();
        assert!(line.starts_with("\"a,b\","), "{line}");
        assert!(line.contains("\"x \"\"y\"\"\""), "{line}");
        assert_eq!(csv.lines().next().unwrap().split(',').count(), 25);
        // Every row has one cell per column.
        let plain = to_csv(&[Row::default()]);
        let mut lines = plain.lines();
        assert_eq!(lines.next().unwrap().split(',').count(), lines.next().unwrap().split(',').count());
    }
}
