// Copies the resolved off-screen image of a 3D view into egui's render pass.

@group(0) @binding(0) var image: texture_2d<f32>;
@group(0) @binding(1) var image_sampler: sampler;

struct Out {
    @builtin(position) pos: vec4<f32>,
    @location(0) uv: vec2<f32>,
};

// One triangle covering the viewport.
@vertex
fn vs_fullscreen(@builtin(vertex_index) vi: u32) -> Out {
    let x = f32((vi << 1u) & 2u);
    let y = f32(vi & 2u);
    var out: Out;
    out.pos = vec4<f32>(x * 2.0 - 1.0, 1.0 - y * 2.0, 0.0, 1.0);
    out.uv = vec2<f32>(x, y);
    return out;
}

// For a non-sRGB target (the web): the image is already display-encoded.
@fragment
fn fs_display(in: Out) -> @location(0) vec4<f32> {
    return textureSample(image, image_sampler, in.uv);
}

// For an sRGB target (native): decode, the hardware encodes again on write.
@fragment
fn fs_linear(in: Out) -> @location(0) vec4<f32> {
    let c = textureSample(image, image_sampler, in.uv);
    return vec4<f32>(pow(c.rgb, vec3<f32>(2.2)), c.a);
}
