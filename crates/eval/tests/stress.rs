//! Pass/fail part of the numerical stress suite: the exact body and the
//! fitted maps must survive every stress family; the naive pipeline is
//! expected to break somewhere (else the comparison shows nothing).

use shadowfocus_eval::{fixtures, stress};
use std::path::Path;
use std::sync::OnceLock;

fn outcomes() -> &'static [stress::StressOutcome] {
    static O: OnceLock<Vec<stress::StressOutcome>> = OnceLock::new();
    O.get_or_init(stress::run_all)
}

#[test]
fn every_family_is_swept() {
    let o = outcomes();
    for fam in ["far_over_near", "world_offset", "light_distance", "gamma_behind", "gamma_front", "coplanar", "scale"] {
        assert!(o.iter().filter(|c| c.family == fam).count() >= 3, "family {fam} missing");
    }
    // γ reaches exactly 0 and light distance 1e15.
    assert!(o.iter().any(|c| c.family == "gamma_front" && c.param == 0.0));
    assert!(o.iter().any(|c| c.family == "light_distance" && c.param == 1e15));
}

#[test]
fn body_agrees_with_the_big_integer_oracle() {
    for o in outcomes() {
        assert!(o.body_error.is_none(), "{} {}: {:?}", o.family, o.label, o.body_error);
        assert!(
            o.oracle_agrees,
            "{} {}: ours dim {} with {} vertices, exact dim {} with {}",
            o.family, o.label, o.dimension, o.vertices, o.oracle_dimension, o.oracle_vertices
        );
        // Rounding to nearest moves a vertex by at most half an ulp of its
        // largest coordinate; the body engine promises a few ulps.
        assert!(o.oracle_error <= 16.0 * f64::EPSILON, "{} {}: vertex error {:e} of the magnitude", o.family, o.label, o.oracle_error);
    }
    // Not vacuous: every kind of result the families produce is compared.
    let dims: std::collections::BTreeSet<i32> = outcomes().iter().map(|o| o.oracle_dimension).collect();
    assert!([0, 2, 3].iter().all(|d| dims.contains(d)), "dimensions seen: {dims:?}");
}

#[test]
fn body_never_loses_a_view_corner_inside_the_scene() {
    for o in outcomes() {
        assert!(o.body_error.is_none(), "{} {}: {:?}", o.family, o.label, o.body_error);
        assert_eq!(o.exact_violations, 0, "{} {}: corner of V ∩ S outside H", o.family, o.label);
        // Rounded body: at most a few ulps of the magnitude outside.
        assert!(o.rounded_excess <= 64.0 * f64::EPSILON, "{} {}: rounded excess {:e}", o.family, o.label, o.rounded_excess);
    }
    // The check is not vacuous: most cases have corners of V inside S.
    assert!(outcomes().iter().filter(|o| o.corners_in_scene > 0).count() * 2 > outcomes().len());
}

#[test]
fn fitted_maps_contain_their_bodies() {
    for o in outcomes() {
        assert!(o.fit_errors.is_empty(), "{} {}: {:?}", o.family, o.label, o.fit_errors);
        assert_eq!(
            o.maps_not_containing, 0,
            "{} {}: {} of {} maps leave H outside the clip volume",
            o.family, o.label, o.maps_not_containing, o.maps_checked
        );
    }
    assert!(outcomes().iter().all(|o| o.dimension != 3 || o.maps_checked > 0));
}

#[test]
fn naive_pipeline_breaks_where_ours_does_not() {
    let broke: Vec<_> = outcomes().iter().filter(|o| stress::naive_broke(o)).map(|o| format!("{} {}", o.family, o.label)).collect();
    assert!(!broke.is_empty(), "the naive pipeline survived every stress case");
}

#[test]
fn body_matches_the_cgal_fixtures_and_the_naive_pipeline_does_not() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures");
    let rows = fixtures::compare_all(&dir).expect("fixtures readable");
    let cases: usize = rows.iter().map(|r| r.cases - r.skipped).sum();
    assert!(cases > 1000, "only {cases} fixture cases read");
    for r in &rows {
        assert_eq!(r.ours_errors, 0, "{}", r.file);
        assert_eq!(r.ours_dimension_mismatches, 0, "{}", r.file);
        assert!(r.ours_max_vertex_error <= 64.0 * f64::EPSILON, "{}: {:e}", r.file, r.ours_max_vertex_error);
    }
    let naive_bad: usize = rows.iter().map(|r| r.naive_lost + r.naive_degenerate + r.naive_failed).sum();
    eprintln!("{}", fixtures::report_markdown(&rows));
    assert!(naive_bad > 0, "naive pipeline agreed with CGAL everywhere");
}
