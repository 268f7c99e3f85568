//! What the two renderers (WebGPU in [`super::gpu`], WebGL2 in [`super::webgl`]) share: how a
//! layer is drawn, the light and the background, so both draw the same picture.

/// How a layer is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Style {
    /// Opaque shaded triangles.
    Fill,
    /// Lines (index pairs).
    Lines,
    /// Translucent triangles drawn after the opaque ones.
    Translucent,
}

/// The direction of the light the fill is shaded by (both faces lit alike).
pub(super) const LIGHT: [f32; 3] = [0.3, -0.5, 0.8];

/// The view's background colour.
pub(super) const BACKGROUND: wgpu::Color = wgpu::Color {
    r: 0.93,
    g: 0.94,
    b: 0.96,
    a: 1.0,
};
