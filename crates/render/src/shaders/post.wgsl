// Screen-space passes: eye-space blur of the shadow term and the final lit composite.

struct VsOut {
    @builtin(position) pos: vec4<f32>,
};

// One triangle covering the screen.
@vertex
fn vs(@builtin(vertex_index) i: u32) -> VsOut {
    let x = f32((i << 1u) & 2u) * 2.0 - 1.0;
    let y = f32(i & 2u) * 2.0 - 1.0;
    var o: VsOut;
    o.pos = vec4<f32>(x, y, 0.0, 1.0);
    return o;
}

struct BlurParams {
    // xy = step direction in pixels, z = focal length in pixels, w = world radius
    a: vec4<f32>,
    // x = max radius px, y = 1 when the source is aux.z (first pass)
    b: vec4<f32>,
};

@group(0) @binding(0) var<uniform> bp: BlurParams;
@group(0) @binding(1) var aux_tex: texture_2d<u32>;
@group(0) @binding(2) var src_tex: texture_2d<f32>;

fn aux_at(q: vec2<i32>) -> vec4<f32> {
    return bitcast<vec4<f32>>(textureLoad(aux_tex, q, 0));
}

fn src_at(q: vec2<i32>) -> f32 {
    if (bp.b.y > 0.5) {
        return aux_at(q).z;
    }
    return textureLoad(src_tex, q, 0).x;
}

// Separable, edge-aware Gaussian of constant eye-space radius: its screen radius is
// world_radius · focal_px / depth, so near shadows blur over more pixels than far ones.
@fragment
fn fs_blur(in: VsOut) -> @location(0) f32 {
    let px = vec2<i32>(in.pos.xy);
    let a = aux_at(px);
    let depth = a.y;
    let centre = src_at(px);
    if (!(depth > 0.0)) {
        return centre;
    }
    let r = min(bp.a.w * bp.a.z / depth, bp.b.x);
    if (r < 0.5) {
        return centre;
    }
    let dims = vec2<i32>(textureDimensions(aux_tex));
    var sum = 0.0;
    var wsum = 0.0;
    for (var k = -4; k <= 4; k = k + 1) {
        let off = bp.a.xy * (f32(k) * r / 4.0);
        let q = clamp(px + vec2<i32>(round(off)), vec2<i32>(0), dims - vec2<i32>(1));
        let d = aux_at(q).y;
        // Skip background and taps across a depth discontinuity (another surface).
        if (d > 0.0 && abs(d - depth) <= 0.05 * depth) {
            let t = f32(k) / 2.0;
            let w = exp(-0.5 * t * t);
            sum = sum + w * src_at(q);
            wsum = wsum + w;
        }
    }
    return sum / max(wsum, 1e-6);
}

struct CompositeParams {
    spot: mat4x4<f32>,
    // xyz = direction (travel) or position, w = 0 directional, 1 point, 2 spot
    light: vec4<f32>,
    // x = 1 when the shadow term comes from the blur target
    flags: vec4<f32>,
};

@group(0) @binding(0) var<uniform> cp: CompositeParams;
@group(0) @binding(1) var world_tex: texture_2d<u32>;
@group(0) @binding(2) var normal_tex: texture_2d<f32>;
@group(0) @binding(3) var albedo_tex: texture_2d<f32>;
@group(0) @binding(4) var aux2_tex: texture_2d<u32>;
@group(0) @binding(5) var vis_tex: texture_2d<f32>;

@fragment
fn fs_composite(in: VsOut) -> @location(0) vec4<f32> {
    let px = vec2<i32>(in.pos.xy);
    let w = bitcast<vec4<f32>>(textureLoad(world_tex, px, 0));
    if (w.w == 0.0) {
        let dims = vec2<f32>(textureDimensions(world_tex));
        let t = in.pos.y / dims.y;
        return vec4<f32>(mix(vec3<f32>(0.55, 0.70, 0.90), vec3<f32>(0.85, 0.90, 0.95), t), 1.0);
    }
    let n = textureLoad(normal_tex, px, 0).xyz;
    let albedo = textureLoad(albedo_tex, px, 0).rgb;
    var vis = bitcast<vec4<f32>>(textureLoad(aux2_tex, px, 0)).z;
    if (cp.flags.x > 0.5) {
        vis = textureLoad(vis_tex, px, 0).x;
    }
    var l: vec3<f32>;
    var spot = 1.0;
    if (cp.light.w < 0.5) {
        l = -normalize(cp.light.xyz);
    } else {
        l = normalize(cp.light.xyz - w.xyz);
        if (cp.light.w > 1.5) {
            let c = cp.spot * vec4<f32>(w.xyz, 1.0);
            if (!(c.w > 0.0 && abs(c.x) <= c.w && abs(c.y) <= c.w && c.z >= 0.0 && c.z <= c.w)) {
                spot = 0.0;
            }
        }
    }
    let diffuse = max(dot(n, l), 0.0) * vis * spot;
    return vec4<f32>(albedo * (0.28 + 0.72 * diffuse), 1.0);
}
