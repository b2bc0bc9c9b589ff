// Main pass: G-buffer with world position, normal, albedo, shadow term, aliasing and chosen split.

// MAX_MAPS (the most maps a frame holds) is defined by the renderer from
// the crate's `MAX_MAPS` (`uniforms::scene_wgsl`).

struct MapInfo {
    world_to_clip: mat4x4<f32>,
    // x, y = view-depth range served; z = 1 for a map stored as 1 − z (its test is not the
    // buffer's); w = +1 for a "less" buffer, −1 for a reversed one.
    split: vec4<f32>,
    // A point light's cube face: xyz = the light, w = the face (0 = +x, 1 = −x, …, 5 = −z);
    // w = −1 for every other map.
    face: vec4<f32>,
    // x = the map's side in texels; y = x over the array's side: a map smaller than the array
    // lies in its layer's top-left corner.
    size: vec4<f32>,
};

struct Frame {
    view_proj: mat4x4<f32>,
    eye: vec4<f32>,
    // xyz = view direction, w = the scene's surface offset (`Scene::surface_offset`)
    forward: vec4<f32>,
    // near, far, width, height
    cam: vec4<f32>,
    lin_a: vec4<f32>,
    // x = linear mode (0 = projective depth)
    lin_b: vec4<f32>,
    // x = map count, y unused (each map's side is in its MapInfo), z = pcf (0 off, 1 hardware, 2 kernel), w = kernel radius
    params: vec4<f32>,
    // x = blend band (fraction of split length), y = receiver-plane bias on (1) / off (0),
    // z = its constant term (map depth units), w = largest tan θ its slope term follows
    params2: vec4<f32>,
    maps: array<MapInfo, MAX_MAPS>,
};

@group(0) @binding(0) var<uniform> f: Frame;
@group(0) @binding(1) var shadow_tex: texture_depth_2d_array;
// One comparison sampler (bilinear, or nearest when PCF is off): GL allows one sampler per
// texture in a shader. It is "less-equal", or "greater-equal" for a reversed buffer (every map of
// the frame a "greater" one); a map whose test is not the buffer's is stored as 1 − z.
@group(0) @binding(2) var cmp: sampler_comparison;

struct VsOut {
    @builtin(position) pos: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) color: vec4<f32>,
};

@vertex
fn vs(@location(0) p: vec3<f32>, @location(1) color: vec4<f32>) -> VsOut {
    var o: VsOut;
    o.pos = f.view_proj * vec4<f32>(p, 1.0);
    o.world = p;
    o.color = color;
    return o;
}

fn linear_depth(p: vec3<f32>) -> f32 {
    if (f.lin_b.x < 1.5) {
        return dot(f.lin_a.xyz, p) + f.lin_a.w;
    }
    return length(p - f.lin_a.xyz) * f.lin_a.w;
}

// Whether the map's clip volume contains p (w > 0, |x|, |y| ≤ w, 0 ≤ z ≤ w in linear mode
// only x, y matter since depth is stored independently of the matrix).
fn map_contains(i: u32, p: vec3<f32>) -> bool {
    let c = f.maps[i].world_to_clip * vec4<f32>(p, 1.0);
    if (!(c.w > 0.0) || abs(c.x) > c.w || abs(c.y) > c.w) {
        return false;
    }
    if (f.lin_b.x > 0.5) {
        return true;
    }
    return c.z >= 0.0 && c.z <= c.w;
}

// A cube face answers only for the receivers in its own 90° cone (its image may reach past it,
// its casters do not): the face of the largest coordinate of p − light (the first on ties), as a
// cube map chooses. NOTE: the faces' cones overlap by a relative 2⁻²⁰, far above the f32 rounding
// of p − light, so a tie rounded either way picks a face that holds p.
fn face_holds(i: u32, p: vec3<f32>) -> bool {
    let c = f.maps[i].face;
    if (c.w < 0.0) {
        return true;
    }
    let d = p - c.xyz;
    let a = abs(d);
    var k = 2u;
    var s = d.z;
    if (a.x >= a.y && a.x >= a.z) {
        k = 0u;
        s = d.x;
    } else if (a.y >= a.z) {
        k = 1u;
        s = d.y;
    }
    return f32(2u * k + select(0u, 1u, s < 0.0)) == c.w;
}

// Whether map i answers for the receiver p: p in its clip volume (and its cone, for a face).
fn map_answers(i: u32, p: vec3<f32>) -> bool {
    return map_contains(i, p) && face_holds(i, p);
}

// NOTE: the reference is clamped to the depth range. A receiver-plane reference (`plane_taps`)
// is the receiver's plane extended to a neighbouring texel centre, and where the receiver lies at
// the map's far face that plane passes beyond it: there the texel holds the cleared value (nothing
// drawn up to the far face), which the unclamped reference would fail against — a false shadow
// along the far edge of every map whose farthest point from the light is a receiver (a sun behind
// the viewer, at each split's far end).
//
// NOTE: the coordinates are clamped to the outermost texel centres, then scaled into the map's
// corner of its layer. For a map as wide as the array this is what clamp-to-edge addressing
// reads anyway (bilinear weights past the last centre fall on the edge texel); for a smaller one
// it keeps the taps off the cleared texels beyond its corner, so it is sampled as a whole map.
fn compare_tap(i: u32, uv: vec2<f32>, r: f32) -> f32 {
    let size = f.maps[i].size;
    let half = 0.5 / size.x;
    let at = clamp(uv, vec2<f32>(half), vec2<f32>(1.0 - half)) * size.y;
    return textureSampleCompareLevel(shadow_tex, cmp, at, i, clamp(r, 0.0, 1.0));
}

// A bound on the rounding of a receiver's projective depth: z = c.z / c.w is evaluated in f32
// here and, for the same surface, rasterised from f32 vertex positions in the shadow pass.
// NOTE: each clip coordinate is a 4-term f32 dot product, off by at most a few ulps of
// Σ|m_rj||p_j| (not of its value, which cancels near the map's near plane); z/w inherits
// (e_z + |z| e_w) / w. Float depth buffers make the constant depth bias vanish at z ≈ 0, and the
// slope bias vanishes on surfaces facing the light, so without this a receiver on the near plane
// facing the light would shadow itself wherever the two roundings differ.
fn depth_rounding(m: mat4x4<f32>, p: vec3<f32>, z: f32, w: f32) -> f32 {
    let ap = vec4<f32>(abs(p), 1.0);
    let ez = dot(abs(vec4<f32>(m[0].z, m[1].z, m[2].z, m[3].z)), ap);
    let ew = dot(abs(vec4<f32>(m[0].w, m[1].w, m[2].w, m[3].w)), ap);
    let u = 5.9604645e-8;
    return 8.0 * u * (ez + abs(z) * ew) / w;
}

// The per-map depth bias: how the reference depth of a receiver at p (unit normal n) changes per
// texel of map i on the receiver's own plane, g = (∂r/∂u, ∂r/∂v) in the map's depth units per
// texel (r the stored depth: z, or 1 − z for a map stored flipped).
//
// Derivation. A receiver plane tilted by θ to the light ray moves along the ray by τ·tan θ
// across one texel of world size τ (the texel's footprint at the receiver); the map stores the
// plane's depth at texel centres, and a lookup compares against centres up to one texel away
// (bilinear PCF) or half a texel (nearest), so the test must tolerate the plane's depth change
// over each tap's offset, plus the depth quantisation. In the map's depth units that change is
// (τ·tan θ)·∂z/∂ℓ per texel for an orthographic map (∂z/∂ℓ = 1 / depth range); for perspective
// and warped maps (PSM, LiSPSM, TSM) τ and ∂z/∂ℓ vary over the map, and the exact form is the
// chain rule: with J = ∂(u, v, z)/∂p at p (rows a, b, c; u, v in texels), the receiver's tangent
// plane maps to the plane n' = J⁻ᵀ n in (u, v, z), so Δz = g·(Δu, Δv) with
//   g_u = −n·(b × c) / n·(a × b),  g_v = −n·(c × a) / n·(a × b),
// where a × b is the map's ray direction ℓ (u, v constant along it) and |n·ℓ̂| = cos θ: |g| is
// tan θ times the texel's depth extent τ·∂z/∂ℓ. Projective maps take planes to planes in
// (u, v, z) and rasterise z affinely there, so this is exact for every map kind: the depth stored
// at a texel centre δ texels from the lookup is r + g·δ wherever the receiver itself is the
// nearest surface there. Each tap is therefore compared against its own reference r + g·δ
// (`plane_taps`), less a bias of 1/16 texel of slope, (|g_u| + |g_v|)/16, for the sub-texel
// precision of rasterisation (vertices snap to at least 1/16 texel), and a constant term for the
// depth format (params2.z). No larger bias is needed on a planar receiver, so light leaks at
// contacts stay within that sixteenth of a texel and the surface offset that `fs` lifts the
// lookup point by (which also absorbs a curved receiver's rise above its plane, up to that
// offset). The tilt is capped at tan θ = params2.w.
fn plane_slope(m: mat4x4<f32>, c: vec4<f32>, n: vec3<f32>, flipped: bool, res: f32) -> vec2<f32> {
    let k = 1.0 / (c.w * c.w);
    let hr = 0.5 * res;
    let mx = vec3<f32>(m[0].x, m[1].x, m[2].x);
    let my = vec3<f32>(m[0].y, m[1].y, m[2].y);
    let mz = vec3<f32>(m[0].z, m[1].z, m[2].z);
    let mw = vec3<f32>(m[0].w, m[1].w, m[2].w);
    // u = res·(0.5 + 0.5 x/w), v = res·(0.5 − 0.5 y/w): texel coordinates, rows top to bottom.
    let a = (hr * k) * (mx * c.w - c.x * mw);
    let b = (-hr * k) * (my * c.w - c.y * mw);
    var dz = k * (mz * c.w - c.z * mw);
    if (flipped) {
        dz = -dz;
    }
    let l = cross(a, b);
    let nl = dot(n, l);
    let tmax = f.params2.w;
    let lim = length(l) * inverseSqrt(1.0 + tmax * tmax);
    let den = select(-1.0, 1.0, nl >= 0.0) * max(abs(nl), lim);
    let g = -vec2<f32>(dot(n, cross(b, dz)), dot(n, cross(dz, a))) / den;
    // A degenerate map (zero Jacobian) gets no slope term.
    return select(vec2<f32>(0.0), g, abs(g) < vec2<f32>(3.0e38));
}

// Bilinear PCF with receiver-plane references: the four texel centres around st + o (texel
// coordinates, o an integer offset), each compared (nearest sampler) against the receiver's plane
// at that centre, weighted bilinearly.
fn plane_taps(i: u32, st: vec2<f32>, o: vec2<f32>, r: f32, g: vec2<f32>, bias: f32) -> f32 {
    let base = floor(st - 0.5) + 0.5;
    let t = st - base;
    let inv = 1.0 / f.maps[i].size.x;
    var sum = 0.0;
    for (var dy = 0; dy < 2; dy = dy + 1) {
        for (var dx = 0; dx < 2; dx = dx + 1) {
            let e = vec2<f32>(f32(dx), f32(dy));
            let centre = base + e + o;
            let v = compare_tap(i, centre * inv, r + dot(g, centre - st) - bias);
            let w = mix(1.0 - t, t, e);
            sum = sum + w.x * w.y * v;
        }
    }
    return sum;
}

// Fraction of the light reaching p (receiver unit normal n) according to map i (1 = lit).
fn shadow_lookup(i: u32, p: vec3<f32>, n: vec3<f32>) -> f32 {
    let m = f.maps[i].world_to_clip;
    let c = m * vec4<f32>(p, 1.0);
    let ndc = c.xyz / c.w;
    let uv = vec2<f32>(0.5 + 0.5 * ndc.x, 0.5 - 0.5 * ndc.y);
    let res = f.maps[i].size.x;
    let mode = u32(f.params.z);
    let k = i32(f.params.w);
    let texel = 1.0 / res;
    var r: f32;
    if (f.lin_b.x > 0.5) {
        r = linear_depth(p);
    } else {
        let flipped = f.maps[i].split.z > 0.5;
        // Toward the light in stored depth: −1 in a "less" buffer, +1 in a reversed one.
        let s = -f.maps[i].split.w;
        // NOTE: the clamp keeps receivers on the map's far face (z = 1 up to rounding, 0 in a
        // reversed buffer) from being compared against the cleared value and shadowing themselves.
        r = clamp(ndc.z, 0.0, 1.0);
        if (flipped) {
            r = 1.0 - r;
        }
        r = r + s * depth_rounding(m, p, ndc.z, c.w);
        if (f.params2.y > 0.5) {
            // Receiver-plane bias; the sampler is the nearest one (see `Renderer::render`).
            let g = plane_slope(m, c, n, flipped, res);
            let bias = -s * (f.params2.z + 0.0625 * (abs(g.x) + abs(g.y)));
            let st = uv * res;
            if (mode == 0u) {
                let centre = floor(st) + 0.5;
                return compare_tap(i, centre * texel, r + dot(g, centre - st) - bias);
            }
            if (mode == 1u) {
                return plane_taps(i, st, vec2<f32>(0.0), r, g, bias);
            }
            var sum = 0.0;
            for (var y = -k; y <= k; y = y + 1) {
                for (var x = -k; x <= k; x = x + 1) {
                    sum = sum + plane_taps(i, st, vec2<f32>(f32(x), f32(y)), r, g, bias);
                }
            }
            let nk = f32(2 * k + 1);
            return sum / (nk * nk);
        }
    }
    if (mode < 2u) {
        return compare_tap(i, uv, r);
    }
    var sum = 0.0;
    for (var y = -k; y <= k; y = y + 1) {
        for (var x = -k; x <= k; x = x + 1) {
            sum = sum + compare_tap(i, uv + vec2<f32>(f32(x), f32(y)) * texel, r);
        }
    }
    let nk = f32(2 * k + 1);
    return sum / (nk * nk);
}

// Screen pixels per shadow texel: e = 1/sqrt(|det ∂t/∂(x,y)|), t = texcoord × resolution.
// Chain rule on t = (res/2)·(c.xy/c.w) + const with c = M·p and ∂c = M·∂p (w-component 0):
//   ∂t = (res/2)·(∂c.xy·c.w − c.xy·∂c.w)/c.w².
// Computed from the world-position derivatives, which are taken in uniform control flow.
fn aliasing(i: u32, p: vec3<f32>, dx: vec3<f32>, dy: vec3<f32>) -> f32 {
    let m = f.maps[i].world_to_clip;
    let c = m * vec4<f32>(p, 1.0);
    let cx = m * vec4<f32>(dx, 0.0);
    let cy = m * vec4<f32>(dy, 0.0);
    let k = 0.5 * f.maps[i].size.x / (c.w * c.w);
    let tx = k * (cx.xy * c.w - c.xy * cx.w);
    let ty = k * (cy.xy * c.w - c.xy * cy.w);
    let det = abs(tx.x * ty.y - tx.y * ty.x);
    if (!(det > 0.0)) {
        return 3.0e38;
    }
    return inverseSqrt(det);
}

// Float data go out as f32 bits in 32-bit integer targets: float colour targets are not
// renderable on every GL driver (Mesa's core profile among them), integer ones are.
struct GOut {
    // xyz world, w = 1 receiver, 2 other geometry (all-zero bits = background after clear)
    @location(0) world: vec4<u32>,
    // xyz unit normal facing the camera
    @location(1) normal: vec4<f32>,
    @location(2) albedo: vec4<f32>,
    // x = aliasing e (−1 when uncovered), y = view depth, z = shadow term, w = chosen map (−1 none)
    @location(3) aux: vec4<u32>,
};

@fragment
fn fs(in: VsOut) -> GOut {
    let p = in.world;
    let dx = dpdx(p);
    let dy = dpdy(p);
    var n = normalize(cross(dx, dy));
    if (dot(n, f.eye.xyz - p) < 0.0) {
        n = -n;
    }
    // NOTE: a visible point's true depth lies in [near, far]; the f32 dot product can land a
    // rounding error outside, which must not make a pixel at the frustum's ends "uncovered".
    let depth = clamp(dot(p - f.eye.xyz, f.forward.xyz), f.cam.x, f.cam.y);
    let count = u32(f.params.x);
    var chosen = -1;
    for (var i = 0u; i < count; i = i + 1u) {
        let s = f.maps[i].split;
        if (depth >= s.x && depth <= s.y && map_answers(i, p)) {
            chosen = i32(i);
            break;
        }
    }
    var vis = 1.0;
    var e = -1.0;
    // NOTE: the lookup is made at p lifted off its surface by the scene's surface offset, the
    // point the ground truth casts its ray from; the map and split are chosen at p itself.
    let lifted = p + n * f.forward.w;
    if (chosen >= 0) {
        let i = u32(chosen);
        vis = shadow_lookup(i, lifted, n);
        e = aliasing(i, p, dx, dy);
        // Blend band: over the last fraction of this split, fade into the next map that covers p.
        let band = f.params2.x;
        let s = f.maps[i].split;
        let len = (s.y - s.x) * band;
        if (band > 0.0 && len > 0.0 && depth > s.y - len) {
            for (var j = i + 1u; j < count; j = j + 1u) {
                if (map_answers(j, p)) {
                    let t = clamp((depth - (s.y - len)) / len, 0.0, 1.0);
                    vis = mix(vis, shadow_lookup(j, lifted, n), t);
                    break;
                }
            }
        }
    }
    var o: GOut;
    o.world = bitcast<vec4<u32>>(vec4<f32>(p, select(2.0, 1.0, in.color.a > 0.75)));
    o.normal = vec4<f32>(n, 0.0);
    o.albedo = vec4<f32>(in.color.rgb, 1.0);
    o.aux = bitcast<vec4<u32>>(vec4<f32>(e, depth, vis, f32(chosen)));
    return o;
}
