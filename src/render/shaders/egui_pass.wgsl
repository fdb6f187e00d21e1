// egui's own triangles (text, rectangles, lines, circles) drawn with the least a fragment can
// cost (`render::egui_pass`): vertex colour times the font atlas's sample, premultiplied alpha
// blended by the pipeline — what egui-wgpu's shader computes with dithering and predictable
// texture filtering off, without their branches (a CPU rasteriser pays for a branch even when
// it is not taken). `fs_main_linear_framebuffer` is for an sRGB target (the hardware encodes
// on write), as egui-wgpu picks.

struct Locals {
    // The screen's size in points (egui's vertex positions are in points).
    screen_size_pt: vec2<f32>,
    pad: vec2<f32>,
};
@group(0) @binding(0) var<uniform> locals: Locals;

@group(1) @binding(0) var atlas: texture_2d<f32>;
@group(1) @binding(1) var atlas_sampler: sampler;

struct VertexOutput {
    @location(0) uv: vec2<f32>,
    // gamma-encoded 0–1, premultiplied alpha
    @location(1) colour: vec4<f32>,
    @builtin(position) position: vec4<f32>,
};

@vertex
fn vs_main(
    @location(0) pos_pt: vec2<f32>,
    @location(1) uv: vec2<f32>,
    @location(2) colour: u32,
) -> VertexOutput {
    var out: VertexOutput;
    out.uv = uv;
    // The same arithmetic as egui-wgpu's `unpack_color`, so the same values reach the blend.
    out.colour = vec4<f32>(
        f32(colour & 255u),
        f32((colour >> 8u) & 255u),
        f32((colour >> 16u) & 255u),
        f32((colour >> 24u) & 255u),
    ) / 255.0;
    out.position = vec4<f32>(
        2.0 * pos_pt.x / locals.screen_size_pt.x - 1.0,
        1.0 - 2.0 * pos_pt.y / locals.screen_size_pt.y,
        0.0,
        1.0,
    );
    return out;
}

// 0–1 linear from 0–1 sRGB gamma (IEC 61966-2-1), as egui-wgpu decodes.
fn linear_from_gamma(srgb: vec3<f32>) -> vec3<f32> {
    let lower = srgb / vec3<f32>(12.92);
    let higher = pow((srgb + vec3<f32>(0.055)) / vec3<f32>(1.055), vec3<f32>(2.4));
    return select(higher, lower, srgb < vec3<f32>(0.04045));
}

@fragment
fn fs_main_gamma_framebuffer(in: VertexOutput) -> @location(0) vec4<f32> {
    return in.colour * textureSample(atlas, atlas_sampler, in.uv);
}

@fragment
fn fs_main_linear_framebuffer(in: VertexOutput) -> @location(0) vec4<f32> {
    let c = in.colour * textureSample(atlas, atlas_sampler, in.uv);
    return vec4<f32>(linear_from_gamma(c.rgb), c.a);
}
