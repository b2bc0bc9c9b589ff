// Visible depth range: the least and greatest view depth over the pixels that see geometry
// (sample-distribution shadow maps [SDSM10]), reduced from the G-buffer's world positions; and,
// where asked for, the receiver pixels' bounds and greatest view depth in each of 16 slices of
// the view, apart for each world axis their surface normal lies closest to (the visible
// receiver boxes).
//
// NOTE: a view depth in front of the camera is a non-negative f32, and the bit patterns of
// non-negative f32s order as u32s do, so atomicMin/atomicMax on the bits reduce the floats.
// World coordinates have either sign: `ordered` maps every f32 to a u32 of the same order
// (negatives' bits inverted, positives' sign bit set), and the reader maps it back.

struct View {
    eye: vec4<f32>,
    forward: vec4<f32>,
    // x, y: the image's size; z: 1 where the receiver slices are asked for.
    size: vec4<u32>,
    // The 15 view depths between the slices, ascending (the 16th lane unused).
    planes: array<vec4<f32>, 4>,
}

// Per slice: min x, y, z, max x, y, z, greatest depth, as `ordered` words; the slices of
// pixels facing x, then y, then z.
const SLICE_WORDS: u32 = 7u;
const SLICES: u32 = 16u;

@group(0) @binding(0) var world: texture_2d<u32>;
@group(0) @binding(1) var<uniform> view: View;
@group(0) @binding(2) var<storage, read_write> range: array<atomic<u32>, 2>;
@group(0) @binding(3) var<storage, read_write> slices: array<atomic<u32>, 336>;
@group(0) @binding(4) var normals: texture_2d<f32>;

fn ordered(x: f32) -> u32 {
    let b = bitcast<u32>(x);
    return select(b | 0x80000000u, ~b, (b >> 31u) == 1u);
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= view.size.x || id.y >= view.size.y) {
        return;
    }
    let t = textureLoad(world, vec2<i32>(id.xy), 0);
    // w = 0: background.
    if (t.w == 0u) {
        return;
    }
    let p = bitcast<vec3<f32>>(t.xyz);
    let depth = dot(p - view.eye.xyz, view.forward.xyz);
    let z = bitcast<u32>(max(depth, 0.0));
    atomicMin(&range[0], z);
    atomicMax(&range[1], z);
    // w = 1: a receiver.
    if (view.size.z == 0u || bitcast<f32>(t.w) != 1.0) {
        return;
    }
    // The slice is the number of planes at or before the depth.
    var k = 0u;
    for (var i = 0u; i < 15u; i++) {
        k += select(0u, 1u, view.planes[i / 4u][i % 4u] <= depth);
    }
    // The axis the normal lies closest to: the largest |n_i|, the first of equals.
    let n = abs(textureLoad(normals, vec2<i32>(id.xy), 0).xyz);
    let axis = select(select(2u, 1u, n.y >= n.z), 0u, n.x >= n.y && n.x >= n.z);
    let base = (axis * SLICES + k) * SLICE_WORDS;
    for (var a = 0u; a < 3u; a++) {
        atomicMin(&slices[base + a], ordered(p[a]));
        atomicMax(&slices[base + 3u + a], ordered(p[a]));
    }
    atomicMax(&slices[base + 6u], ordered(depth));
}
