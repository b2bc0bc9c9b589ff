//! Arbitrary bytes through the JSON-lines reader and `shadowfocus body`:
//! never a panic; one output line per non-blank input line, each a JSON
//! object with an `id` and either a body or an `error`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use shadowfocus::cli::body::run;
use shadowfocus::cli::case::parse_case;

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
    let expected = text.lines().filter(|l| !l.trim().is_empty()).count();
    let out = String::from_utf8(out).expect("output is UTF-8");
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), expected, "one result per case line");
    let mut errors = 0;
    for l in &lines {
        let v: serde_json::Value = serde_json::from_str(l).expect("each result is JSON");
        assert!(v.get("id").is_some(), "result without id: {l}");
        if v.get("error").is_some() {
            errors += 1;
        } else {
            let dim = v["dimension"].as_i64().expect("dimension");
            assert!((-1..=3).contains(&dim));
        }
    }
    assert_eq!(errors, failed, "the failure count matches the error lines");
});
