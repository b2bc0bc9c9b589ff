//! The focus body `H = hull(V ∪ {l}) ∩ S ∩ L` and its rounded output form.

use crate::input::aabb::Aabb;
use crate::input::frustum::Frustum;
use crate::input::light::Light;
use crate::limits::{MAX_FACES, MAX_FACE_INDICES, MAX_VERTICES};
use glam::{DVec3, DVec4};

/// Dimension of a focus body.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Dimension {
    /// No point.
    Empty,
    /// A single point.
    Point,
    /// A segment.
    Segment,
    /// A convex polygon.
    Polygon,
    /// A convex polytope with volume.
    Solid,
}

impl Dimension {
    /// −1 for empty, else the affine dimension.
    pub fn as_i32(self) -> i32 {
        match self {
            Dimension::Empty => -1,
            Dimension::Point => 0,
            Dimension::Segment => 1,
            Dimension::Polygon => 2,
            Dimension::Solid => 3,
        }
    }

    fn from_i8(d: i8) -> Dimension {
        match d {
            0 => Dimension::Point,
            1 => Dimension::Segment,
            2 => Dimension::Polygon,
            3 => Dimension::Solid,
            _ => Dimension::Empty,
        }
    }
}

/// What a focus-body computation did and skipped.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FocusStats {
    /// `S` was not clipped because `hull(V ∪ {l}) ⊆ S` (V and l inside S).
    pub scene_clip_skipped: bool,
    /// `L` was not clipped (no spot light).
    pub light_clip_skipped: bool,
    /// Halfspaces offered to the clipper.
    pub planes_offered: u16,
    /// Halfspaces that actually cut.
    pub planes_cut: u16,
    /// Faces of `S` and `L` the certified path did not clip because the
    /// body's bounding box lies strictly inside them.
    pub planes_cleared: u16,
    /// Stopped early because the body became empty.
    pub early_exit: bool,
    /// Big-integer evaluations: on the exact engine, predicates and
    /// coordinates the floating-point filters could not settle; on the float
    /// path, vertices placed from their planes' exact intersection (where
    /// the float estimate's proven error was above the output tolerance).
    pub exact_evaluations: u32,
    /// The certified floating-point path answered; the exact engine was
    /// not needed.
    pub float_path: bool,
    /// The float path answered a spot light only on its second try, with
    /// `L` clipped before `S` (the first, `S` before `L`, left a sign
    /// unproven).
    pub light_clipped_first: bool,
}

/// A focus body with rounded vertices: a fixed-capacity value, reusable
/// across frames without allocation.
#[derive(Clone)]
pub struct Body {
    pub(crate) dim: i8,
    pub(crate) verts: [DVec3; MAX_VERTICES],
    pub(crate) n_verts: usize,
    pub(crate) idx: [u16; MAX_FACE_INDICES],
    pub(crate) face_start: [u16; MAX_FACES + 1],
    pub(crate) face_planes: [DVec4; MAX_FACES],
    pub(crate) n_faces: usize,
    pub(crate) stats: FocusStats,
    /// The inputs of the last computation, valid when `inputs_valid`.
    pub(crate) inputs: Inputs,
    pub(crate) inputs_valid: bool,
}

/// What [`Body::exact`] rebuilds the inputs from: corners rather than
/// validated frusta.
///
/// NOTE: a validated frustum carries its face structure and normals (about
/// 900 bytes, as does every `Light` value, whatever its kind); copying two
/// of them per body was a visible share of a frame. The corners are all that
/// defines them, and validating the same corners again gives the same
/// frustum.
#[derive(Clone, Copy)]
pub(crate) struct Inputs {
    view: [DVec3; 8],
    light: LightInput,
    /// A spot light's frustum corners (unused for other lights).
    spot_corners: [DVec3; 8],
    scene: Aabb,
}

#[derive(Clone, Copy)]
pub(crate) enum LightInput {
    Directional(DVec3),
    Point(DVec3),
    Spot(DVec3),
}

impl Inputs {
    /// The validated inputs again (the same corners validate to the same
    /// frusta).
    pub(crate) fn rebuild(&self) -> Option<(Frustum, Light, Aabb)> {
        let view = Frustum::from_corners(self.view).ok()?;
        let light = match self.light {
            LightInput::Directional(direction) => Light::Directional { direction },
            LightInput::Point(position) => Light::Point { position },
            LightInput::Spot(position) => Light::Spot { position, frustum: Frustum::from_corners(self.spot_corners).ok()? },
        };
        Some((view, light, self.scene))
    }
}

impl Default for Body {
    fn default() -> Self {
        Body::new()
    }
}

impl std::fmt::Debug for Body {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Body")
            .field("dimension", &self.dimension())
            .field("vertices", &self.vertices())
            .field("faces", &self.faces().collect::<Vec<_>>())
            .field("volume", &self.volume())
            .finish()
    }
}

impl Body {
    /// An empty body.
    pub fn new() -> Body {
        Body {
            dim: -1,
            verts: [DVec3::ZERO; MAX_VERTICES],
            n_verts: 0,
            idx: [0; MAX_FACE_INDICES],
            face_start: [0; MAX_FACES + 1],
            face_planes: [DVec4::ZERO; MAX_FACES],
            n_faces: 0,
            stats: FocusStats::default(),
            inputs: Inputs {
                view: [DVec3::ZERO; 8],
                light: LightInput::Point(DVec3::ZERO),
                spot_corners: [DVec3::ZERO; 8],
                scene: Aabb { min: DVec3::ZERO, max: DVec3::ZERO },
            },
            inputs_valid: false,
        }
    }

    pub(crate) fn clear(&mut self) {
        self.dim = -1;
        self.n_verts = 0;
        self.n_faces = 0;
    }

    /// What kind of convex set the body is.
    pub fn dimension(&self) -> Dimension {
        Dimension::from_i8(self.dim)
    }

    /// Whether the body has no point.
    pub fn is_empty(&self) -> bool {
        self.dim < 0
    }

    /// Rounded vertices; every exact vertex is within a few ulps (of the
    /// inputs' magnitude) of its rounded counterpart.
    pub fn vertices(&self) -> &[DVec3] {
        &self.verts[..self.n_verts]
    }

    /// Number of faces (0 unless solid).
    pub fn face_count(&self) -> usize {
        self.n_faces
    }

    /// Face `i` as vertex indices, counter-clockwise seen from outside (for
    /// a polygon: seen from the side its face plane's normal points to);
    /// `None` for `i ≥ face_count()`.
    #[inline]
    pub fn face(&self, i: usize) -> Option<&[u16]> {
        (i < self.n_faces).then(|| self.face_unchecked(i))
    }

    /// Face `i < n_faces`.
    #[inline]
    fn face_unchecked(&self, i: usize) -> &[u16] {
        &self.idx[self.face_start[i] as usize..self.face_start[i + 1] as usize]
    }

    /// Each face as indices into [`Body::vertices`], in order around the face.
    pub fn faces(&self) -> impl Iterator<Item = &[u16]> + '_ {
        (0..self.n_faces).map(move |i| self.face_unchecked(i))
    }

    /// Per face: unit outward normal (xyz) and offset (w); inside is
    /// `n · p + w ≤ 0`. Rounded from the exact plane.
    pub fn face_planes(&self) -> &[DVec4] {
        &self.face_planes[..self.n_faces]
    }

    /// What the computation of this body skipped and which engine answered.
    pub fn stats(&self) -> &FocusStats {
        &self.stats
    }

    pub(crate) fn record_inputs(&mut self, view: &Frustum, light: &Light, scene: &Aabb) {
        let inputs = &mut self.inputs;
        inputs.view = *view.corners();
        inputs.scene = *scene;
        inputs.light = match light {
            Light::Directional { direction } => LightInput::Directional(*direction),
            Light::Point { position } => LightInput::Point(*position),
            Light::Spot { position, frustum } => {
                inputs.spot_corners = *frustum.corners();
                LightInput::Spot(*position)
            }
        };
        self.inputs_valid = true;
    }

    /// The smallest box around the rounded vertices, `None` when empty.
    pub fn bounds(&self) -> Option<Aabb> {
        Aabb::around(self.vertices())
    }

    /// Volume from the rounded vertices (0 unless solid).
    ///
    /// NOTE: computed on request (a few hundred flops) rather than with
    /// every body: fitting a shadow map never needs it.
    pub fn volume(&self) -> f64 {
        if self.dim != 3 || self.n_verts == 0 {
            return 0.0;
        }
        // NOTE: volume = Σ area_f · height_f / 3 with heights measured from a
        // vertex r of the body. For a convex body every height is ≥ 0, so the
        // sum has no cancellation; areas come from cross products of edges
        // local to each face. (Fanning signed tetrahedra from r instead cancels
        // catastrophically when the body has a vertex very far away.)
        let r = self.verts[0];
        let mut sum = 0.0;
        for (f, face) in self.faces().enumerate() {
            let n = self.face_planes[f].truncate();
            let q = self.verts[face[0] as usize];
            let mut area2 = glam::DVec3::ZERO;
            for k in 1..face.len() - 1 {
                let b = self.verts[face[k] as usize] - q;
                let c = self.verts[face[k + 1] as usize] - q;
                area2 += b.cross(c);
            }
            let height = n.dot(q - r);
            if height > 0.0 {
                // NOTE: past the f64 range the cross products overflow; an
                // overflowed area is +∞, never NaN (∞ − ∞).
                let area = area2.length();
                sum += 0.5 * if area.is_nan() { f64::INFINITY } else { area } * height;
            }
        }
        sum / 3.0
    }
}
