//! A tile's header bounds from its vertices' Earth-centred positions: the bounding sphere and
//! the horizon occlusion point, as CesiumJS computes them (`BoundingSphere.fromPoints` in
//! spirit, `EllipsoidalOccluder.computeHorizonCullingPointFromVertices` exactly).

use crate::pyramid::globe::{WGS84_A, WGS84_F};

/// A sphere (centre, radius) holding every point: centred on the points' bounding box.
pub(crate) fn bounding_sphere(points: &[[f64; 3]]) -> ([f64; 3], f64) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let c: [f64; 3] = std::array::from_fn(|k| (lo[k] + hi[k]) / 2.0);
    let r = points.iter().map(|p| distance(*p, c)).fold(0.0, f64::max);
    (c, r)
}

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// The point in the ellipsoid-scaled frame (each axis divided by the ellipsoid's radius along
/// it) on the ray from the centre through `direction` (ECEF) beyond which every point is
/// below the horizon when the point is; `None` when no such point exists (a tile reaching
/// round more than a hemisphere).
pub(crate) fn horizon_occlusion_point(
    direction: [f64; 3],
    points: &[[f64; 3]],
) -> Option<[f64; 3]> {
    let b = WGS84_A * (1.0 - WGS84_F);
    let radii = [WGS84_A, WGS84_A, b];
    let scale = |p: [f64; 3]| std::array::from_fn::<f64, 3, _>(|k| p[k] / radii[k]);
    let norm = |p: [f64; 3]| (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
    let d = scale(direction);
    let len = norm(d);
    let d = d.map(|v| v / len);
    let mut most = 0.0f64;
    for &p in points {
        let s = scale(p);
        let m2 = s[0] * s[0] + s[1] * s[1] + s[2] * s[2];
        let m = m2.sqrt();
        let dir = s.map(|v| v / m);
        let (m2, m) = (m2.max(1.0), m.max(1.0));
        let cos_alpha = dir[0] * d[0] + dir[1] * d[1] + dir[2] * d[2];
        let cross = [
            dir[1] * d[2] - dir[2] * d[1],
            dir[2] * d[0] - dir[0] * d[2],
            dir[0] * d[1] - dir[1] * d[0],
        ];
        let sin_alpha = norm(cross);
        let cos_beta = 1.0 / m;
        let sin_beta = (m2 - 1.0).sqrt() * cos_beta;
        let denominator = cos_alpha * cos_beta - sin_alpha * sin_beta;
        if denominator <= 0.0 {
            return None;
        }
        most = most.max(1.0 / denominator);
    }
    Some(d.map(|v| v * most))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pyramid::globe::ecef;

    #[test]
    fn the_sphere_holds_every_point() {
        let points: Vec<[f64; 3]> = (0..50)
            .map(|i| ecef((i as f64 * 0.001).to_radians(), 0.6, i as f64))
            .collect();
        let (c, r) = bounding_sphere(&points);
        assert!(points.iter().all(|&p| distance(p, c) <= r + 1e-9));
    }

    #[test]
    fn the_occlusion_point_sees_every_point_above_the_horizon() {
        // Points on a small patch: the occlusion point lies outside the ellipsoid, along the
        // patch's direction, and every point is on the near side of its horizon plane.
        let points: Vec<[f64; 3]> = (0..100)
            .map(|i| {
                let lon = (-98.0 + (i % 10) as f64 * 0.01).to_radians();
                let lat = (33.0 + (i / 10) as f64 * 0.01).to_radians();
                ecef(lon, lat, 300.0 + i as f64)
            })
            .collect();
        let centre = ecef((-97.95f64).to_radians(), 33.05f64.to_radians(), 0.0);
        let h = horizon_occlusion_point(centre, &points).unwrap();
        let m = (h[0] * h[0] + h[1] * h[1] + h[2] * h[2]).sqrt();
        assert!(m > 1.0 && m < 1.001, "{m}");
        // A flat patch at height 0 puts the point just above the surface; a higher patch further.
        let low: Vec<[f64; 3]> = points.iter().map(|p| p.map(|v| v * 0.9999)).collect();
        let h_low = horizon_occlusion_point(centre, &low).unwrap();
        let m_low = (h_low[0].powi(2) + h_low[1].powi(2) + h_low[2].powi(2)).sqrt();
        assert!(m_low <= m);
    }
}
