//! Orbit camera: turns around a target point, z up (the machine's convention), right-handed.

use glam::camera::rh::{proj::directx, view::look_at_mat4};
use glam::{Mat4, Vec2, Vec3};

/// Nearest clipping distance of the perspective (scene units, mm), so a camera zoomed onto its
/// target keeps a positive near plane.
const MIN_NEAR: f32 = 1e-3;
/// Smallest aspect ratio (width / height) the projection is built with (a view of no width).
const MIN_ASPECT: f32 = 1e-3;

/// An orbit camera. Angles in radians, lengths in mm, in the view's local frame (relative to
/// the scene origin chosen by [`super::geometry::Origin`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrbitCamera {
    /// Point looked at.
    pub target: Vec3,
    /// Turn about +z from +x (rad).
    pub yaw: f32,
    /// Elevation above the xy-plane (rad), within ±89°.
    pub pitch: f32,
    /// Eye-to-target distance (mm).
    pub distance: f32,
    /// Vertical field of view (rad).
    pub fov_y: f32,
}

impl Default for OrbitCamera {
    fn default() -> Self {
        Self { target: Vec3::ZERO, yaw: -0.9, pitch: 0.55, distance: 200.0, fov_y: 35f32.to_radians() }
    }
}

impl OrbitCamera {
    /// Eye position.
    #[must_use]
    pub fn eye(&self) -> Vec3 {
        let dir = Vec3::new(self.pitch.cos() * self.yaw.cos(), self.pitch.cos() * self.yaw.sin(), self.pitch.sin());
        self.target + dir * self.distance
    }

    /// `clip_from_world` for a viewport of the given aspect ratio (depth 0..1, as wgpu).
    #[must_use]
    pub fn clip_from_world(&self, aspect: f32) -> Mat4 {
        let near = (self.distance * 0.01).max(MIN_NEAR);
        let far = self.distance * 20.0 + 1000.0;
        // WebGPU clip space: z in [0, 1], y up (glam's DirectX/WebGPU convention).
        directx::perspective(self.fov_y, aspect.max(MIN_ASPECT), near, far)
            * look_at_mat4(self.eye(), self.target, Vec3::Z)
    }

    /// Turns the camera by screen-space drag (points).
    pub fn orbit(&mut self, dx: f32, dy: f32) {
        self.yaw -= dx * 0.008;
        self.pitch = (self.pitch + dy * 0.008).clamp(-1.55, 1.55);
    }

    /// Moves the target in the view plane by a drag of (dx, dy) points in a viewport `h`
    /// points high, so the part follows the pointer.
    pub fn pan(&mut self, dx: f32, dy: f32, h: f32) {
        let eye = self.eye();
        let forward = (self.target - eye).normalize();
        let right = forward.cross(Vec3::Z).normalize_or_zero();
        let up = right.cross(forward);
        let mm_per_point = 2.0 * self.distance * (self.fov_y * 0.5).tan() / h.max(1.0);
        self.target += (-dx * right + dy * up) * mm_per_point;
    }

    /// Zooms by a factor (> 1 moves closer).
    pub fn zoom(&mut self, factor: f32) {
        self.distance = (self.distance / factor).clamp(0.05, 1.0e5);
    }

    /// Frames a bounding sphere (centre, radius in mm) keeping the angles.
    pub fn fit(&mut self, center: Vec3, radius: f32) {
        self.target = center;
        self.distance = (radius.max(0.1) / (self.fov_y * 0.5).sin()) * 1.1;
    }

    /// Where a local point appears, in normalised device coordinates (x right, y up, both
    /// −1 … 1 inside a viewport of the given aspect ratio); `None` behind the eye.
    #[must_use]
    pub fn project(&self, aspect: f32, p: Vec3) -> Option<Vec2> {
        let q = self.clip_from_world(aspect) * p.extend(1.0);
        if q.w <= f32::EPSILON * self.distance.max(1.0) {
            return None;
        }
        Some(Vec2::new(q.x / q.w, q.y / q.w))
    }

    /// The ray through a point of the viewport given in normalised device coordinates (as
    /// [`Self::project`] gives them): its start on the near plane and its unit direction away
    /// from the eye, local coordinates (mm). Every point that projects to `ndc` lies on it.
    #[must_use]
    pub fn ray(&self, aspect: f32, ndc: Vec2) -> (Vec3, Vec3) {
        let inv = self.clip_from_world(aspect).inverse();
        let near = inv.project_point3(Vec3::new(ndc.x, ndc.y, 0.0));
        let far = inv.project_point3(Vec3::new(ndc.x, ndc.y, 1.0));
        let dir = (far - near).normalize_or(self.target - self.eye());
        (near, dir.normalize_or(Vec3::NEG_Z))
    }

    /// Normalised device coordinates of a pointer at `(x, y)` points from the top-left corner
    /// of a viewport `w` × `h` points.
    #[must_use]
    pub fn ndc_of(x: f32, y: f32, w: f32, h: f32) -> Vec2 {
        Vec2::new(2.0 * x / w.max(1.0) - 1.0, 1.0 - 2.0 * y / h.max(1.0))
    }

    /// Millimetres covered by one point at the target's depth in a viewport `h` points high.
    #[must_use]
    pub fn mm_per_point(&self, h: f32) -> f32 {
        2.0 * self.distance * (self.fov_y * 0.5).tan() / h.max(1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points in front of the camera project to a pixel whose ray passes through them (within
    /// f32 rounding), and the ray through the viewport's centre is the line of sight.
    #[test]
    fn the_ray_through_a_projected_point_passes_through_it() {
        let cams = [
            OrbitCamera::default(),
            OrbitCamera { target: Vec3::new(10.0, -4.0, 3.0), yaw: 2.1, pitch: -0.4, distance: 80.0, fov_y: 0.5 },
            OrbitCamera { target: Vec3::new(0.0, 0.0, 50.0), yaw: -2.9, pitch: 1.3, distance: 15.0, fov_y: 1.1 },
        ];
        let mut checked = 0;
        for cam in cams {
            for aspect in [0.6f32, 1.0, 1.9] {
                // A grid of points around the target, within the view's depth.
                for i in 0..5 {
                    for j in 0..5 {
                        for k in 0..3 {
                            let span = 0.3 * cam.distance;
                            let p = cam.target
                                + Vec3::new(
                                    span * (i as f32 / 4.0 - 0.5),
                                    span * (j as f32 / 4.0 - 0.5),
                                    span * (k as f32 / 2.0 - 0.5),
                                );
                            let Some(ndc) = cam.project(aspect, p) else { continue };
                            if ndc.x.abs() > 1.0 || ndc.y.abs() > 1.0 {
                                continue;
                            }
                            let (o, d) = cam.ray(aspect, ndc);
                            assert!((d.length() - 1.0).abs() < 1e-5);
                            let t = (p - o).dot(d);
                            assert!(t > 0.0, "the point lies ahead of the near plane");
                            let miss = (o + t * d - p).length();
                            assert!(miss < 1e-4 * cam.distance, "miss {miss} mm at {p} ({aspect})");
                            checked += 1;
                        }
                    }
                }
                let (o, d) = cam.ray(aspect, Vec2::ZERO);
                let sight = (cam.target - cam.eye()).normalize();
                assert!(d.dot(sight) > 1.0 - 1e-6 && (o - cam.eye()).cross(sight).length() < 1e-3 * cam.distance);
            }
        }
        assert!(checked > 100, "{checked}");
        // Pointer → NDC: the corners and the centre.
        assert_eq!(OrbitCamera::ndc_of(0.0, 0.0, 200.0, 100.0), Vec2::new(-1.0, 1.0));
        assert_eq!(OrbitCamera::ndc_of(200.0, 100.0, 200.0, 100.0), Vec2::new(1.0, -1.0));
        assert_eq!(OrbitCamera::ndc_of(100.0, 50.0, 200.0, 100.0), Vec2::ZERO);
    }
}
