//! Built-in procedural validation scenes (deterministic; no downloads).
//!
//! Units are metres, +y is up. Every object casts and receives shadows in the rendering and in the
//! mismatch metric; the ground surfaces (floor, board, terrain) are the "receivers" over which
//! aliasing statistics are taken, as in the papers' analyses of shadows on the ground.

use glam::DVec3;

use crate::error::RenderError;
use crate::scene::{MeshBuilder, Scene};
use crate::types::{CameraSpec, LightSpec};

/// Names accepted by [`builtin_scene`].
pub const BUILTIN_SCENES: [&str; 7] =
    ["chessboard", "huge-chessboard", "forest", "robot-war", "duelling-frusta", "inverted", "thin-casters"];

/// Builds a built-in scene by name.
pub fn builtin_scene(name: &str) -> Result<Scene, RenderError> {
    match name {
        "chessboard" => chessboard(),
        "huge-chessboard" => huge_chessboard(),
        "forest" => forest(),
        "robot-war" => robot_war(),
        "duelling-frusta" => duelling_frusta(),
        "inverted" => inverted(),
        "thin-casters" => thin_casters(),
        _ => Err(RenderError::UnknownScene { name: name.to_string(), known: BUILTIN_SCENES.join(", ") }),
    }
}

/// SplitMix64: a tiny deterministic generator for placements.
struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [lo, hi).
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * ((self.next_u64() >> 11) as f64 / (1u64 << 53) as f64)
    }
}

fn look(eye: DVec3, target: DVec3) -> DVec3 {
    target - eye
}

fn deg(d: f64) -> f64 {
    d.to_radians()
}

const LIGHT_SQUARE: [u8; 3] = [222, 204, 166];
const DARK_SQUARE: [u8; 3] = [96, 64, 42];
const WHITE_PIECE: [u8; 3] = [236, 232, 220];
const BLACK_PIECE: [u8; 3] = [58, 56, 66];

#[derive(Clone, Copy)]
enum Piece {
    Pawn,
    Rook,
    Knight,
    Bishop,
    Queen,
    King,
}

/// Lathe profile (radius, height) of a piece standing on a unit square, ≈ 0.7–1.35 tall.
fn piece_profile(p: Piece) -> Vec<(f64, f64)> {
    match p {
        Piece::Pawn => vec![(0.30, 0.0), (0.30, 0.08), (0.20, 0.14), (0.12, 0.34), (0.20, 0.40), (0.16, 0.56), (0.09, 0.66), (0.0, 0.70)],
        Piece::Rook => vec![(0.33, 0.0), (0.33, 0.10), (0.24, 0.16), (0.20, 0.60), (0.27, 0.66), (0.27, 0.82), (0.0, 0.82)],
        Piece::Knight => vec![(0.32, 0.0), (0.32, 0.10), (0.22, 0.18), (0.18, 0.45), (0.0, 0.45)],
        Piece::Bishop => vec![(0.32, 0.0), (0.32, 0.09), (0.22, 0.16), (0.13, 0.58), (0.22, 0.64), (0.17, 0.86), (0.06, 0.98), (0.0, 1.02)],
        Piece::Queen => vec![(0.35, 0.0), (0.35, 0.10), (0.24, 0.18), (0.14, 0.78), (0.25, 0.86), (0.20, 1.06), (0.10, 1.12), (0.0, 1.18)],
        Piece::King => {
            vec![(0.36, 0.0), (0.36, 0.10), (0.25, 0.18), (0.15, 0.84), (0.26, 0.92), (0.18, 1.10), (0.05, 1.14), (0.05, 1.34), (0.0, 1.36)]
        }
    }
}

/// One piece on the square whose centre is `c`, scaled by `s` (square side).
fn add_piece(mb: &mut MeshBuilder, piece: Piece, c: DVec3, s: f64, color: [u8; 3], facing: f64, segments: u32) {
    mb.begin(false);
    let prof: Vec<(f64, f64)> = piece_profile(piece).iter().map(|&(r, h)| (r * s, h * s)).collect();
    mb.lathe(c, &prof, segments, color);
    if let Piece::Knight = piece {
        // Head: a tilted-forward block and a muzzle on top of the lathe base.
        let ax = DVec3::new(1.0, 0.0, 0.0);
        let az = DVec3::new(0.0, 0.0, 1.0);
        mb.oriented_box(c + DVec3::new(0.0, 0.62 * s, 0.0), DVec3::new(0.13, 0.2, 0.2) * s, ax, az, color);
        mb.oriented_box(c + DVec3::new(0.0, 0.74 * s, facing * 0.2 * s), DVec3::new(0.11, 0.09, 0.18) * s, ax, az, color);
    }
    mb.end();
}

/// The square (i, j) of a board whose squares' edges are `edge`, at height y.
fn grid_cell(edge: &[f64; 9], i: usize, j: usize, y: f64) -> [DVec3; 4] {
    let (x0, x1, z0, z1) = (edge[i], edge[i + 1], edge[j], edge[j + 1]);
    [DVec3::new(x0, y, z0), DVec3::new(x1, y, z0), DVec3::new(x1, y, z1), DVec3::new(x0, y, z1)]
}

/// The sides and bottom of a board slab from y = 0 down to `bottom`, cut at the squares' edges.
/// NOTE: every edge of a face is then an edge of its neighbour, vertex for vertex. A side made of
/// one quad would meet the squares' corners on its top edge (a T-junction): rasterised, the
/// squares' edges and the side's long edge round apart, and the far side face, seen from behind,
/// shows through at single pixels along the board's far edge.
fn add_slab_sides(mb: &mut MeshBuilder, edge: &[f64; 9], bottom: f64) {
    let rim = [120, 84, 60];
    let (lo, hi) = (edge[0], edge[8]);
    for k in 0..8 {
        let (a, b) = (edge[k], edge[k + 1]);
        for z in [lo, hi] {
            mb.quad([DVec3::new(a, bottom, z), DVec3::new(b, bottom, z), DVec3::new(b, 0.0, z), DVec3::new(a, 0.0, z)], rim);
        }
        for x in [lo, hi] {
            mb.quad([DVec3::new(x, bottom, a), DVec3::new(x, bottom, b), DVec3::new(x, 0.0, b), DVec3::new(x, 0.0, a)], rim);
        }
        for j in 0..8 {
            mb.quad(grid_cell(edge, k, j, bottom), rim);
        }
    }
}

/// A chess set: board slab with squares on top (one object) and 32 pieces; board centred at the
/// origin, top face at y = 0.
fn add_chess_set(mb: &mut MeshBuilder, square: f64, piece_scale: f64, slab: f64, segments: u32, scatter: Option<u64>) {
    mb.begin(true);
    let half = 4.0 * square;
    // The squares' edges, shared by the top, the sides and the bottom.
    let edge: [f64; 9] = std::array::from_fn(|k| -half + k as f64 * square);
    for j in 0..8 {
        for i in 0..8 {
            let col = if (i + j) % 2 == 0 { DARK_SQUARE } else { LIGHT_SQUARE };
            mb.quad(grid_cell(&edge, i, j, 0.0), col);
        }
    }
    add_slab_sides(mb, &edge, -slab);
    mb.end();
    use Piece::*;
    let back = [Rook, Knight, Bishop, Queen, King, Bishop, Knight, Rook];
    // Squares: the starting position, or (with a seed) a deterministic mid-game scatter over
    // distinct squares so that shadows fall all over the board.
    let mut squares: Vec<(usize, usize)> = Vec::new();
    match scatter {
        None => {
            for (row, pawn_row) in [(0usize, 1usize), (7, 6)] {
                for i in 0..8 {
                    squares.push((i, row));
                    squares.push((i, pawn_row));
                }
            }
        }
        Some(seed) => {
            let mut rng = Rng(seed);
            let mut free: Vec<(usize, usize)> = (0..64).map(|k| (k % 8, k / 8)).collect();
            for _ in 0..32 {
                let k = (rng.next_u64() % free.len() as u64) as usize;
                squares.push(free.swap_remove(k));
            }
        }
    }
    for (k, &(i, j)) in squares.iter().enumerate() {
        let (color, facing) = if k < 16 { (WHITE_PIECE, 1.0) } else { (BLACK_PIECE, -1.0) };
        let piece = if k % 2 == 1 { Pawn } else { back[(k / 2) % 8] };
        let c = DVec3::new(-half + (i as f64 + 0.5) * square, 0.0, -half + (j as f64 + 0.5) * square);
        add_piece(mb, piece, c, piece_scale, color, facing, segments);
    }
}

fn finish(name: &str, mut mb: MeshBuilder, camera: CameraSpec, light: LightSpec) -> Result<Scene, RenderError> {
    mb.end();
    Scene::new(name, mb.vertices, mb.indices, &mb.objects, camera, light)
}

/// `chessboard`: a 8 m board with 32 pieces on a floor, lit by a spot light (PSM paper, Fig. 1).
pub fn chessboard() -> Result<Scene, RenderError> {
    let mut mb = MeshBuilder::default();
    mb.begin(true);
    mb.quad(
        [DVec3::new(-14.0, -0.3, -14.0), DVec3::new(14.0, -0.3, -14.0), DVec3::new(14.0, -0.3, 14.0), DVec3::new(-14.0, -0.3, 14.0)],
        [150, 150, 142],
    );
    add_chess_set(&mut mb, 1.0, 1.0, 0.3, 14, None);
    let eye = DVec3::new(1.5, 5.0, 10.5);
    let camera = CameraSpec { eye, forward: look(eye, DVec3::new(0.0, 0.0, 0.5)), up: DVec3::Y, fovy: deg(50.0), near: 0.5, far: 40.0 };
    let lp = DVec3::new(-6.0, 10.0, -5.0);
    let light = LightSpec::Spot {
        position: lp,
        direction: look(lp, DVec3::new(0.5, 0.0, 1.0)),
        up: DVec3::Y,
        fovy: deg(65.0),
        near: 1.0,
        far: 40.0,
    };
    finish("chessboard", mb, camera, light)
}

/// `huge-chessboard`: a 700 m × 700 m board with 32 pieces 25–50 m tall scattered over it, a low
/// directional light, camera 30 m above the board's edge, near 1 m, far 800 m, fov 60° (PSSM
/// paper's test scene). Only the board is a receiver for aliasing statistics.
pub fn huge_chessboard() -> Result<Scene, RenderError> {
    let mut mb = MeshBuilder::default();
    add_chess_set(&mut mb, 87.5, 38.0, 6.0, 20, Some(0xC4E55));
    // From beside the board's left edge, low, looking across the empty middle ranks.
    let eye = DVec3::new(-385.0, 30.0, -100.0);
    let camera = CameraSpec { eye, forward: look(eye, DVec3::new(200.0, 0.0, 60.0)), up: DVec3::Y, fovy: deg(60.0), near: 1.0, far: 800.0 };
    // A low sun (≈ 21° elevation) throwing long shadows across the board toward +z.
    let light = LightSpec::Directional { direction: DVec3::new(0.35, -0.36, 0.86) };
    finish("huge-chessboard", mb, camera, light)
}

fn terrain_height(x: f64, z: f64) -> f64 {
    3.0 * (0.031 * x + 0.5).sin() * (0.026 * z).cos() + 1.4 * (0.11 * x + 0.07 * z).sin() + 0.5 * (0.23 * z - 0.1 * x).sin()
}

/// `forest`: 256 m × 256 m rolling terrain with 10,000 trees, directional light, camera at eye
/// height near the forest edge, near 0.1, far 70, fov 45° ([SCH05]'s setting).
pub fn forest() -> Result<Scene, RenderError> {
    let mut mb = MeshBuilder::default();
    let mut rng = Rng(0x5EED_F0E5_7000);
    mb.begin(true);
    mb.heightfield(-128.0, -128.0, 128.0, 128.0, 128, 128, terrain_height, |_, y, _| {
        let g = (110.0 + 8.0 * y).clamp(80.0, 140.0) as u8;
        [g / 2 + 20, g, g / 3 + 10]
    });
    mb.end();
    // 100 × 100 jittered grid over [−120, 120]²; rows in z so culled sets are long index runs.
    let step = 2.4;
    for j in 0..100 {
        for i in 0..100 {
            let x = -120.0 + (i as f64 + rng.range(0.15, 0.85)) * step;
            let z = -120.0 + (j as f64 + rng.range(0.15, 0.85)) * step;
            let y = terrain_height(x, z) - 0.2;
            let trunk_h = rng.range(1.6, 3.2);
            let r = rng.range(0.12, 0.22);
            let crown_h = rng.range(2.5, 5.5);
            let crown_r = rng.range(0.7, 1.3);
            let base = DVec3::new(x, y, z);
            mb.begin(false);
            mb.lathe(base, &[(r, 0.0), (r * 0.7, trunk_h + 0.2)], 5, [110, 80, 50]);
            let g = rng.range(70.0, 120.0) as u8;
            mb.lathe(base, &[(crown_r, trunk_h), (0.0, trunk_h + crown_h)], 6, [30, g, 40]);
            mb.end();
        }
    }
    let eye = DVec3::new(0.0, terrain_height(0.0, -126.0) + 1.7, -126.0);
    let camera = CameraSpec { eye, forward: DVec3::new(0.12, -0.08, 1.0), up: DVec3::Y, fovy: deg(45.0), near: 0.1, far: 70.0 };
    let light = LightSpec::Directional { direction: DVec3::new(0.55, -0.6, 0.3) };
    finish("forest", mb, camera, light)
}

/// A walking robot: legs, torso, head, arms and a gun, `h` metres tall, turned by `yaw`.
fn add_robot(mb: &mut MeshBuilder, at: DVec3, h: f64, yaw: f64, color: [u8; 3]) {
    let ax = DVec3::new(yaw.cos(), 0.0, yaw.sin());
    let az = DVec3::new(-yaw.sin(), 0.0, yaw.cos());
    let u = h / 10.0;
    let p = |x: f64, y: f64, z: f64| at + ax * (x * u) + DVec3::Y * (y * u) + az * (z * u);
    mb.begin(false);
    mb.oriented_box(p(-1.2, 2.5, 0.0), DVec3::new(0.6, 2.5, 0.7) * u, ax, az, color);
    mb.oriented_box(p(1.2, 2.5, 0.3), DVec3::new(0.6, 2.5, 0.7) * u, ax, az, color);
    mb.oriented_box(p(0.0, 6.5, 0.0), DVec3::new(2.2, 1.7, 1.4) * u, ax, az, color);
    mb.oriented_box(p(0.0, 9.0, 0.3), DVec3::new(0.9, 0.8, 0.9) * u, ax, az, [200, 60, 40]);
    mb.oriented_box(p(-2.8, 6.4, 0.8), DVec3::new(0.5, 0.5, 2.0) * u, ax, az, color);
    mb.oriented_box(p(2.8, 6.8, 1.2), DVec3::new(0.4, 0.4, 2.6) * u, ax, az, [70, 70, 70]);
    mb.end();
}

/// `robot-war`: 100 robots and 59 buildings on a 1.2 km × 1.2 km plain (160 objects with the
/// ground), directional light, near 1, far 1000, fov 60° (PSSM paper's test scene).
pub fn robot_war() -> Result<Scene, RenderError> {
    let mut mb = MeshBuilder::default();
    let mut rng = Rng(0x02B0_73A8);
    mb.begin(true);
    mb.heightfield(
        -600.0,
        -600.0,
        600.0,
        600.0,
        16,
        16,
        |_, _| 0.0,
        |x, _, z| {
            let c = if ((x / 75.0).floor() + (z / 75.0).floor()) as i64 % 2 == 0 { 128 } else { 118 };
            [c, c - 6, c - 20]
        },
    );
    mb.end();
    for _ in 0..59 {
        // Keep the foreground open: no building within 160 m of the camera.
        let (x, z) = loop {
            let (x, z) = (rng.range(-560.0, 560.0), rng.range(-480.0, 560.0));
            if (x + 20.0).hypot(z + 590.0) > 160.0 {
                break (x, z);
            }
        };
        let (w, d, h) = (rng.range(20.0, 60.0), rng.range(20.0, 60.0), rng.range(15.0, 80.0));
        let yaw = rng.range(0.0, std::f64::consts::PI);
        let ax = DVec3::new(yaw.cos(), 0.0, yaw.sin());
        let az = DVec3::new(-yaw.sin(), 0.0, yaw.cos());
        let g = rng.range(140.0, 200.0) as u8;
        mb.begin(false);
        mb.oriented_box(DVec3::new(x, 0.5 * h, z), DVec3::new(0.5 * w, 0.5 * h, 0.5 * d), ax, az, [g, g, g.saturating_sub(10)]);
        mb.end();
    }
    for k in 0..100 {
        let (x, z) = (rng.range(-500.0, 500.0), rng.range(-520.0, 560.0));
        let h = rng.range(12.0, 25.0);
        let color = if k % 2 == 0 { [70, 110, 170] } else { [170, 120, 60] };
        add_robot(&mut mb, DVec3::new(x, 0.0, z), h, rng.range(0.0, std::f64::consts::TAU), color);
    }
    let eye = DVec3::new(-20.0, 14.0, -590.0);
    let camera = CameraSpec { eye, forward: DVec3::new(0.08, -0.04, 1.0), up: DVec3::Y, fovy: deg(60.0), near: 1.0, far: 1000.0 };
    // Afternoon sun from the left: shadows fall across the view, between the buildings.
    let light = LightSpec::Directional { direction: DVec3::new(0.75, -0.5, 0.25) };
    finish("robot-war", mb, camera, light)
}

/// `duelling-frusta`: posts and blocks on a plain with the light shining almost straight at the
/// viewer (light direction nearly opposite the view direction), near 0.5, far 250, fov 60°.
pub fn duelling_frusta() -> Result<Scene, RenderError> {
    let mut mb = MeshBuilder::default();
    let mut rng = Rng(0xD0E1);
    mb.begin(true);
    mb.heightfield(-150.0, -150.0, 150.0, 150.0, 12, 12, |_, _| 0.0, |_, _, _| [140, 150, 120]);
    mb.end();
    for j in 0..12 {
        for i in 0..10 {
            let x = -90.0 + i as f64 * 20.0 + rng.range(-4.0, 4.0);
            let z = -100.0 + j as f64 * 20.0 + rng.range(-4.0, 4.0);
            mb.begin(false);
            if (i + j) % 3 == 0 {
                let s = rng.range(2.0, 5.0);
                mb.cuboid(DVec3::new(x - s, 0.0, z - s), DVec3::new(x + s, 2.0 * s, z + s), [180, 90, 70]);
            } else {
                let h = rng.range(6.0, 14.0);
                mb.cuboid(DVec3::new(x - 0.4, 0.0, z - 0.4), DVec3::new(x + 0.4, h, z + 0.4), [200, 190, 160]);
            }
            mb.end();
        }
    }
    let eye = DVec3::new(0.0, 9.0, -125.0);
    let camera = CameraSpec { eye, forward: DVec3::new(0.0, -0.15, 1.0), up: DVec3::Y, fovy: deg(60.0), near: 0.5, far: 250.0 };
    let light = LightSpec::Directional { direction: DVec3::new(0.08, -0.32, -1.0) };
    finish("duelling-frusta", mb, camera, light)
}

/// `inverted`: a point light behind and above the camera lighting blocks and columns in front of
/// it — in a perspective shadow map's post-projective space the light lies beyond infinity and
/// the map's depth order inverts.
pub fn inverted() -> Result<Scene, RenderError> {
    let mut mb = MeshBuilder::default();
    let mut rng = Rng(0x1A7E);
    mb.begin(true);
    mb.heightfield(-40.0, -40.0, 40.0, 40.0, 8, 8, |_, _| 0.0, |_, _, _| [150, 140, 130]);
    mb.end();
    for k in 0..18 {
        let x = -12.0 + (k % 6) as f64 * 4.8 + rng.range(-1.0, 1.0);
        let z = -8.0 + (k / 6) as f64 * 9.0 + rng.range(-1.5, 1.5);
        mb.begin(false);
        if k % 2 == 0 {
            let h = rng.range(1.0, 3.0);
            mb.cuboid(DVec3::new(x - 0.8, 0.0, z - 0.8), DVec3::new(x + 0.8, h, z + 0.8), [90, 130, 190]);
        } else {
            let r = rng.range(0.3, 0.6);
            mb.lathe(DVec3::new(x, 0.0, z), &[(r, 0.0), (r, 3.5), (r * 1.6, 3.7), (0.0, 3.9)], 12, [210, 170, 90]);
        }
        mb.end();
    }
    let eye = DVec3::new(0.0, 3.0, -20.0);
    let camera = CameraSpec { eye, forward: DVec3::new(0.0, -0.2, 1.0), up: DVec3::Y, fovy: deg(55.0), near: 0.3, far: 80.0 };
    let light = LightSpec::Point { position: DVec3::new(3.0, 9.0, -31.0) };
    finish("inverted", mb, camera, light)
}

/// `thin-casters`: posts, beams on post pairs, slatted fences and crates over a 400 m × 400 m
/// ground box, the camera at eye height (1.7 m) looking slightly down, fov 60°, near 0.5, far
/// 250, and a sun 15° above the horizon shining toward the camera (light direction nearly
/// opposite the view direction): the duelling-frusta case at ground level, where the focus body
/// is long, flat and seen almost edge-on by the light. Thin casters make undersampling visible
/// (a 0.12 m slat is under a texel wide in much of a uniform map), and the grazing sun makes a
/// too large depth bias visible as light leaking under every caster's base.
pub fn thin_casters() -> Result<Scene, RenderError> {
    let mut mb = MeshBuilder::default();
    let mut rng = Rng(0x7416_CA57);
    // The ground: a slab whose top face is y = 0 (the only receiver).
    mb.begin(true);
    mb.cuboid(DVec3::new(-200.0, -2.0, -200.0), DVec3::new(200.0, 0.0, 200.0), [150, 158, 128]);
    mb.end();
    let wood = [176, 140, 96];
    let steel = [150, 150, 160];
    // Rows across the view, from 6 m to ~220 m ahead of the camera (at z = −150), spaced in
    // proportion to their distance and as wide as the view, so that casters and their long
    // shadows (toward the camera) fill the image at every depth.
    let mut d = 6.0f64;
    let mut j = 0usize;
    while d < 220.0 {
        let half = (1.1 * d + 3.0f64).min(185.0);
        let n = 7usize;
        for i in 0..n {
            let x = -half + (i as f64 + rng.range(0.2, 0.8)) * 2.0 * half / n as f64;
            let z = -150.0 + d + rng.range(-0.2, 0.2) * d;
            let yaw = rng.range(0.0, std::f64::consts::PI);
            let ax = DVec3::new(yaw.cos(), 0.0, yaw.sin());
            let az = DVec3::new(-yaw.sin(), 0.0, yaw.cos());
            let at = |u: f64, y: f64, v: f64| DVec3::new(x, 0.0, z) + ax * u + DVec3::Y * y + az * v;
            match (i * 3 + j) % 4 {
                0 => {
                    // A post.
                    let (r, h) = (rng.range(0.08, 0.16), rng.range(2.0, 6.0));
                    mb.begin(false);
                    mb.oriented_box(at(0.0, 0.5 * h, 0.0), DVec3::new(r, 0.5 * h, r), ax, az, wood);
                    mb.end();
                }
                1 => {
                    // Two posts and a beam across their tops.
                    let (span, h) = (rng.range(3.0, 6.0), rng.range(2.2, 3.5));
                    mb.begin(false);
                    for s in [-0.5, 0.5] {
                        mb.oriented_box(at(s * span, 0.5 * h, 0.0), DVec3::new(0.1, 0.5 * h, 0.1), ax, az, steel);
                    }
                    mb.oriented_box(at(0.0, h + 0.1, 0.0), DVec3::new(0.5 * span + 0.3, 0.1, 0.08), ax, az, steel);
                    mb.end();
                }
                2 => {
                    // A fence: two rails and vertical slats 0.12 m wide, 0.14 m apart.
                    let (len, h) = (rng.range(4.0, 8.0), rng.range(1.0, 1.6));
                    mb.begin(false);
                    for y in [0.3, h - 0.15] {
                        mb.oriented_box(at(0.0, y, 0.0), DVec3::new(0.5 * len, 0.04, 0.03), ax, az, wood);
                    }
                    let n = (len / 0.26) as i32;
                    for k in 0..n {
                        let u = -0.5 * len + (k as f64 + 0.5) * len / n as f64;
                        mb.oriented_box(at(u, 0.5 * h, 0.06), DVec3::new(0.06, 0.5 * h, 0.015), ax, az, wood);
                    }
                    mb.end();
                }
                _ => {
                    // A crate, sometimes with a smaller one on top.
                    let s = rng.range(0.4, 1.0);
                    mb.begin(false);
                    mb.oriented_box(at(0.0, s, 0.0), DVec3::splat(s), ax, az, [160, 110, 60]);
                    if rng.range(0.0, 1.0) < 0.5 {
                        let t = 0.6 * s;
                        mb.oriented_box(at(0.1 * s, 2.0 * s + t, -0.1 * s), DVec3::splat(t), az, -ax, [170, 120, 70]);
                    }
                    mb.end();
                }
            }
        }
        d = d * 1.15 + 1.5;
        j += 1;
    }
    let eye = DVec3::new(0.0, 1.7, -150.0);
    let camera = CameraSpec { eye, forward: DVec3::new(0.0, -0.06, 1.0), up: DVec3::Y, fovy: deg(60.0), near: 0.5, far: 250.0 };
    // 15° above the horizon, travelling toward the camera, 5° off the view axis.
    let (el, az) = (deg(15.0), deg(5.0));
    let light = LightSpec::Directional { direction: DVec3::new(el.cos() * az.sin(), -el.sin(), -el.cos() * az.cos()) };
    finish("thin-casters", mb, camera, light)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtin_scenes_build_and_are_deterministic() {
        for name in BUILTIN_SCENES {
            if name == "forest" {
                continue; // large; covered by the integration tests
            }
            let a = builtin_scene(name).unwrap();
            let b = builtin_scene(name).unwrap();
            assert_eq!(a.vertices, b.vertices, "{name}");
            assert_eq!(a.indices, b.indices, "{name}");
            assert!(a.objects.iter().all(|o| o.index_count > 0 && !o.aabb.is_empty()), "{name}");
            let c = a.camera;
            assert!(c.near < c.far, "{name}");
        }
    }

    #[test]
    fn scene_shapes_match_their_descriptions() {
        let hc = huge_chessboard().unwrap();
        assert_eq!(hc.objects.len(), 33, "board + 32 pieces");
        let ext = hc.bounds.max - hc.bounds.min;
        assert!((ext.x - 700.0).abs() < 1e-9 && (ext.z - 700.0).abs() < 1e-9);
        assert_eq!((hc.camera.near, hc.camera.far), (1.0, 800.0));
        let rw = robot_war().unwrap();
        assert_eq!(rw.objects.len(), 160);
        assert!((rw.bounds.max.x - rw.bounds.min.x - 1200.0).abs() < 1e-9);
        let inv = inverted().unwrap();
        let lp = inv.light.position().unwrap();
        assert!(inv.camera.view_depth(lp) < 0.0, "the light is behind the camera");
        let df = duelling_frusta().unwrap();
        let LightSpec::Directional { direction } = df.light else { panic!() };
        assert!(direction.normalize().dot(df.camera.forward.normalize()) < -0.8, "light faces the viewer");
        let tc = thin_casters().unwrap();
        let ext = tc.bounds.max - tc.bounds.min;
        assert!((ext.x - 400.0).abs() < 1e-9 && (ext.z - 400.0).abs() < 1e-9);
        assert!(tc.objects[0].receiver && tc.objects[1..].iter().all(|o| !o.receiver));
        assert!(tc.objects.len() > 100, "{} objects", tc.objects.len());
        let c = tc.camera;
        assert_eq!((c.near, c.far, c.eye.y), (0.5, 250.0, 1.7));
        assert!((c.fovy - 60f64.to_radians()).abs() < 1e-12);
        let LightSpec::Directional { direction } = tc.light else { panic!() };
        let d = direction.normalize();
        assert!((d.y + 15f64.to_radians().sin()).abs() < 1e-12, "sun 15° above the horizon");
        assert!(d.dot(c.forward.normalize()) < -0.9, "light faces the viewer");
        // Thin casters: posts at most 0.32 m thick (0.46 m across their box when turned).
        let thin = tc.objects[1..]
            .iter()
            .filter(|o| {
                let e = o.aabb.max - o.aabb.min;
                e.x.max(e.z) < 0.5
            })
            .count();
        assert!(thin > 25, "{thin} posts");
    }

    #[test]
    fn forest_has_ten_thousand_trees_on_terrain() {
        let f = forest().unwrap();
        assert_eq!(f.objects.len(), 10_001, "terrain + 10,000 trees");
        assert!(f.objects[0].receiver && f.objects[1..].iter().all(|o| !o.receiver));
        assert_eq!((f.camera.near, f.camera.far), (0.1, 70.0));
        assert!((f.camera.fovy - 45f64.to_radians()).abs() < 1e-12);
        assert!(matches!(f.light, LightSpec::Directional { .. }));
        // Trees are in row order, so neighbouring objects are contiguous in the index list.
        for w in f.objects.windows(2) {
            assert_eq!(w[0].first_index + w[0].index_count, w[1].first_index);
        }
    }

    #[test]
    fn unknown_scene_is_an_error() {
        assert!(matches!(builtin_scene("nope"), Err(RenderError::UnknownScene { .. })));
    }
}
