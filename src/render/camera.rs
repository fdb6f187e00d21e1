//! Orbit camera: turns around a target point, z up (the machine's convention), right-handed.

use glam::camera::rh::{proj::directx, view::look_at_mat4};
use glam::{Mat4, Vec3};

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
        let near = (self.distance * 0.01).max(1e-3);
        let far = self.distance * 20.0 + 1000.0;
        // WebGPU clip space: z in [0, 1], y up (glam's DirectX/WebGPU convention).
        directx::perspective(self.fov_y, aspect.max(1e-3), near, far) * look_at_mat4(self.eye(), self.target, Vec3::Z)
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

    /// Millimetres covered by one point at the target's depth in a viewport `h` points high.
    #[must_use]
    pub fn mm_per_point(&self, h: f32) -> f32 {
        2.0 * self.distance * (self.fov_y * 0.5).tan() / h.max(1.0)
    }
}
