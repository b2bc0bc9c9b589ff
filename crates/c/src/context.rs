//! The context C holds: every buffer a call needs, allocated once.

use crate::convert;
use crate::error::Failure;
use crate::types::SfStatus;
use shadowfocus_focus::{
    cull_casters, fit_prepared, fit_prepared_with_state, CasterRegion, FitState, FocusResult, FocusSettings, PreparedView,
};
use shadowfocus_geom::{Aabb, Body, Camera, Focuser, Frustum, Light};
use std::ffi::c_char;

/// The inputs of the last successful fit, for the whole view's body.
#[derive(Clone, Copy, Debug)]
struct Fitted {
    camera: Camera,
    light: Light,
    scene: Aabb,
}

/// Owns the fit result, the prepared view, the body work space, the caster
/// scratch and the last error message. Opaque to C.
pub struct SfContext {
    result: FocusResult,
    view: Option<PreparedView>,
    fitted: Option<Fitted>,
    focuser: Focuser,
    body: Body,
    boxes: Vec<Aabb>,
    /// The last error message, NUL-terminated ("" after a success).
    error: Vec<u8>,
}

impl SfContext {
    /// A context with every buffer allocated.
    pub fn new() -> SfContext {
        SfContext {
            result: FocusResult::new(),
            view: None,
            fitted: None,
            focuser: Focuser::new(),
            body: Body::new(),
            boxes: Vec::new(),
            error: vec![0],
        }
    }

    /// The last error message as a C string, valid until the next call
    /// with this context.
    pub fn last_error(&self) -> *const c_char {
        self.error.as_ptr().cast()
    }

    /// The last error message, without its NUL.
    pub fn last_error_str(&self) -> &str {
        std::str::from_utf8(&self.error[..self.error.len() - 1]).unwrap_or("")
    }

    /// Records the outcome of a call: "" on success (no allocation), the
    /// message otherwise; returns the status code.
    pub fn finish(&mut self, outcome: Result<(), Failure>) -> SfStatus {
        self.error.clear();
        let status = match outcome {
            Ok(()) => SfStatus::SF_OK,
            Err(f) => {
                self.error.extend(f.message.bytes().map(|b| if b == 0 { b'?' } else { b }));
                f.status
            }
        };
        self.error.push(0);
        status
    }

    /// Forgets the last fit (when a fit fails or panics, its maps may be half written).
    pub fn forget_fit(&mut self) {
        self.fitted = None;
    }

    /// Checks `camera` and `settings` and prepares the view every
    /// following `fit_light` uses.
    pub fn prepare(&mut self, camera: &Camera, settings: &FocusSettings) -> Result<(), Failure> {
        self.fitted = None;
        match &mut self.view {
            Some(view) => view.prepare(camera, settings)?,
            None => self.view = Some(PreparedView::new(camera, settings)?),
        }
        Ok(())
    }

    /// Fits `light` over `scene` from the prepared view, carrying `state`
    /// from the previous frame when one is given.
    pub fn fit_light(&mut self, light: &Light, scene: &Aabb, state: Option<&mut FitState>) -> Result<(), Failure> {
        self.fitted = None;
        let view = self.view.as_ref().ok_or_else(|| Failure::invalid("no view prepared: call sf_prepare_view or sf_fit first"))?;
        match state {
            Some(state) => fit_prepared_with_state(view, light, scene, state, &mut self.result)?,
            None => fit_prepared(view, light, scene, &mut self.result)?,
        }
        self.fitted = Some(Fitted { camera: *view.camera(), light: *light, scene: *scene });
        Ok(())
    }

    /// The result of the last successful fit.
    pub fn result(&self) -> Result<&FocusResult, Failure> {
        match self.fitted {
            Some(_) => Ok(&self.result),
            None => Err(Failure::invalid("no successful fit in this context")),
        }
    }

    fn map(&self, index: usize) -> Result<&shadowfocus_focus::ShadowMap, Failure> {
        let maps = self.result()?.maps();
        maps.get(index).ok_or_else(|| Failure::invalid(format!("map_index {index} is out of range: the last fit has {} maps", maps.len())))
    }

    /// The body of map `index` of the last fit.
    pub fn map_body(&self, index: usize) -> Result<&Body, Failure> {
        Ok(self.map(index)?.body())
    }

    /// The caster region of map `index` of the last fit.
    pub fn caster_region(&self, index: usize) -> Result<CasterRegion, Failure> {
        Ok(CasterRegion::of_map(self.map(index)?))
    }

    /// The body of the whole view of the last fit (its camera as fitted,
    /// its light and scene), computed into the context's body.
    pub fn view_body(&mut self) -> Result<&Body, Failure> {
        let f = self.fitted.ok_or_else(|| Failure::invalid("no successful fit in this context"))?;
        let frustum = Frustum::from_camera(&f.camera).map_err(|e| Failure::geom(&e, "view"))?;
        self.focuser.focus_into(&mut self.body, &frustum, &f.light, &f.scene).map_err(|e| Failure::geom(&e, "view body"))?;
        Ok(&self.body)
    }

    /// Culls `boxes` against map `index`; writes the kept indices to `out`
    /// (at least `boxes.len()` long) and returns how many.
    pub fn cull(&mut self, index: usize, boxes: &[crate::types::SfAabb], out: &mut [u32]) -> Result<usize, Failure> {
        self.map(index)?;
        self.boxes.clear();
        self.boxes.reserve(boxes.len());
        for (i, b) in boxes.iter().enumerate() {
            self.boxes.push(convert::aabb(b).map_err(|e| Failure::geom(&e, &format!("boxes[{i}]")))?);
        }
        let map = &self.result.maps()[index];
        Ok(cull_casters(map, &self.boxes, out)?)
    }
}

impl Default for SfContext {
    fn default() -> Self {
        SfContext::new()
    }
}
