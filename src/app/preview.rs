//! The import dialog's preview image of a parsed grid.

/// Grey levels of a `width` × `height` grid: height mapped to 40..=255, lightened or darkened by
/// the slope towards the upper left so relief shows. Returns RGBA bytes, row-major.
pub(crate) fn preview_pixels(width: usize, height: usize, z: &[f64]) -> Vec<u8> {
    let (lo, hi) = z
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let span = if hi > lo { hi - lo } else { 1.0 };
    let mut out = Vec::with_capacity(width * height * 4);
    for y in 0..height {
        for x in 0..width {
            let v = z[y * width + x];
            let left = z[y * width + x.saturating_sub(1)];
            let up = z[y.saturating_sub(1) * width + x];
            let shade = ((v - left) + (v - up)) / span * 4.0 * 255.0;
            let g = (40.0 + (v - lo) / span * 215.0 + shade).clamp(0.0, 255.0) as u8;
            out.extend_from_slice(&[g, g, g, 255]);
        }
    }
    out
}
