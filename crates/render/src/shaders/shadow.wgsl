// Shadow pass: one layer per draw of this pipeline, selected by a dynamic uniform offset.

struct ShadowUniform {
    world_to_clip: mat4x4<f32>,
    // Linear depth d(p): mode 1 (directional): dot(lin_a.xyz, p) + lin_a.w;
    //                    mode 2 (point/spot):  length(p - lin_a.xyz) * lin_a.w.
    lin_a: vec4<f32>,
    // x = mode (0 = projective z), y = constant bias, z = slope-scale bias,
    // w = 1 for a map whose depth test is not the buffer's: stored as 1 − z, so that the buffer's
    // one comparison orders it right.
    lin_b: vec4<f32>,
};

@group(0) @binding(0) var<uniform> u: ShadowUniform;

struct VsOut {
    @builtin(position) pos: vec4<f32>,
    @location(0) world: vec3<f32>,
};

@vertex
fn vs(@location(0) p: vec3<f32>) -> VsOut {
    var o: VsOut;
    var c = u.world_to_clip * vec4<f32>(p, 1.0);
    if (u.lin_b.x > 0.5) {
        // Linear mode writes its own depth; keep the clip z mid-range so that only x, y clip.
        c.z = 0.5 * c.w;
    } else if (u.lin_b.w > 0.5) {
        // z' = 1 − z after the divide: clip z' = w − z.
        c.z = c.w - c.z;
    }
    o.pos = c;
    o.world = p;
    return o;
}

fn linear_depth(p: vec3<f32>) -> f32 {
    if (u.lin_b.x < 1.5) {
        return dot(u.lin_a.xyz, p) + u.lin_a.w;
    }
    return length(p - u.lin_a.xyz) * u.lin_a.w;
}

// Projective depth, saved for inspection: the rasterised z (before bias), as f32 bits (float
// colour targets are not renderable on every GL driver; 32-bit integer targets are).
@fragment
fn fs_viz(in: VsOut) -> @location(0) u32 {
    return bitcast<u32>(in.pos.z);
}

struct LinearOut {
    @builtin(frag_depth) depth: f32,
    @location(0) viz: u32,
};

// Linear depth with slope-scaled bias. The world position is interpolated perspective-correctly,
// so d is exact per fragment (interpolating d itself in map space would not be, for
// perspective maps). Derivatives here are per shadow-map texel.
fn biased_linear(in: VsOut) -> f32 {
    let d = linear_depth(in.world);
    let slope = max(abs(dpdx(d)), abs(dpdy(d)));
    return clamp(d + u.lin_b.y + u.lin_b.z * slope, 0.0, 1.0);
}

@fragment
fn fs_linear(in: VsOut) -> @builtin(frag_depth) f32 {
    return biased_linear(in);
}

@fragment
fn fs_linear_viz(in: VsOut) -> LinearOut {
    var o: LinearOut;
    o.depth = biased_linear(in);
    o.viz = bitcast<u32>(linear_depth(in.world));
    return o;
}
