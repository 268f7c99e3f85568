//! The orbit camera: yaw and pitch around a target point, a distance, and panning. Pure math so
//! it is tested without a GPU; serialisable so a share link can carry the view.

use glam::{Mat4, Vec3};
use serde::{Deserialize, Serialize};

/// An orbit camera looking at `target` from `distance` away, z up.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct OrbitCamera {
    /// Angle around the z axis, radians.
    pub yaw: f32,
    /// Angle above the xy plane, radians, within ±[`MAX_PITCH`].
    pub pitch: f32,
    /// Distance from the target, within [`MIN_DISTANCE`, `MAX_DISTANCE`].
    pub distance: f32,
    /// The point looked at.
    pub target: [f32; 3],
}

/// Pitch limit: just short of straight down or up, where the up vector degenerates.
pub(crate) const MAX_PITCH: f32 = 1.55;
/// Closest zoom.
pub(crate) const MIN_DISTANCE: f32 = 0.05;
/// Farthest zoom.
pub(crate) const MAX_DISTANCE: f32 = 20.0;
/// Vertical field of view, radians.
const FOV_Y: f32 = 0.8;

impl Default for OrbitCamera {
    /// The reset view: the unit-sized surface from the south-west, 35° above it.
    fn default() -> Self {
        Self {
            yaw: -2.2,
            pitch: 0.62,
            distance: 1.9,
            target: [0.0, 0.0, 0.0],
        }
    }
}

impl OrbitCamera {
    /// The eye position.
    pub(crate) fn eye(&self) -> Vec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        Vec3::from(self.target) + self.distance * Vec3::new(cp * cy, cp * sy, sp)
    }

    /// View-projection matrix for a viewport of aspect ratio `aspect` (width / height), with
    /// depth in 0..1 as wgpu expects.
    pub(crate) fn view_projection(&self, aspect: f32) -> Mat4 {
        let view = Mat4::look_at_rh(self.eye(), Vec3::from(self.target), Vec3::Z);
        let near = (self.distance * 0.01).max(1e-3);
        let proj = Mat4::perspective_rh(FOV_Y, aspect.max(1e-3), near, self.distance + 10.0);
        proj * view
    }

    /// Rotates by a drag of (`dx`, `dy`) CSS pixels.
    pub(crate) fn orbit(&mut self, dx: f32, dy: f32) {
        self.yaw -= dx * 0.008;
        self.pitch = (self.pitch + dy * 0.008).clamp(-MAX_PITCH, MAX_PITCH);
    }

    /// Zooms by `factor` (> 1 moves away), clamped to the distance limits.
    pub(crate) fn zoom(&mut self, factor: f32) {
        if factor.is_finite() && factor > 0.0 {
            self.distance = (self.distance * factor).clamp(MIN_DISTANCE, MAX_DISTANCE);
        }
    }

    /// Moves the target by a drag of (`dx`, `dy`) CSS pixels on a viewport `height` pixels tall,
    /// so the surface follows the pointer.
    pub(crate) fn pan(&mut self, dx: f32, dy: f32, height: f32) {
        let eye = self.eye();
        let forward = (Vec3::from(self.target) - eye).normalize();
        let right = forward.cross(Vec3::Z).normalize();
        let up = right.cross(forward);
        let per_pixel = 2.0 * self.distance * (FOV_Y / 2.0).tan() / height.max(1.0);
        let moved = Vec3::from(self.target) + (-dx * right + dy * up) * per_pixel;
        self.target = moved.to_array();
    }
}
