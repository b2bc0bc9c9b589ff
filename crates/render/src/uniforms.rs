//! The uniform blocks the passes share with their shaders, as `#[repr(C)]`
//! structs, and the shader sources with the crate's limits injected: one
//! definition of each, and a test that every struct's layout is the one
//! naga reads from the WGSL.

use crate::types::MAX_MAPS;

pub(crate) const SHADOW_WGSL: &str = include_str!("shaders/shadow.wgsl");
pub(crate) const POST_WGSL: &str = include_str!("shaders/post.wgsl");

/// The main pass's source, with `MAX_MAPS` defined from [`MAX_MAPS`].
pub(crate) fn scene_wgsl() -> String {
    format!("const MAX_MAPS: u32 = {MAX_MAPS}u;\n{}", include_str!("shaders/scene.wgsl"))
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct ShadowUniform {
    pub world_to_clip: [f32; 16],
    pub lin_a: [f32; 4],
    pub lin_b: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct MapInfo {
    pub world_to_clip: [f32; 16],
    pub split: [f32; 4],
    pub face: [f32; 4],
    pub size: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct FrameUniform {
    pub view_proj: [f32; 16],
    pub eye: [f32; 4],
    pub forward: [f32; 4],
    pub cam: [f32; 4],
    pub lin_a: [f32; 4],
    pub lin_b: [f32; 4],
    pub params: [f32; 4],
    pub params2: [f32; 4],
    pub maps: [MapInfo; MAX_MAPS],
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct BlurUniform {
    pub a: [f32; 4],
    pub b: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct CompositeUniform {
    pub spot: [f32; 16],
    pub light: [f32; 4],
    pub flags: [f32; 4],
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::mem::{offset_of, size_of};

    /// Size and member offsets of the WGSL struct `name` in `source`.
    fn layout(source: &str, name: &str) -> (u32, Vec<(String, u32)>) {
        let module = naga::front::wgsl::parse_str(source).unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
        let mut layouter = naga::proc::Layouter::default();
        layouter.update(module.to_ctx()).unwrap();
        let (handle, ty) = module.types.iter().find(|(_, t)| t.name.as_deref() == Some(name)).unwrap_or_else(|| panic!("no struct {name}"));
        let naga::TypeInner::Struct { members, .. } = &ty.inner else { panic!("{name} is not a struct") };
        let members = members.iter().map(|m| (m.name.clone().unwrap_or_default(), m.offset)).collect();
        (layouter[handle].size, members)
    }

    fn check(source: &str, name: &str, size: usize, members: &[(&str, usize)]) {
        let (wgsl_size, wgsl_members) = layout(source, name);
        assert_eq!(wgsl_size as usize, size, "{name}: WGSL size against the Rust struct's");
        let rust: Vec<(String, u32)> = members.iter().map(|(n, o)| (n.to_string(), *o as u32)).collect();
        assert_eq!(wgsl_members, rust, "{name}: members and offsets");
    }

    #[test]
    fn uniform_structs_have_the_shaders_layout() {
        let scene = scene_wgsl();
        check(
            SHADOW_WGSL,
            "ShadowUniform",
            size_of::<ShadowUniform>(),
            &[
                ("world_to_clip", offset_of!(ShadowUniform, world_to_clip)),
                ("lin_a", offset_of!(ShadowUniform, lin_a)),
                ("lin_b", offset_of!(ShadowUniform, lin_b)),
            ],
        );
        check(
            &scene,
            "MapInfo",
            size_of::<MapInfo>(),
            &[
                ("world_to_clip", offset_of!(MapInfo, world_to_clip)),
                ("split", offset_of!(MapInfo, split)),
                ("face", offset_of!(MapInfo, face)),
                ("size", offset_of!(MapInfo, size)),
            ],
        );
        check(
            &scene,
            "Frame",
            size_of::<FrameUniform>(),
            &[
                ("view_proj", offset_of!(FrameUniform, view_proj)),
                ("eye", offset_of!(FrameUniform, eye)),
                ("forward", offset_of!(FrameUniform, forward)),
                ("cam", offset_of!(FrameUniform, cam)),
                ("lin_a", offset_of!(FrameUniform, lin_a)),
                ("lin_b", offset_of!(FrameUniform, lin_b)),
                ("params", offset_of!(FrameUniform, params)),
                ("params2", offset_of!(FrameUniform, params2)),
                ("maps", offset_of!(FrameUniform, maps)),
            ],
        );
        check(POST_WGSL, "BlurParams", size_of::<BlurUniform>(), &[("a", offset_of!(BlurUniform, a)), ("b", offset_of!(BlurUniform, b))]);
        check(
            POST_WGSL,
            "CompositeParams",
            size_of::<CompositeUniform>(),
            &[
                ("spot", offset_of!(CompositeUniform, spot)),
                ("light", offset_of!(CompositeUniform, light)),
                ("flags", offset_of!(CompositeUniform, flags)),
            ],
        );
    }
}
