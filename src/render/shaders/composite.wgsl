// Copies the resolved off-screen image of a 3D view into egui's render pass.

@group(0) @binding(0) var image: texture_2d<f32>;

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

// The image's texel under this fragment. The image has the view's size in pixels and the
// viewport is the view, so a fragment's centre falls on a texel's centre, where a filtered
// sample returns that texel alone: reading it directly gives the same picture and spares a
// CPU rasteriser (SwiftShader) the four fetches and the blend of a bilinear sample at every
// pixel of the view (docs/speed.md, round 8).
fn texel(uv: vec2<f32>) -> vec4<f32> {
    let size = textureDimensions(image);
    let p = min(vec2<u32>(max(uv * vec2<f32>(size), vec2<f32>(0.0))), size - vec2<u32>(1u));
    return textureLoad(image, p, 0);
}

// For a non-sRGB target (the web): the image is already display-encoded.
@fragment
fn fs_display(in: Out) -> @location(0) vec4<f32> {
    return texel(in.uv);
}

// For an sRGB target (native): decode, the hardware encodes again on write.
@fragment
fn fs_linear(in: Out) -> @location(0) vec4<f32> {
    let c = texel(in.uv);
    return vec4<f32>(pow(c.rgb, vec3<f32>(2.2)), c.a);
}
