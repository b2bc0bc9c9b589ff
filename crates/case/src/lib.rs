//! The JSON-lines case format (a view, a light, a scene box per line) that the command line,
//! the evaluation harness, the tests, the fuzz targets and the benches all read.
//!
//! ```text
//! {"id": "c1",
//!  "view": {"corners": [[x,y,z], … 8]} | {"eye": […], "forward": […], "up": […], "fovy_deg": f, "aspect": f, "near": f, "far": f},
//!  "light": {"directional": [dx,dy,dz]} | {"point": [x,y,z]}
//!         | {"spot": {"position": […], "corners": [… 8]}} | {"spot": {"position": […], "forward": […], "up": […], "fovy_deg": f, "aspect": f, "near": f, "far": f}},
//!  "scene": {"min": [x,y,z], "max": [x,y,z]}}
//! ```

use glam::DVec3;
use serde::Deserialize;
use serde_json::Value;
use shadowfocus_geom::{Aabb, Camera, Frustum, GeomError, Light};
use std::fmt;

/// A case after validation.
#[derive(Clone, Debug)]
pub struct Case {
    pub id: Value,
    pub view: Frustum,
    /// The camera, when the case gave one (else recovered by the caller).
    pub camera: Option<Camera>,
    pub light: Light,
    pub scene: Aabb,
}

/// Why a line could not be used.
#[derive(Debug)]
pub struct CaseError {
    /// The case id if it could be read.
    pub id: Value,
    pub message: String,
}

impl fmt::Display for CaseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawCase {
    /// Read separately so that errors can carry it; listed to be accepted.
    #[serde(default, rename = "id")]
    _id: Value,
    view: RawFrustum,
    light: RawLight,
    scene: RawBox,
}

#[derive(Deserialize)]
#[serde(untagged)]
enum RawFrustum {
    Corners { corners: Vec<[f64; 3]> },
    Camera { eye: [f64; 3], forward: [f64; 3], up: [f64; 3], fovy_deg: f64, aspect: f64, near: f64, far: f64 },
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSpot {
    position: [f64; 3],
    #[serde(default)]
    corners: Option<Vec<[f64; 3]>>,
    #[serde(default)]
    forward: Option<[f64; 3]>,
    #[serde(default)]
    up: Option<[f64; 3]>,
    #[serde(default)]
    fovy_deg: Option<f64>,
    #[serde(default)]
    aspect: Option<f64>,
    #[serde(default)]
    near: Option<f64>,
    #[serde(default)]
    far: Option<f64>,
}

#[derive(Deserialize)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
enum RawLight {
    Directional([f64; 3]),
    Point([f64; 3]),
    Spot(RawSpot),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawBox {
    min: [f64; 3],
    max: [f64; 3],
}

fn v3(a: [f64; 3]) -> DVec3 {
    DVec3::from_array(a)
}

fn corners8(c: &[[f64; 3]], what: &str) -> Result<[DVec3; 8], String> {
    if c.len() != 8 {
        return Err(format!("{what} needs exactly 8 corners, got {}", c.len()));
    }
    let mut out = [DVec3::ZERO; 8];
    for (o, p) in out.iter_mut().zip(c) {
        *o = v3(*p);
    }
    Ok(out)
}

fn make_camera(eye: [f64; 3], forward: [f64; 3], up: [f64; 3], fovy_deg: f64, aspect: f64, near: f64, far: f64) -> Camera {
    Camera { eye: v3(eye), forward: v3(forward), up: v3(up), fovy: fovy_deg.to_radians(), aspect, near, far }
}

fn geom(e: GeomError) -> String {
    e.to_string()
}

/// The lines of a JSON-lines input that hold a case (blank lines skipped).
pub fn case_lines(input: impl std::io::BufRead) -> impl Iterator<Item = std::io::Result<String>> {
    input.lines().filter(|line| line.as_ref().map_or(true, |l| !l.trim().is_empty()))
}

/// Parses and validates one line.
pub fn parse_case(line: &str) -> Result<Case, CaseError> {
    let value: Value = serde_json::from_str(line).map_err(|e| CaseError { id: Value::Null, message: format!("malformed JSON: {e}") })?;
    let id = value.get("id").cloned().unwrap_or(Value::Null);
    let fail = |message: String| CaseError { id: id.clone(), message };
    let raw: RawCase = serde_json::from_value(value).map_err(|e| fail(format!("invalid case: {e}")))?;
    let (view, camera) = match raw.view {
        RawFrustum::Corners { corners } => {
            (Frustum::from_corners(corners8(&corners, "view").map_err(&fail)?).map_err(|e| fail(geom(e)))?, None)
        }
        RawFrustum::Camera { eye, forward, up, fovy_deg, aspect, near, far } => {
            let cam = make_camera(eye, forward, up, fovy_deg, aspect, near, far);
            (Frustum::from_camera(&cam).map_err(|e| fail(geom(e)))?, Some(cam))
        }
    };
    let light = match raw.light {
        RawLight::Directional(d) => Light::directional(v3(d)),
        RawLight::Point(p) => Light::point(v3(p)),
        RawLight::Spot(s) => {
            let frustum = match (&s.corners, s.forward, s.up, s.fovy_deg, s.aspect, s.near, s.far) {
                (Some(c), None, None, None, None, None, None) => Frustum::from_corners(corners8(c, "spot light").map_err(&fail)?),
                (None, Some(f), Some(u), Some(fov), Some(a), Some(n), Some(fa)) => {
                    Frustum::from_camera(&make_camera(s.position, f, u, fov, a, n, fa))
                }
                _ => return Err(fail("spot light needs either \"corners\" or all of forward, up, fovy_deg, aspect, near, far".into())),
            }
            .map_err(|e| fail(geom(e)))?;
            Light::spot(v3(s.position), frustum)
        }
    }
    .map_err(|e| fail(geom(e)))?;
    let scene = Aabb::new(v3(raw.scene.min), v3(raw.scene.max)).map_err(|e| fail(geom(e)))?;
    Ok(Case { id, view, camera, light, scene })
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = r#"{"id":"a","view":{"eye":[0,0,0],"forward":[0,0,-1],"up":[0,1,0],"fovy_deg":60,"aspect":1,"near":1,"far":10},"light":{"directional":[0,-1,0]},"scene":{"min":[-5,-5,-12],"max":[5,5,0]}}"#;

    #[test]
    fn camera_form_parses() {
        let c = parse_case(GOOD).unwrap();
        assert_eq!(c.id, Value::from("a"));
        assert!(c.camera.is_some());
    }

    #[test]
    fn bad_lines_get_clear_errors_with_their_id() {
        let e = parse_case("{not json").unwrap_err();
        assert!(e.message.contains("malformed JSON"), "{}", e.message);
        assert_eq!(e.id, Value::Null);
        let e = parse_case(&GOOD.replace("\"near\":1", "\"near\":20")).unwrap_err();
        assert_eq!(e.id, Value::from("a"));
        assert!(e.message.contains("near"), "{}", e.message);
        let e = parse_case(&GOOD.replace("[0,-1,0]", "[0,0,0]")).unwrap_err();
        assert!(e.message.contains("zero length"), "{}", e.message);
        let e = parse_case(&GOOD.replace("\"min\":[-5,-5,-12]", "\"min\":[9,-5,-12]")).unwrap_err();
        assert!(e.message.contains("min > max"), "{}", e.message);
        let e = parse_case(&GOOD.replace("\"fovy_deg\":60", "\"fovy_deg\":1e999")).unwrap_err();
        assert!(!e.message.is_empty());
    }
}
