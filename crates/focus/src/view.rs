//! The camera's side of a frame: the checked settings, the split depths
//! and each split's validated frustum, prepared once per view.

use crate::error::FocusError;
use crate::settings::{DepthHintCoverage, FocusSettings, Method, SplitScheme, SplitSettings};
use crate::splits::split_depths;
use crate::MAX_SPLITS;
use glam::DVec3;
use shadowfocus_geom::{Camera, CameraBasis, Frustum};

/// The camera's side of a frame, prepared once and shared by every light
/// fitted for that camera: the checked settings, the camera basis, the split
/// depths and each split's validated frustum.
///
/// NOTE: a frustum's exact validation is about a fifth of a one-map fit.
/// An engine with several shadowed lights, or a camera that did not move
/// since the last frame, pays it once per view instead of once per light.
/// The frusta are held inline (about 7 KiB): keep one view and refill it
/// with [`PreparedView::prepare`] rather than building a new one per frame.
#[derive(Clone, Debug)]
pub struct PreparedView {
    pub(crate) settings: FocusSettings,
    /// The camera with the visible range the fit uses (see `PsmSettings`).
    pub(crate) camera: Camera,
    /// The camera as given, over its whole depth range (for a view given
    /// as a frustum, the camera given with it).
    pub(crate) whole: Camera,
    pub(crate) basis: CameraBasis,
    /// The split planes as fitted: placed over the camera's (hinted) range,
    /// the outer two moved to the whole view's ends with
    /// [`DepthHintCoverage::View`].
    pub(crate) depths: [f64; MAX_SPLITS + 1],
    pub(crate) splits: usize,
    /// `None` for a split that `delta_bias` left without depth.
    pub(crate) frusta: [Option<Frustum>; MAX_SPLITS],
    /// The frustum given to [`PreparedView::prepare_frustum`], for splits
    /// cut anew ([`PreparedView::split_frustum`]).
    given: Option<Frustum>,
    /// Why the last preparation failed: every fit from the view gives it.
    pub(crate) failed: Option<FocusError>,
}

impl PreparedView {
    /// A view of `camera` with `settings` (see [`PreparedView::prepare`]).
    pub fn new(camera: &Camera, settings: &FocusSettings) -> Result<PreparedView, FocusError> {
        let mut view = PreparedView::unprepared(camera, settings);
        view.prepare(camera, settings)?;
        Ok(view)
    }

    /// A view holding no preparation yet, to be filled by `prepare` or
    /// `prepare_frustum`.
    pub(crate) fn unprepared(camera: &Camera, settings: &FocusSettings) -> PreparedView {
        let placeholder = CameraBasis { forward: DVec3::NEG_Z, right: DVec3::X, up: DVec3::Y };
        PreparedView {
            settings: *settings,
            camera: *camera,
            whole: *camera,
            basis: placeholder,
            depths: [0.0; MAX_SPLITS + 1],
            splits: 0,
            frusta: [None; MAX_SPLITS],
            given: None,
            failed: None,
        }
    }

    /// Keeps the outcome of a preparation: after an error the view holds
    /// none, and every fit from it gives that error.
    fn keep(&mut self, prepared: Result<(), FocusError>) -> Result<(), FocusError> {
        self.failed = prepared.as_ref().err().cloned();
        if self.failed.is_some() {
            self.splits = 0;
        }
        prepared
    }

    /// Checks `camera` and `settings` and validates every split's frustum,
    /// in place (no allocation); the errors are those [`fit`](crate::fit()) gives for the
    /// same camera and settings. After an error the view holds no
    /// preparation, and [`fit_prepared`](crate::fit_prepared) gives that error again.
    pub fn prepare(&mut self, camera: &Camera, settings: &FocusSettings) -> Result<(), FocusError> {
        let prepared = self.fill(camera, settings, None);
        self.keep(prepared)
    }

    /// [`PreparedView::prepare`] for a view given as a frustum (its eight
    /// corners) rather than a camera: every body is computed from `view`
    /// itself, and `camera` — for corners, the one
    /// [`crate::camera_from_corners`] recovers — only chooses the
    /// parameterisation and the split depths. With one split (and no PSM
    /// range tightening) the split's frustum is `view`, exactly; otherwise
    /// split `i` is the part of `view` between its depths, cut along `view`'s
    /// own side edges and rounded outward (see [`slice`]), so that every
    /// point of `view` lies in some split's frustum.
    pub fn prepare_frustum(&mut self, view: &Frustum, camera: &Camera, settings: &FocusSettings) -> Result<(), FocusError> {
        let prepared = self.fill(camera, settings, Some(view));
        self.keep(prepared)
    }

    /// Checks the camera and settings and builds every split's frustum:
    /// from the camera, or cut from `given` (see `prepare_frustum`).
    fn fill(&mut self, camera: &Camera, settings: &FocusSettings, given: Option<&Frustum>) -> Result<(), FocusError> {
        settings.validate()?;
        self.basis = camera.basis()?;
        self.camera = visible_range(camera, settings)?;
        self.whole = *camera;
        self.settings = *settings;
        self.given = given.copied();
        self.splits = split_depths(self.camera.near, self.camera.far, &settings.splits, &mut self.depths);
        if settings.visible_depth.is_some() {
            if settings.splits.scheme == SplitScheme::Optimal && self.splits > 1 {
                self.depths[1] = self.depths[1].min(log_first_plane(&self.camera, settings));
            }
            if settings.visible_depth_coverage == DepthHintCoverage::View {
                let whole = visible_range(camera, &FocusSettings { visible_depth: None, ..*settings })?;
                (self.depths[0], self.depths[self.splits]) = (whole.near, whole.far);
            }
        }
        for i in 0..self.splits {
            self.frusta[i] = self.split_frustum([self.depths[i], self.depths[i + 1]])?;
        }
        Ok(())
    }

    /// The planes the placement starts from and moves: the fitted ones with
    /// the outer two at the camera's (hinted) near and far.
    pub(crate) fn placement_start(&self) -> [f64; MAX_SPLITS + 1] {
        let mut planes = self.depths;
        (planes[0], planes[self.splits]) = (self.camera.near, self.camera.far);
        planes
    }

    /// Placed planes as fitted: the outer two moved to the view's fitted
    /// ends (the identity without [`DepthHintCoverage::View`]).
    pub(crate) fn covered(&self, planes: &[f64; MAX_SPLITS + 1]) -> [f64; MAX_SPLITS + 1] {
        let mut fitted = *planes;
        (fitted[0], fitted[self.splits]) = (self.depths[0], self.depths[self.splits]);
        fitted
    }

    /// Split `i`'s frustum for the view-depth range `range`: the prepared
    /// one where `range` is the view's own, else cut anew into `cut`
    /// (optimal placement moves the planes per light); `None` for an empty
    /// range.
    pub(crate) fn frustum_in<'a>(
        &'a self,
        i: usize,
        range: [f64; 2],
        cut: &'a mut Option<Frustum>,
    ) -> Result<Option<&'a Frustum>, FocusError> {
        if range == self.split_range(i) {
            return Ok(self.frustum(i));
        }
        *cut = self.split_frustum(range)?;
        Ok(cut.as_ref())
    }

    /// The frustum of the view-depth range `range` (`None` for an empty
    /// range): from the camera, or cut from the given frustum.
    pub(crate) fn split_frustum(&self, range: [f64; 2]) -> Result<Option<Frustum>, FocusError> {
        if !(range[0] < range[1]) {
            return Ok(None);
        }
        Ok(Some(match &self.given {
            Some(view) => slice(view, &self.camera, &self.basis, range, &self.whole)?,
            None => Frustum::from_camera_in(&Camera { near: range[0], far: range[1], ..self.camera }, &self.basis)?,
        }))
    }

    /// The settings the view was prepared with.
    pub fn settings(&self) -> &FocusSettings {
        &self.settings
    }

    /// The camera as fitted: the given one, with PSM's tightened near and
    /// far applied.
    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    /// Split boundaries as view depths, one more than there are splits
    /// (none after a failed preparation). With
    /// [`crate::SplitScheme::Optimal`] these are where the placement starts;
    /// each light's own are [`crate::FocusResult::split_depths`].
    pub fn split_depths(&self) -> &[f64] {
        if self.failed.is_some() {
            return &[];
        }
        &self.depths[..=self.splits]
    }

    /// Split `i`'s view frustum (`None` for a split without depth).
    pub(crate) fn frustum(&self, i: usize) -> Option<&Frustum> {
        self.frusta.get(i).and_then(Option::as_ref)
    }

    /// Split `i`'s view-depth range.
    pub(crate) fn split_range(&self, i: usize) -> [f64; 2] {
        [self.depths[i], self.depths[i + 1]]
    }

    /// The camera's unit view direction.
    pub(crate) fn forward(&self) -> DVec3 {
        self.basis.forward
    }
}

/// The first logarithmic plane of the splits over `camera`'s (visible)
/// depth range: where optimal placement over that range starts its first
/// plane at the latest.
///
/// The placement never moves the first plane beyond its start, because the
/// prediction can miss the nearest receivers (a terrain above the scene
/// box's floor, see `placement.rs`). Without a range the start is the
/// practical plane. A range says that something is seen at its near end;
/// the practical plane over it moves out with that end (the forest: 14.4 m
/// for visible depths 4.3–68, against 9.0 m over the whole view), while the
/// logarithmic plane, which spreads texels as the logarithmic bound asks
/// from that end on, stays at 8.5 m.
fn log_first_plane(camera: &Camera, settings: &FocusSettings) -> f64 {
    let mut log = [0.0; MAX_SPLITS + 1];
    split_depths(camera.near, camera.far, &SplitSettings { scheme: SplitScheme::Log, delta_bias: 0.0, ..settings.splits }, &mut log);
    log[1]
}

/// Relative outward margin of a split cut from a given frustum (2⁻²⁰): far
/// above the rounding of the interpolated corners (a few ulps of their
/// magnitudes) and of the creases of the given side faces.
const SLICE_MARGIN: f64 = 1.0 / (1u64 << 20) as f64;

/// The part of `view` between the view depths `range` of `camera` (the
/// fitted camera; `given` is the camera before PSM's tightening, whose near
/// and far are `view`'s own faces).
///
/// Each side edge `c_k → c_{k+4}` is cut at the parameters `t` where its
/// depth along the camera's forward axis is `range[0]` and `range[1]`:
/// `t = (z − d_k)/(d_{k+4} − d_k)`, `d` the corners' depths. A depth at or
/// beyond `given`'s near or far keeps that face's corners exactly; with
/// both, the slice is `view` itself. Where a cut is interior, the
/// parameters are widened by `SLICE_MARGIN` on both sides and the eight
/// corners are moved away from their centroid by a factor `1 + SLICE_MARGIN`
/// — a homothety, so the result contains the exact slice whatever the
/// rounding of the interpolated corners and whichever diagonal the given
/// side faces were creased along.
fn slice(view: &Frustum, camera: &Camera, basis: &CameraBasis, range: [f64; 2], given: &Camera) -> Result<Frustum, FocusError> {
    let keep_near = range[0] <= given.near;
    let keep_far = range[1] >= given.far;
    if keep_near && keep_far {
        return Ok(*view);
    }
    let c = view.corners();
    let depth = |p: DVec3| basis.forward.dot(p - camera.eye);
    let mut out = [DVec3::ZERO; 8];
    for k in 0..4 {
        let (a, b) = (c[k], c[k + 4]);
        let (da, db) = (depth(a), depth(b));
        let at = |z: f64, bias: f64| {
            let t = if db > da { (z - da) / (db - da) + bias } else { 0.5 };
            let t = t.clamp(0.0, 1.0);
            a + (b - a) * t
        };
        out[k] = if keep_near { a } else { at(range[0], -SLICE_MARGIN) };
        out[k + 4] = if keep_far { b } else { at(range[1], SLICE_MARGIN) };
    }
    let centroid = out.iter().copied().sum::<DVec3>() / 8.0;
    for p in &mut out {
        *p = centroid + (*p - centroid) * (1.0 + SLICE_MARGIN);
    }
    Ok(Frustum::from_corners(out)?)
}

/// The camera whose depth range is fitted: narrowed to the visible depth
/// range where the engine gives one ([`FocusSettings::visible_depth`]),
/// and for PSM to its own tightened range (see `PsmSettings`).
fn visible_range(camera: &Camera, settings: &FocusSettings) -> Result<Camera, FocusError> {
    let mut cam = *camera;
    if let Some([lo, hi]) = settings.visible_depth {
        cam.near = cam.near.max(lo);
        cam.far = cam.far.min(hi);
        if !(cam.near < cam.far) {
            return Err(FocusError::InvalidSettings { what: "visible_depth", reason: "leaves no depth range inside the camera's" });
        }
    }
    if settings.method == Method::Psm {
        cam.near = cam.near.max(settings.psm.near.unwrap_or(cam.near));
        cam.far = cam.far.min(settings.psm.far.unwrap_or(cam.far));
        if !(cam.near < cam.far) {
            return Err(FocusError::InvalidSettings { what: "psm.near/psm.far", reason: "leave no depth range inside the camera's" });
        }
    }
    Ok(cam)
}
