//! The big-integer oracle against the CGAL fixtures: two independent exact
//! computations of the same bodies must agree, or one of them is wrong.

use shadowfocus_eval::{fixtures, oracle};
use std::path::Path;

#[test]
fn oracle_agrees_with_the_cgal_fixtures() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures");
    let mut checked = 0;
    let mut by_dimension = [0usize; 5];
    for file in fixtures::FILES {
        let (cases, _) = fixtures::read_file(&dir, file).expect("fixtures readable");
        // Every fourth case keeps the test at a few seconds; every file and
        // every light kind is still covered.
        for c in cases.iter().step_by(4) {
            let h = oracle::exact_body(&c.view, &c.light, &c.scene).expect("finite fixture");
            assert_eq!(h.dimension, c.expected_dimension, "{file} {}: dimension", c.id);
            let a = oracle::compare(&h, c.expected_dimension, &c.expected_vertices);
            assert!(a.vertex_counts_match, "{file} {}: {} exact vertices, CGAL has {}", c.id, h.vertices.len(), c.expected_vertices.len());
            // CGAL's vertices are the exact ones rounded to nearest: half an
            // ulp per coordinate, at most an ulp of the case's magnitude.
            assert!(
                a.max_vertex_error <= f64::EPSILON * c.magnitude,
                "{file} {}: vertex error {:e} (magnitude {:e})",
                c.id,
                a.max_vertex_error,
                c.magnitude
            );
            by_dimension[(h.dimension + 1) as usize] += 1;
            checked += 1;
        }
    }
    eprintln!("oracle = CGAL on {checked} cases (by dimension −1..3: {by_dimension:?})");
    assert!(checked > 900, "only {checked} fixture cases checked");
    assert!(by_dimension.iter().all(|&n| n > 0), "some dimension never occurs: {by_dimension:?}");
}
