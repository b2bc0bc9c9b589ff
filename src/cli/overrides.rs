//! `--light` and `--camera`: a frame's light and camera given on the command
//! line, for built-in and glTF scenes alike.
//!
//! ```text
//! --light directional:DX,DY,DZ | point:X,Y,Z | spot:X,Y,Z,FX,FY,FZ,FOVY_DEG
//! --camera EX,EY,EZ,FX,FY,FZ[,FOVY_DEG,NEAR,FAR]
//! ```
//!
//! A directional light's vector is its travel direction (light → scene); a
//! spot light's is its axis. Whatever the command line leaves out comes from
//! the scene: a camera without field of view and depth range keeps the
//! scene's, and its up vector is the scene camera's (or +y, or −z, the first
//! one not parallel to the new forward direction); a spot light's lit depth
//! range reaches from a thousandth of to just past the farthest corner of the
//! scene's box.

use glam::DVec3;
use shadowfocus_render::{Bounds, CameraSpec, LightSpec, Scene};
use std::fmt;

/// What is wrong with a `--light` or `--camera` value.
#[derive(Clone, Debug, PartialEq)]
pub enum OverrideError {
    /// `--light` names no known kind (or has no `KIND:`).
    UnknownLightKind { given: String },
    /// Wrong number of comma-separated numbers.
    WrongCount { what: &'static str, expected: &'static str, got: usize },
    /// A field that does not parse as a number.
    NotANumber { what: &'static str, index: usize, text: String },
    /// NaN or infinity.
    NonFinite { what: &'static str, index: usize, value: f64 },
    /// A direction (light, spot axis, camera forward) of length zero.
    ZeroDirection { what: &'static str },
    /// A field of view outside (0°, 180°).
    FieldOfView { what: &'static str, degrees: f64 },
    /// Not 0 < near < far.
    DepthRange { near: f64, far: f64 },
}

impl fmt::Display for OverrideError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            OverrideError::UnknownLightKind { given } => {
                write!(f, "unknown light {given:?}: expected directional:DX,DY,DZ, point:X,Y,Z or spot:X,Y,Z,FX,FY,FZ,FOVY_DEG")
            }
            OverrideError::WrongCount { what, expected, got } => write!(f, "{what} takes {expected} numbers, got {got}"),
            OverrideError::NotANumber { what, index, text } => write!(f, "{what}: value {} ({text:?}) is not a number", index + 1),
            OverrideError::NonFinite { what, index, value } => write!(f, "{what}: value {} is {value}, not a finite number", index + 1),
            OverrideError::ZeroDirection { what } => write!(f, "{what} is the zero vector"),
            OverrideError::FieldOfView { what, degrees } => write!(f, "{what}: field of view {degrees}° is not within (0°, 180°)"),
            OverrideError::DepthRange { near, far } => write!(f, "camera: need 0 < near < far, got near {near} far {far}"),
        }
    }
}

impl std::error::Error for OverrideError {}

/// Comma-separated finite numbers, `counts` of them (one of).
fn numbers(what: &'static str, text: &str, counts: &[usize], expected: &'static str) -> Result<Vec<f64>, OverrideError> {
    let fields: Vec<&str> = if text.trim().is_empty() { Vec::new() } else { text.split(',').collect() };
    if !counts.contains(&fields.len()) {
        return Err(OverrideError::WrongCount { what, expected, got: fields.len() });
    }
    let mut v = Vec::with_capacity(fields.len());
    for (index, field) in fields.iter().enumerate() {
        let x: f64 = field.trim().parse().map_err(|_| OverrideError::NotANumber { what, index, text: field.trim().to_string() })?;
        if !x.is_finite() {
            return Err(OverrideError::NonFinite { what, index, value: x });
        }
        v.push(x);
    }
    Ok(v)
}

fn vec3(v: &[f64]) -> DVec3 {
    DVec3::new(v[0], v[1], v[2])
}

fn direction(what: &'static str, v: &[f64]) -> Result<DVec3, OverrideError> {
    let d = vec3(v);
    // Scaled by its largest component first, so that huge and tiny vectors
    // that are not zero pass (and normalise) too.
    let m = d.abs().max_element();
    if m == 0.0 {
        return Err(OverrideError::ZeroDirection { what });
    }
    Ok(d / m)
}

fn field_of_view(what: &'static str, degrees: f64) -> Result<f64, OverrideError> {
    if degrees > 0.0 && degrees < 180.0 {
        Ok(degrees.to_radians())
    } else {
        Err(OverrideError::FieldOfView { what, degrees })
    }
}

/// A `--light` value; a spot light's depth range is set from the scene
/// ([`LightOverride::resolve`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightOverride {
    Directional { direction: DVec3 },
    Point { position: DVec3 },
    Spot { position: DVec3, direction: DVec3, fovy: f64 },
}

/// Parses `directional:DX,DY,DZ`, `point:X,Y,Z` or `spot:X,Y,Z,FX,FY,FZ,FOVY_DEG`.
pub fn parse_light(s: &str) -> Result<LightOverride, OverrideError> {
    let unknown = || OverrideError::UnknownLightKind { given: s.to_string() };
    let (kind, rest) = s.split_once(':').ok_or_else(unknown)?;
    match kind.trim().to_ascii_lowercase().as_str() {
        "directional" => {
            let v = numbers("directional light", rest, &[3], "3 (DX,DY,DZ)")?;
            Ok(LightOverride::Directional { direction: direction("directional light direction", &v)? })
        }
        "point" => {
            let v = numbers("point light", rest, &[3], "3 (X,Y,Z)")?;
            Ok(LightOverride::Point { position: vec3(&v) })
        }
        "spot" => {
            let v = numbers("spot light", rest, &[7], "7 (X,Y,Z,FX,FY,FZ,FOVY_DEG)")?;
            Ok(LightOverride::Spot {
                position: vec3(&v),
                direction: direction("spot light direction", &v[3..6])?,
                fovy: field_of_view("spot light", v[6])?,
            })
        }
        _ => Err(unknown()),
    }
}

/// The first of `candidates` not parallel to `forward`.
fn up_for(forward: DVec3, candidates: &[DVec3]) -> DVec3 {
    let f = forward.normalize();
    candidates.iter().copied().find(|u| u.length() > 0.0 && f.cross(u.normalize()).length() > 1e-6).unwrap_or(DVec3::X)
}

impl LightOverride {
    /// The renderer's light, in a scene with box `bounds`.
    pub fn resolve(&self, bounds: &Bounds) -> LightSpec {
        match *self {
            LightOverride::Directional { direction } => LightSpec::Directional { direction },
            LightOverride::Point { position } => LightSpec::Point { position },
            LightOverride::Spot { position, direction, fovy } => {
                let reach = bounds.corners().iter().map(|c| c.distance(position)).fold(0.0, f64::max);
                let far = (reach * 1.01).max(1e-3);
                LightSpec::Spot { position, direction, up: up_for(direction, &[DVec3::Y, DVec3::NEG_Z]), fovy, near: far * 1e-3, far }
            }
        }
    }
}

/// A `--camera` value: eye and forward, with or without field of view and
/// depth range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraOverride {
    pub eye: DVec3,
    pub forward: DVec3,
    /// Vertical field of view (radians), near, far.
    pub lens: Option<(f64, f64, f64)>,
}

/// Parses `EX,EY,EZ,FX,FY,FZ` or `EX,EY,EZ,FX,FY,FZ,FOVY_DEG,NEAR,FAR`.
pub fn parse_camera(s: &str) -> Result<CameraOverride, OverrideError> {
    let v = numbers("camera", s, &[6, 9], "6 (EX,EY,EZ,FX,FY,FZ) or 9 (…,FOVY_DEG,NEAR,FAR)")?;
    let forward = direction("camera forward direction", &v[3..6])?;
    let lens = if v.len() == 9 {
        let fovy = field_of_view("camera", v[6])?;
        let (near, far) = (v[7], v[8]);
        if !(near > 0.0 && near < far) {
            return Err(OverrideError::DepthRange { near, far });
        }
        Some((fovy, near, far))
    } else {
        None
    };
    Ok(CameraOverride { eye: vec3(&v), forward, lens })
}

impl CameraOverride {
    /// The renderer's camera, replacing `base` (the scene's).
    pub fn resolve(&self, base: &CameraSpec) -> CameraSpec {
        let (fovy, near, far) = self.lens.unwrap_or((base.fovy, base.near, base.far));
        CameraSpec { eye: self.eye, forward: self.forward, up: up_for(self.forward, &[base.up, DVec3::Y, DVec3::NEG_Z]), fovy, near, far }
    }
}

/// `--light` and `--camera` as `render`, `demo` and `sweep` take them.
#[derive(Clone, Debug, Default, clap::Args)]
pub struct Overrides {
    /// Replace the scene's light: directional:DX,DY,DZ (travel direction) |
    /// point:X,Y,Z | spot:X,Y,Z,FX,FY,FZ,FOVY_DEG.
    #[arg(long, value_parser = parse_light, allow_hyphen_values = true)]
    pub light: Option<LightOverride>,
    /// Replace the scene's camera: EX,EY,EZ,FX,FY,FZ[,FOVY_DEG,NEAR,FAR]
    /// (without the last three, the scene's field of view and depth range).
    #[arg(long, value_parser = parse_camera, allow_hyphen_values = true)]
    pub camera: Option<CameraOverride>,
}

/// The camera and light of one frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    pub camera: CameraSpec,
    pub light: LightSpec,
}

impl Frame {
    /// The scene's own camera and light.
    pub fn of(scene: &Scene) -> Frame {
        Frame { camera: scene.camera, light: scene.light }
    }

    /// The scene's camera and light with the overrides applied, validated.
    pub fn with(scene: &Scene, o: &Overrides) -> Result<Frame, String> {
        let frame = Frame {
            camera: o.camera.map_or(scene.camera, |c| c.resolve(&scene.camera)),
            light: o.light.map_or(scene.light, |l| l.resolve(&scene.bounds)),
        };
        frame.camera.validate().map_err(|e| e.to_string())?;
        frame.light.validate().map_err(|e| e.to_string())?;
        Ok(frame)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lights_parse() {
        assert_eq!(parse_light("directional:0,-2,0"), Ok(LightOverride::Directional { direction: DVec3::new(0.0, -1.0, 0.0) }));
        assert_eq!(parse_light("point: 1, 2.5 ,-3"), Ok(LightOverride::Point { position: DVec3::new(1.0, 2.5, -3.0) }));
        let Ok(LightOverride::Spot { position, direction, fovy }) = parse_light("Spot:0,10,0,0,-1,0,90") else { panic!() };
        assert_eq!((position, direction), (DVec3::new(0.0, 10.0, 0.0), DVec3::NEG_Y));
        assert!((fovy - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        // Huge and tiny directions are not zero.
        assert!(parse_light("directional:1e300,-1e300,0").is_ok());
        assert!(parse_light("directional:0,-1e-310,0").is_ok());
    }

    #[test]
    fn malformed_lights_get_typed_errors() {
        let e = |s: &str| parse_light(s).unwrap_err();
        assert!(matches!(e("sun:0,-1,0"), OverrideError::UnknownLightKind { .. }));
        assert!(matches!(e("0,-1,0"), OverrideError::UnknownLightKind { .. }));
        assert_eq!(e("directional:0,-1"), OverrideError::WrongCount { what: "directional light", expected: "3 (DX,DY,DZ)", got: 2 });
        assert!(matches!(e("directional:"), OverrideError::WrongCount { got: 0, .. }));
        assert!(matches!(e("point:1,2,3,4"), OverrideError::WrongCount { got: 4, .. }));
        assert!(matches!(e("spot:0,1,0,0,-1,0"), OverrideError::WrongCount { got: 6, .. }));
        assert!(matches!(e("point:1,x,3"), OverrideError::NotANumber { index: 1, .. }));
        assert!(matches!(e("point:1,,3"), OverrideError::NotANumber { index: 1, .. }));
        assert!(matches!(e("directional:NaN,-1,0"), OverrideError::NonFinite { index: 0, .. }));
        assert!(matches!(e("point:0,inf,0"), OverrideError::NonFinite { index: 1, .. }));
        assert_eq!(e("directional:0,0,0"), OverrideError::ZeroDirection { what: "directional light direction" });
        assert_eq!(e("spot:0,1,0,0,0,-0,45"), OverrideError::ZeroDirection { what: "spot light direction" });
        assert!(matches!(e("spot:0,1,0,0,-1,0,180"), OverrideError::FieldOfView { .. }));
        assert!(matches!(e("spot:0,1,0,0,-1,0,0"), OverrideError::FieldOfView { .. }));
        // The messages say what is wrong.
        assert_eq!(e("point:1,2").to_string(), "point light takes 3 (X,Y,Z) numbers, got 2");
        assert_eq!(e("directional:0,0,0").to_string(), "directional light direction is the zero vector");
        assert!(e("lamp:1").to_string().contains("expected directional:DX,DY,DZ, point:X,Y,Z or spot:"));
    }

    #[test]
    fn cameras_parse_and_reject_bad_values() {
        let c = parse_camera("0,2,10,0,0,-1").unwrap();
        assert_eq!((c.eye, c.forward, c.lens), (DVec3::new(0.0, 2.0, 10.0), DVec3::NEG_Z, None));
        let c = parse_camera("0,2,10,0,0,-1,60,0.1,100").unwrap();
        let (fovy, near, far) = c.lens.unwrap();
        assert!((fovy - 60f64.to_radians()).abs() < 1e-15 && near == 0.1 && far == 100.0);
        let e = |s: &str| parse_camera(s).unwrap_err();
        assert!(matches!(e("0,2,10,0,0"), OverrideError::WrongCount { got: 5, .. }));
        assert!(matches!(e("0,2,10,0,0,-1,60"), OverrideError::WrongCount { got: 7, .. }));
        assert!(matches!(e("0,2,10,0,0,-1,60,1,2,3"), OverrideError::WrongCount { got: 10, .. }));
        assert!(matches!(e("0,2,nan,0,0,-1"), OverrideError::NonFinite { index: 2, .. }));
        assert!(matches!(e("0,2,10,0,0,-1,60,0.1,1e999"), OverrideError::NonFinite { index: 8, .. }));
        assert_eq!(e("0,2,10,0,0,0"), OverrideError::ZeroDirection { what: "camera forward direction" });
        assert_eq!(e("0,2,10,0,0,-1,60,5,5"), OverrideError::DepthRange { near: 5.0, far: 5.0 });
        assert_eq!(e("0,2,10,0,0,-1,60,10,5"), OverrideError::DepthRange { near: 10.0, far: 5.0 });
        assert_eq!(e("0,2,10,0,0,-1,60,0,5"), OverrideError::DepthRange { near: 0.0, far: 5.0 });
        assert!(matches!(e("0,2,10,0,0,-1,200,0.1,5"), OverrideError::FieldOfView { .. }));
        assert_eq!(e("0,2,10,0,0,-1,60,5,5").to_string(), "camera: need 0 < near < far, got near 5 far 5");
    }

    #[test]
    fn overrides_replace_the_scenes_camera_and_light() {
        let scene = shadowfocus_render::builtin_scene("duelling-frusta").unwrap();
        assert_eq!(Frame::with(&scene, &Overrides::default()).unwrap(), Frame::of(&scene));
        let o = Overrides { light: Some(parse_light("point:0,30,0").unwrap()), camera: Some(parse_camera("0,20,0,0,-1,0").unwrap()) };
        let f = Frame::with(&scene, &o).unwrap();
        assert_eq!(f.light, LightSpec::Point { position: DVec3::new(0.0, 30.0, 0.0) });
        assert_eq!((f.camera.eye, f.camera.forward), (DVec3::new(0.0, 20.0, 0.0), DVec3::NEG_Y));
        assert_eq!((f.camera.fovy, f.camera.near, f.camera.far), (scene.camera.fovy, scene.camera.near, scene.camera.far));
        assert!(f.camera.forward.cross(f.camera.up).length() > 0.5, "an up vector not parallel to a camera looking straight down");
        // A spot light reaches every corner of the scene's box.
        let o = Overrides { light: Some(parse_light("spot:0,40,0,0,-1,0,100").unwrap()), camera: None };
        let f = Frame::with(&scene, &o).unwrap();
        let LightSpec::Spot { near, far, .. } = f.light else { panic!() };
        let reach = scene.bounds.corners().iter().map(|c| c.distance(DVec3::new(0.0, 40.0, 0.0))).fold(0.0, f64::max);
        assert!(far > reach && near > 0.0 && near < far);
    }
}
