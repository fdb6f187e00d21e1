// The 3D view's off-screen pass: lit meshes, instanced spheres, screen-space-wide lines.
// Colours are display-space RGBA; shading happens in that space (as egui's own drawing).

struct Frame {
    // clip_from_local: perspective × view, local = relative to the scene origin (mm).
    clip_from_local: mat4x4<f32>,
    // xyz: eye position (local mm).
    eye: vec4<f32>,
    // x, y: viewport size in physical pixels; z: 1 to hide the back (non-cutter) side of
    // surfaces, 0 to show it darkened; w: unused.
    viewport: vec4<f32>,
};

@group(0) @binding(0) var<uniform> frame: Frame;

struct Shaded {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
    @location(1) color: vec4<f32>,
    @location(2) to_eye: vec3<f32>,
};

// Headlight shading. The side the normal points to (the cutter's side) is lit in full; the
// back side is drawn darker so the cutter side is always recognisable.
fn shade(normal: vec3<f32>, to_eye: vec3<f32>, color: vec4<f32>) -> vec4<f32> {
    let n = normalize(normal);
    let e = normalize(to_eye);
    let ndl = dot(n, e);
    let facing = abs(ndl);
    let h = normalize(e + vec3<f32>(0.0, 0.0, 0.35));
    let spec = pow(max(abs(dot(n, h)), 0.0), 48.0) * 0.22;
    var rgb = color.rgb * (0.32 + 0.68 * facing) + vec3<f32>(spec);
    if (ndl < 0.0) {
        rgb = rgb * 0.5;
    }
    return vec4<f32>(min(rgb, vec3<f32>(1.0)), color.a);
}

@vertex
fn vs_mesh(
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
) -> Shaded {
    var out: Shaded;
    out.clip = frame.clip_from_local * vec4<f32>(position, 1.0);
    out.normal = normal;
    out.color = color;
    out.to_eye = frame.eye.xyz - position;
    return out;
}

@vertex
fn vs_sphere(
    @location(0) unit: vec3<f32>,
    @location(1) center_radius: vec4<f32>,
    @location(2) color: vec4<f32>,
) -> Shaded {
    var out: Shaded;
    let p = center_radius.xyz + unit * center_radius.w;
    out.clip = frame.clip_from_local * vec4<f32>(p, 1.0);
    out.normal = unit;
    out.color = color;
    out.to_eye = frame.eye.xyz - p;
    return out;
}

@fragment
fn fs_shaded(in: Shaded) -> @location(0) vec4<f32> {
    if (frame.viewport.z > 0.5 && dot(in.normal, in.to_eye) < 0.0) {
        discard;
    }
    return shade(in.normal, in.to_eye, in.color);
}

// Spheres are closed: never hide their back.
@fragment
fn fs_sphere(in: Shaded) -> @location(0) vec4<f32> {
    return shade(in.normal, in.to_eye, in.color);
}

struct LineOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) color: vec4<f32>,
};

// One segment = 6 vertices (two triangles) expanded in screen space to `width` pixels, with
// the ends extended by half a width so consecutive segments join without gaps. The segment's
// data is stored once per vertex (not instanced: see `Renderer3d::set_lines`), so the corner
// is the vertex index modulo 6.
@vertex
fn vs_line(
    @builtin(vertex_index) vi: u32,
    @location(0) a_width: vec4<f32>,
    @location(1) b_pad: vec4<f32>,
    @location(2) color: vec4<f32>,
) -> LineOut {
    var corners = array<vec2<f32>, 6>(
        vec2<f32>(0.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(0.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(0.0, 1.0),
    );
    let corner = corners[vi % 6u];
    let ca = frame.clip_from_local * vec4<f32>(a_width.xyz, 1.0);
    let cb = frame.clip_from_local * vec4<f32>(b_pad.xyz, 1.0);
    let half_px = frame.viewport.xy * 0.5;
    let sa = ca.xy / max(ca.w, 1e-5) * half_px;
    let sb = cb.xy / max(cb.w, 1e-5) * half_px;
    var dir = sb - sa;
    let len = length(dir);
    if (len > 1e-6) {
        dir = dir / len;
    } else {
        dir = vec2<f32>(1.0, 0.0);
    }
    let nrm = vec2<f32>(-dir.y, dir.x);
    var c = ca;
    if (corner.x > 0.5) {
        c = cb;
    }
    let width = a_width.w;
    let offset_px = nrm * corner.y * width * 0.5 + dir * (corner.x * 2.0 - 1.0) * width * 0.5;
    var out: LineOut;
    // b_pad.w: depth bias toward the eye (normalised depth), 0 for most lines.
    out.clip = vec4<f32>(c.xy + offset_px / half_px * c.w, c.z - b_pad.w * c.w, c.w);
    out.color = color;
    return out;
}

@fragment
fn fs_line(in: LineOut) -> @location(0) vec4<f32> {
    return in.color;
}
