//! Command-line front end: JSON-lines I/O and the render commands around
//! the library crates.

pub mod animate;
pub mod bench;
pub mod body;
pub use shadowfocus_case as case;
pub mod fit;
pub mod overrides;
pub mod render;
pub mod sweep;

/// What the `--bench` tests share: input lines and the check of a timing.
#[cfg(test)]
pub(crate) mod bench_test {
    /// The first `n` non-blank lines of the smoke fixtures.
    pub fn smoke_lines(n: usize) -> Vec<String> {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/cases/smoke.jsonl");
        let text = std::fs::read_to_string(path).unwrap();
        text.lines().filter(|l| !l.trim().is_empty()).take(n).map(str::to_owned).collect()
    }

    /// Every timing in `keys` is a positive, finite number of nanoseconds.
    pub fn assert_times(r: &serde_json::Value, keys: &[&str]) {
        for key in keys {
            let t = r[*key].as_f64().unwrap();
            assert!(t > 0.0 && t.is_finite(), "{key}: {t}");
        }
    }
}
