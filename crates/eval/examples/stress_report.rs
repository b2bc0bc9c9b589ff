//! Prints the numerical stress report and the CGAL fixture comparison as
//! markdown: `cargo run --release -p shadowfocus-eval --example stress_report`.

use shadowfocus_eval::{fixtures, stress};
use std::path::Path;

fn main() {
    println!("{}", stress::report_markdown(&stress::run_all()));
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures");
    match fixtures::compare_all(&dir) {
        Ok(rows) => println!("{}", fixtures::report_markdown(&rows)),
        Err(e) => eprintln!("fixtures: {e}"),
    }
}
