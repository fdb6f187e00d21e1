//! What the GPU draws, as plain vertex data built from core types. The layouts match the
//! WGSL structs in `shaders/` (`#[repr(C)]`, 16-byte aligned where WGSL requires it).
//!
//! Colours are display (sRGB-encoded) RGBA in 0..1; shading happens in that space, as egui's
//! own drawing does.

use bytemuck::{Pod, Zeroable};
use glam::{DVec2, DVec3, Vec3};

use crate::geom::{ParametricSurface, Surface};

/// Converts core positions (f64, mm) to view-local f32 positions relative to a fixed origin
/// near the part, so f32 rounding stays far below what a pixel shows.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Origin(pub DVec3);

impl Origin {
    /// A world point as local f32 coordinates.
    #[must_use]
    pub fn local(&self, p: DVec3) -> [f32; 3] {
        let d = p - self.0;
        [d.x as f32, d.y as f32, d.z as f32]
    }
    /// A world point as a local `Vec3`.
    #[must_use]
    pub fn local_vec(&self, p: DVec3) -> Vec3 {
        Vec3::from_array(self.local(p))
    }
}

/// A shaded triangle-mesh vertex.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct MeshVertex {
    /// Local position (mm).
    pub position: [f32; 3],
    /// Unit normal (the surface's oriented normal).
    pub normal: [f32; 3],
    /// RGBA.
    pub color: [f32; 4],
}

/// A triangle mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Vertices.
    pub vertices: Vec<MeshVertex>,
    /// Triangle indices, counter-clockwise.
    pub indices: Vec<u32>,
}

impl Mesh {
    /// Appends another mesh.
    pub fn extend(&mut self, other: &Mesh) {
        let base = self.vertices.len() as u32;
        self.vertices.extend_from_slice(&other.vertices);
        self.indices.extend(other.indices.iter().map(|i| i + base));
    }
}

/// One screen-space-wide line segment, drawn as a quad (its data repeated at each of the quad's
/// six vertices, see `Renderer3d::set_lines`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct LineSegment {
    /// Local start (mm).
    pub a: [f32; 3],
    /// Width on screen (physical pixels).
    pub width_px: f32,
    /// Local end (mm).
    pub b: [f32; 3],
    /// Pulls the segment toward the eye by this much normalised depth (0 to 1 over the
    /// depth range; 0 by default), so of lines that coincide in space (a program drawn over
    /// its design path) the one with the larger bias is drawn on top. Keeps `color` 16-byte
    /// aligned.
    pub depth_bias: f32,
    /// RGBA.
    pub color: [f32; 4],
}

impl LineSegment {
    /// A segment between two local points.
    #[must_use]
    pub fn new(a: [f32; 3], b: [f32; 3], width_px: f32, color: [f32; 4]) -> Self {
        Self { a, width_px, b, depth_bias: 0.0, color }
    }

    /// The same segment with a depth bias (see [`LineSegment::depth_bias`]).
    #[must_use]
    pub fn with_depth_bias(mut self, bias: f32) -> Self {
        self.depth_bias = bias;
        self
    }
}

/// A sphere (instance data): the ball cutters and small markers.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct SphereInstance {
    /// Local centre (mm).
    pub center: [f32; 3],
    /// Radius (mm).
    pub radius: f32,
    /// RGBA; alpha < 1 draws it translucent.
    pub color: [f32; 4],
}

/// Samples a surface on an `n × n` grid over its domain into a shaded mesh; with
/// `offset ≠ 0` the offset surface `r + offset·n` instead.
#[must_use]
pub fn tessellate(surface: &Surface, origin: Origin, n: usize, offset: f64, color: [f32; 4]) -> Mesh {
    let n = n.max(2);
    let d = surface.domain();
    let mut mesh = Mesh { vertices: Vec::with_capacity(n * n), indices: Vec::with_capacity(6 * (n - 1) * (n - 1)) };
    for i in 0..n {
        for j in 0..n {
            let u = d.u.min + d.u.width() * i as f64 / (n - 1) as f64;
            let v = d.v.min + d.v.width() * j as f64 / (n - 1) as f64;
            let s = surface.derivatives_at(DVec2::new(u, v));
            let normal = if s.normal == DVec3::ZERO { s.du.cross(s.dv).normalize_or_zero() } else { s.normal };
            let p = s.point + offset * normal;
            mesh.vertices.push(MeshVertex {
                position: origin.local(p),
                normal: [normal.x as f32, normal.y as f32, normal.z as f32],
                color,
            });
        }
    }
    for i in 0..n - 1 {
        for j in 0..n - 1 {
            let a = (i * n + j) as u32;
            let b = ((i + 1) * n + j) as u32;
            let c = ((i + 1) * n + j + 1) as u32;
            let e = (i * n + j + 1) as u32;
            mesh.indices.extend_from_slice(&[a, b, c, a, c, e]);
        }
    }
    mesh
}

/// Iso-parameter lines: `count` lines of constant u and of constant v across the domain,
/// each sampled at `samples` points, lifted `lift` mm along the normal so they sit on top of
/// the shaded surface.
#[must_use]
pub fn iso_lines(
    surface: &Surface,
    origin: Origin,
    count: usize,
    samples: usize,
    lift: f64,
    width_px: f32,
    color: [f32; 4],
) -> Vec<LineSegment> {
    let d = surface.domain();
    let mut out = Vec::new();
    let lifted = |uv: DVec2| {
        let s = surface.derivatives_at(uv);
        origin.local(s.point + lift * s.normal)
    };
    for k in 0..=count {
        let fu = d.u.min + d.u.width() * k as f64 / count as f64;
        let fv = d.v.min + d.v.width() * k as f64 / count as f64;
        for line in 0..2 {
            let mut prev: Option<[f32; 3]> = None;
            for m in 0..=samples {
                let t = m as f64 / samples as f64;
                let uv = if line == 0 {
                    DVec2::new(fu, d.v.min + d.v.width() * t)
                } else {
                    DVec2::new(d.u.min + d.u.width() * t, fv)
                };
                let p = lifted(uv);
                if let Some(q) = prev {
                    out.push(LineSegment::new(q, p, width_px, color));
                }
                prev = Some(p);
            }
        }
    }
    out
}

/// A polyline through world points.
#[must_use]
pub fn polyline(
    points: impl IntoIterator<Item = DVec3>,
    origin: Origin,
    width_px: f32,
    color: [f32; 4],
) -> Vec<LineSegment> {
    let mut out = Vec::new();
    let mut prev: Option<[f32; 3]> = None;
    for p in points {
        let q = origin.local(p);
        if let Some(a) = prev {
            out.push(LineSegment::new(a, q, width_px, color));
        }
        prev = Some(q);
    }
    out
}

/// A unit icosphere: vertices (also its normals) and triangle indices. `subdivisions` 2
/// gives 320 triangles.
#[must_use]
pub fn icosphere(subdivisions: u32) -> (Vec<[f32; 3]>, Vec<u32>) {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let mut verts: Vec<Vec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
    .collect();
    let mut tris: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        let mut cache = std::collections::BTreeMap::new();
        let mut mid = |a: u32, b: u32, verts: &mut Vec<Vec3>| -> u32 {
            let key = (a.min(b), a.max(b));
            *cache.entry(key).or_insert_with(|| {
                verts.push(((verts[a as usize] + verts[b as usize]) * 0.5).normalize());
                (verts.len() - 1) as u32
            })
        };
        let mut next = Vec::with_capacity(tris.len() * 4);
        for [a, b, c] in tris {
            let ab = mid(a, b, &mut verts);
            let bc = mid(b, c, &mut verts);
            let ca = mid(c, a, &mut verts);
            next.extend_from_slice(&[[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        tris = next;
    }
    (verts.iter().map(|v| v.to_array()).collect(), tris.into_iter().flatten().collect())
}

/// Bounding sphere (centre, radius) of world points; `None` for no points.
#[must_use]
pub fn bounds(points: impl IntoIterator<Item = DVec3>) -> Option<(DVec3, f64)> {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    let mut any = false;
    for p in points {
        if p.is_finite() {
            lo = lo.min(p);
            hi = hi.max(p);
            any = true;
        }
    }
    any.then(|| ((lo + hi) * 0.5, ((hi - lo) * 0.5).length()))
}
