//! Camera paths: the scene's own camera moved over `t ∈ [0, 1]`.

use glam::DVec3;
use shadowfocus_render::{CameraSpec, Scene};

/// A camera path through a static scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CameraPath {
    /// 30° around the vertical axis through the point the camera looks at.
    Orbit,
    /// Forward along the view direction, a fifth of the distance to that point.
    Walk,
    /// 30° of yaw in place.
    Turn,
    /// The field of view narrowed to 60 % of the scene's.
    Zoom,
}

impl CameraPath {
    pub fn name(self) -> &'static str {
        match self {
            CameraPath::Orbit => "orbit",
            CameraPath::Walk => "walk",
            CameraPath::Turn => "turn",
            CameraPath::Zoom => "zoom",
        }
    }
}

pub fn parse_path(s: &str) -> Result<CameraPath, String> {
    [CameraPath::Orbit, CameraPath::Walk, CameraPath::Turn, CameraPath::Zoom]
        .into_iter()
        .find(|p| p.name() == s)
        .ok_or_else(|| format!("unknown camera path {s:?}: expected orbit, walk, turn or zoom"))
}

/// The point the scene's camera looks at: where its view axis meets the
/// plane of the scene bounds' lowest point (along the camera's up), else a
/// tenth of the way to far.
fn look_point(scene: &Scene, c: &CameraSpec) -> DVec3 {
    let (f, up) = (c.forward.normalize(), c.up.normalize());
    let height = c.eye.dot(up) - scene.bounds.min.dot(up);
    let down = -f.dot(up);
    // NOTE: a view axis within 0.06° of the horizon meets the ground
    // beyond any sensible orbit centre; those cameras orbit a point ahead.
    let t = if down > 1e-3 { (height / down).min(c.far) } else { 0.1 * c.far };
    c.eye + f * t.max(c.near)
}

/// The camera of frame `k` of `frames` along `path`.
pub fn path_camera(scene: &Scene, path: CameraPath, k: usize, frames: usize) -> CameraSpec {
    let c = scene.camera;
    let t = k as f64 / (frames.max(2) - 1) as f64;
    let up = c.up.normalize();
    let turn = |v: DVec3, angle: f64| glam::DQuat::from_axis_angle(up, angle) * v;
    let angle = 30f64.to_radians() * t;
    match path {
        CameraPath::Orbit => {
            let p = look_point(scene, &c);
            CameraSpec { eye: p + turn(c.eye - p, angle), forward: turn(c.forward, angle), ..c }
        }
        CameraPath::Walk => {
            let d = (look_point(scene, &c) - c.eye).length() * 0.2;
            CameraSpec { eye: c.eye + c.forward.normalize() * (d * t), ..c }
        }
        CameraPath::Turn => CameraSpec { forward: turn(c.forward, angle), ..c },
        CameraPath::Zoom => CameraSpec { fovy: c.fovy * (1.0 - 0.4 * t), ..c },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_start_at_the_scene_camera_and_move() {
        let scene = shadowfocus_render::builtin_scene("chessboard").unwrap();
        for path in [CameraPath::Orbit, CameraPath::Walk, CameraPath::Turn, CameraPath::Zoom] {
            assert_eq!(parse_path(path.name()), Ok(path));
            assert_eq!(path_camera(&scene, path, 0, 10), scene.camera, "{path:?}");
            let last = path_camera(&scene, path, 9, 10);
            assert_ne!(last, scene.camera, "{path:?} does not move");
            last.validate().unwrap();
        }
        assert!(parse_path("spin").unwrap_err().contains("orbit, walk, turn or zoom"));
    }
}
