// Visible depth range: the least and greatest view depth over the pixels that see geometry
// (sample-distribution shadow maps [SDSM10]), reduced from the G-buffer's world positions.
//
// NOTE: a view depth in front of the camera is a non-negative f32, and the bit patterns of
// non-negative f32s order as u32s do, so atomicMin/atomicMax on the bits reduce the floats.

struct View {
    eye: vec4<f32>,
    forward: vec4<f32>,
    size: vec4<u32>,
}

@group(0) @binding(0) var world: texture_2d<u32>;
@group(0) @binding(1) var<uniform> view: View;
@group(0) @binding(2) var<storage, read_write> range: array<atomic<u32>, 2>;

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
    let z = bitcast<u32>(max(dot(p - view.eye.xyz, view.forward.xyz), 0.0));
    atomicMin(&range[0], z);
    atomicMax(&range[1], z);
}
