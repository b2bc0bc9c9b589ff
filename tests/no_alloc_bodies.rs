//! The certified float path allocates nothing once a `Body` has been used,
//! including the bodies that place a vertex from its planes' exact
//! intersection: checked with a counting allocator over every fixture.

use shadowfocus::cli::case::parse_case;
use shadowfocus::geom::{focus_body_into, Body};
use std::alloc::{GlobalAlloc, Layout, System};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;
static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn float_path_bodies_do_not_allocate() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/cases");
    let mut cases = Vec::new();
    for name in ["classic", "directional", "point", "spot", "scene", "extreme"] {
        let text = std::fs::read_to_string(root.join(format!("{name}.jsonl"))).unwrap();
        cases.extend(text.lines().filter(|l| !l.trim().is_empty()).map(|l| parse_case(l).unwrap()));
    }
    let mut body = Body::new();
    // A first pass sizes the body's scratch space (and lets the test
    // harness finish its own allocations).
    for case in &cases {
        focus_body_into(&mut body, &case.view, &case.light, &case.scene).unwrap();
    }
    let (mut float_path, mut placed_exactly, mut exact_engine) = (0, 0, 0);
    for case in &cases {
        let before = ALLOCATIONS.load(Ordering::Relaxed);
        focus_body_into(&mut body, &case.view, &case.light, &case.scene).unwrap();
        let allocated = ALLOCATIONS.load(Ordering::Relaxed) - before;
        let stats = body.stats();
        if stats.float_path {
            assert_eq!(allocated, 0, "{}", case.id);
            float_path += 1;
            placed_exactly += (stats.exact_evaluations > 0) as usize;
        } else {
            exact_engine += 1;
        }
    }
    eprintln!("{float_path} float-path bodies ({placed_exactly} with a vertex placed exactly), {exact_engine} from the exact engine");
    assert!(float_path > 3700 && placed_exactly > 50, "{float_path} float-path bodies, {placed_exactly} placed exactly");
}
