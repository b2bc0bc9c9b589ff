//! Where a world point lands in a frame, and whether the frame sees it.

use glam::{DMat4, DVec3, DVec4};
use shadowfocus_render::RenderOutput;

/// A frame's camera as a projection to pixels.
pub struct Screen {
    clip_from_world: DMat4,
    eye: DVec3,
    /// World distance per unit distance from the eye that `sees` accepts
    /// between a point and what its pixel shows: three pixels' footprint.
    reach: f64,
    width: u32,
    height: u32,
}

impl Screen {
    pub fn new(out: &RenderOutput) -> Result<Screen, String> {
        let c = &out.camera;
        let aspect = out.width as f64 / out.height as f64;
        let clip_from_world = c.projection_matrix(aspect) * c.view_matrix().map_err(|e| e.to_string())?;
        let reach = 6.0 * (0.5 * c.fovy).tan() / out.height as f64;
        Ok(Screen { clip_from_world, eye: c.eye, reach, width: out.width, height: out.height })
    }

    /// `p`'s position in pixels (x right, y down; pixel centres at +0.5), if
    /// it lies in front of the camera and inside the image.
    pub fn project(&self, p: DVec3) -> Option<(f64, f64)> {
        let q = self.clip_from_world * DVec4::new(p.x, p.y, p.z, 1.0);
        if !(q.w > 0.0) {
            return None;
        }
        let (x, y) = ((0.5 + 0.5 * q.x / q.w) * self.width as f64, (0.5 - 0.5 * q.y / q.w) * self.height as f64);
        (x >= 0.0 && y >= 0.0 && x < self.width as f64 && y < self.height as f64).then_some((x, y))
    }

    /// The pixel `p` projects to, if that pixel shows geometry within
    /// `reach` of `p` (so `p` is not hidden behind something else).
    pub fn sees(&self, out: &RenderOutput, p: DVec3) -> Option<usize> {
        let (x, y) = self.project(p)?;
        let i = y as usize * self.width as usize + x as usize;
        let w = out.world[i];
        let shown = DVec3::new(w[0] as f64, w[1] as f64, w[2] as f64);
        (w[3] != 0.0 && (shown - p).length() <= (p - self.eye).length() * self.reach).then_some(i)
    }
}
