// Fills the callback's viewport (a large opaque rectangle of the UI) with one colour: no
// texture, no blending. `FILL_RGB` is replaced by the colour (three floats, already in the
// target's encoding) when the pipeline of that colour is created (`render::flat_fill`).

// One triangle covering the viewport (egui-wgpu sets it to the callback's rectangle and the
// scissor to its clip rectangle).
@vertex
fn vs_fullscreen(@builtin(vertex_index) vi: u32) -> @builtin(position) vec4<f32> {
    let x = f32((vi << 1u) & 2u);
    let y = f32(vi & 2u);
    return vec4<f32>(x * 2.0 - 1.0, 1.0 - y * 2.0, 0.0, 1.0);
}

@fragment
fn fs_flat() -> @location(0) vec4<f32> {
    return vec4<f32>(FILL_RGB, 1.0);
}
