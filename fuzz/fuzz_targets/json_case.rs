//! Arbitrary bytes through the JSON-lines reader and `shadowfocus body`:
//! never a panic; one output line per non-blank input line, each a JSON
//! object with an `id` and either a body or an `error`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use shadowfocus_cli::cli::body::run;
use shadowfocus_cli::cli::case::parse_case;
use shadowfocus_fuzz::check_result_lines;

fuzz_target!(|data: &[u8]| {
    let text = std::str::from_utf8(data).ok();
    if let Some(text) = text {
        for line in text.lines() {
            let _ = parse_case(line);
        }
    }
    let mut out = Vec::new();
    let result = run(std::io::Cursor::new(data), &mut out);
    let Some(text) = text else {
        // Not UTF-8: the reader may stop with an I/O error, but not panic.
        return;
    };
    let failed = result.expect("UTF-8 input reads without I/O errors");
    check_result_lines(text, out, failed, |v, _| {
        let dim = v["dimension"].as_i64().expect("dimension");
        assert!((-1..=3).contains(&dim));
    });
});
