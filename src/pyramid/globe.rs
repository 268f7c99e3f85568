//! Where a georeferenced grid lies on the WGS84 ellipsoid: UTM and longitude/latitude map
//! coordinates to Earth-centred, Earth-fixed (ECEF) positions, and the local east-north-up
//! frame a tileset's root transform places on the globe.
//!
//! The UTM inverse is Krüger's series to sixth order in the third flattening (Karney 2011,
//! "Transverse Mercator with an accuracy of a few nanometers"), good to well under a millimetre
//! inside a zone; heights are taken as heights above the ellipsoid (no geoid model).

use crate::heightfield::{Georeference, Heightfield, Placement};

/// WGS84 semi-major axis, metres.
pub(super) const WGS84_A: f64 = 6_378_137.0;
/// WGS84 flattening.
pub(super) const WGS84_F: f64 = 1.0 / 298.257_223_563;
/// UTM's scale on the central meridian.
const UTM_K0: f64 = 0.9996;
/// UTM's false easting, metres.
const UTM_FALSE_EASTING: f64 = 500_000.0;
/// UTM's false northing in the southern hemisphere, metres.
const UTM_FALSE_NORTHING_SOUTH: f64 = 10_000_000.0;

/// A map coordinate system the pyramid can place on the globe.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MapSystem {
    /// EPSG:4326: x = longitude, y = latitude, in degrees.
    LonLat,
    /// WGS84 / UTM: x = easting, y = northing, in metres (EPSG:326zz north, 327zz south).
    Utm {
        /// Zone 1 to 60.
        zone: u8,
        /// True for the southern hemisphere's false northing.
        south: bool,
    },
}

impl MapSystem {
    /// The system an EPSG code names, if it is one of those supported.
    pub(crate) fn from_epsg(code: u16) -> Option<Self> {
        match code {
            4326 => Some(Self::LonLat),
            32601..=32660 => Some(Self::Utm {
                zone: (code - 32600) as u8,
                south: false,
            }),
            32701..=32760 => Some(Self::Utm {
                zone: (code - 32700) as u8,
                south: true,
            }),
            _ => None,
        }
    }

    /// Longitude and latitude in radians of map point (`x`, `y`).
    pub fn to_lon_lat(&self, x: f64, y: f64) -> (f64, f64) {
        match *self {
            Self::LonLat => (x.to_radians(), y.to_radians()),
            Self::Utm { zone, south } => {
                let northing = if south {
                    y - UTM_FALSE_NORTHING_SOUTH
                } else {
                    y
                };
                let central = (f64::from(zone) * 6.0 - 183.0).to_radians();
                transverse_mercator_inverse(x - UTM_FALSE_EASTING, northing, central)
            }
        }
    }
}

impl std::fmt::Display for MapSystem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Self::LonLat => write!(f, "EPSG:4326 (WGS84 longitude, latitude)"),
            Self::Utm { zone, south } => write!(
                f,
                "EPSG:{} (WGS84 / UTM zone {zone}{})",
                if south { 32700 } else { 32600 } + u16::from(zone),
                if south { 'S' } else { 'N' }
            ),
        }
    }
}

/// The ellipsoid's third flattening n = f / (2 − f) and squared eccentricity e².
fn shape() -> (f64, f64) {
    (WGS84_F / (2.0 - WGS84_F), WGS84_F * (2.0 - WGS84_F))
}

/// The rectifying radius of WGS84 and the coefficients β₁…β₆ of the series from the rectifying
/// to the conformal sphere (Karney 2011, eq. 36), sixth order in n.
fn series() -> (f64, [f64; 6]) {
    let (n, _) = shape();
    let n2 = n * n;
    let n3 = n2 * n;
    let n4 = n3 * n;
    let n5 = n4 * n;
    let n6 = n5 * n;
    let radius = WGS84_A / (1.0 + n) * (1.0 + n2 / 4.0 + n4 / 64.0 + n6 / 256.0);
    let beta = [
        n / 2.0 - 2.0 * n2 / 3.0 + 37.0 * n3 / 96.0 - n4 / 360.0 - 81.0 * n5 / 512.0
            + 96_199.0 * n6 / 604_800.0,
        n2 / 48.0 + n3 / 15.0 - 437.0 * n4 / 1440.0 + 46.0 * n5 / 105.0
            - 1_118_711.0 * n6 / 3_870_720.0,
        17.0 * n3 / 480.0 - 37.0 * n4 / 840.0 - 209.0 * n5 / 4480.0 + 5569.0 * n6 / 90_720.0,
        4397.0 * n4 / 161_280.0 - 11.0 * n5 / 504.0 - 830_251.0 * n6 / 7_257_600.0,
        4583.0 * n5 / 161_280.0 - 108_847.0 * n6 / 3_991_680.0,
        20_648_693.0 * n6 / 638_668_800.0,
    ];
    (radius, beta)
}

/// Longitude and latitude (radians) of a UTM-scaled transverse Mercator point, `x` east and
/// `y` north of the origin on central meridian `central` (radians).
fn transverse_mercator_inverse(x: f64, y: f64, central: f64) -> (f64, f64) {
    let (_, e2) = shape();
    let (radius, beta) = series();
    let xi = y / (UTM_K0 * radius);
    let eta = x / (UTM_K0 * radius);
    // ζ' = ζ − Σ βⱼ sin(2jζ) for complex ζ = ξ + iη, summed by Clenshaw's recurrence so that
    // one complex sine and cosine of 2ζ serve every term.
    let (s, c) = (2.0 * xi).sin_cos();
    let (sh, ch) = ((2.0 * eta).sinh(), (2.0 * eta).cosh());
    let sin2 = (s * ch, c * sh);
    let cos2 = (c * ch, -s * sh);
    let twice_cos = (2.0 * cos2.0, 2.0 * cos2.1);
    let (mut y1, mut y2) = ((0.0, 0.0), (0.0, 0.0));
    for b in beta.iter().rev() {
        let next = (
            twice_cos.0 * y1.0 - twice_cos.1 * y1.1 - y2.0 + b,
            twice_cos.0 * y1.1 + twice_cos.1 * y1.0 - y2.1,
        );
        y2 = y1;
        y1 = next;
    }
    let sum = (sin2.0 * y1.0 - sin2.1 * y1.1, sin2.0 * y1.1 + sin2.1 * y1.0);
    let (xi1, eta1) = (xi - sum.0, eta - sum.1);
    let conformal_tan = xi1.sin() / (eta1.sinh().powi(2) + xi1.cos().powi(2)).sqrt();
    let lon = central + eta1.sinh().atan2(xi1.cos());
    (lon, latitude_from_conformal(conformal_tan, e2).atan())
}

/// tan φ from the tangent of the conformal latitude, by Newton's method (Karney 2011, eq. 19–21).
fn latitude_from_conformal(conformal_tan: f64, e2: f64) -> f64 {
    let e = e2.sqrt();
    let mut tau = conformal_tan;
    for _ in 0..8 {
        let root = (1.0 + tau * tau).sqrt();
        let sigma = (e * (e * tau / root).atanh()).sinh();
        let conformal = tau * (1.0 + sigma * sigma).sqrt() - sigma * root;
        let slope = (1.0 - e2) * (1.0 + conformal * conformal).sqrt() * root
            / (1.0 + (1.0 - e2) * tau * tau);
        let step = (conformal_tan - conformal) / slope;
        tau += step;
        // Newton converges quadratically: after a step this small, tau is good to the last bit.
        if step.abs() < 1.5e-9 * tau.abs().max(1.0) {
            break;
        }
    }
    tau
}

/// The ECEF position (metres) of longitude `lon`, latitude `lat` (radians) at `height` metres
/// above the WGS84 ellipsoid.
pub fn ecef(lon: f64, lat: f64, height: f64) -> [f64; 3] {
    let (_, e2) = shape();
    let (sin_lat, cos_lat) = lat.sin_cos();
    let (sin_lon, cos_lon) = lon.sin_cos();
    let normal = WGS84_A / (1.0 - e2 * sin_lat * sin_lat).sqrt();
    [
        (normal + height) * cos_lat * cos_lon,
        (normal + height) * cos_lat * sin_lon,
        (normal * (1.0 - e2) + height) * sin_lat,
    ]
}

/// The frame a pyramid's positions are written in.
#[derive(Clone, Debug, PartialEq)]
pub enum Frame {
    /// The input's own coordinates, unplaced.
    Local,
    /// East-north-up metres around `origin` (ECEF) on the globe, for map system `system`.
    Globe {
        /// The map system the grid's x and y are in.
        system: MapSystem,
        /// ECEF of the frame's origin.
        origin: [f64; 3],
        /// East, north and up unit vectors in ECEF.
        axes: [[f64; 3]; 3],
    },
}

impl Frame {
    /// The east-north-up frame at longitude `lon`, latitude `lat` (radians) and `height`.
    pub(crate) fn east_north_up(system: MapSystem, lon: f64, lat: f64, height: f64) -> Self {
        let (sin_lat, cos_lat) = lat.sin_cos();
        let (sin_lon, cos_lon) = lon.sin_cos();
        Self::Globe {
            system,
            origin: ecef(lon, lat, height),
            axes: [
                [-sin_lon, cos_lon, 0.0],
                [-sin_lat * cos_lon, -sin_lat * sin_lon, cos_lat],
                [cos_lat * cos_lon, cos_lat * sin_lon, sin_lat],
            ],
        }
    }

    /// The frame for `hf`'s grid, and why it is local when it is: a plain height field whose
    /// GeoTIFF names a supported system (see `MapSystem::from_epsg`) is placed on the globe
    /// with its centre as the origin; every other input stays in its own coordinates.
    pub fn of(hf: &Heightfield) -> (Self, Option<String>) {
        let Some(geo) = hf.georeference() else {
            return (Self::Local, None);
        };
        let Some(system) = system_of(geo) else {
            let why = match geo.epsg {
                Some(code) => format!(
                    "its coordinate system EPSG:{code} is not one the pyramid places on the globe (EPSG:4326 and WGS84 UTM zones 32601-32660, 32701-32760)"
                ),
                None => "the GeoTIFF names no EPSG coordinate system (GeoKeys 2048/3072)".into(),
            };
            return (Self::Local, Some(why));
        };
        if *hf.placement() != Placement::Grid {
            return (
                Self::Local,
                Some("the grid is not in its map's plane".into()),
            );
        }
        let [ox, oy] = hf.origin();
        let [sx, sy] = hf.spacing();
        let cx = ox + sx * (hf.width() - 1) as f64 / 2.0;
        let cy = oy + sy * (hf.height() - 1) as f64 / 2.0;
        let (lo, hi) = hf.z_range();
        let (lon, lat) = system.to_lon_lat(cx, cy);
        (Self::east_north_up(system, lon, lat, (lo + hi) / 2.0), None)
    }

    /// A world position (the input's coordinates: map x, map y, height) in this frame.
    pub fn place(&self, world: [f64; 3]) -> [f64; 3] {
        match self {
            Self::Local => world,
            Self::Globe {
                system,
                origin,
                axes,
            } => {
                let (lon, lat) = system.to_lon_lat(world[0], world[1]);
                let p = ecef(lon, lat, world[2]);
                let d = [p[0] - origin[0], p[1] - origin[1], p[2] - origin[2]];
                axes.map(|a| a[0] * d[0] + a[1] * d[1] + a[2] * d[2])
            }
        }
    }

    /// The column-major 4×4 matrix from this frame to ECEF, `None` for a local frame.
    pub fn transform(&self) -> Option<[f64; 16]> {
        match self {
            Self::Local => None,
            Self::Globe { origin, axes, .. } => {
                let [e, n, u] = axes;
                Some([
                    e[0], e[1], e[2], 0.0, n[0], n[1], n[2], 0.0, u[0], u[1], u[2], 0.0, origin[0],
                    origin[1], origin[2], 1.0,
                ])
            }
        }
    }
}

/// The supported map system a GeoTIFF's georeferencing names, if any.
fn system_of(geo: &Georeference) -> Option<MapSystem> {
    geo.pixel_scale?;
    geo.tiepoint?;
    MapSystem::from_epsg(geo.epsg?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_on_the_central_meridian_at_the_equator_is_exact() {
        // Zone 31's central meridian is 3° E; easting 500 000 m, northing 0 is (3° E, 0°).
        let (lon, lat) = MapSystem::Utm {
            zone: 31,
            south: false,
        }
        .to_lon_lat(500_000.0, 0.0);
        assert!((lon.to_degrees() - 3.0).abs() < 1e-12);
        assert!(lat.abs() < 1e-15);
        let p = ecef(lon, lat, 0.0);
        let want = [
            WGS84_A * 3f64.to_radians().cos(),
            WGS84_A * 3f64.to_radians().sin(),
            0.0,
        ];
        for k in 0..3 {
            assert!((p[k] - want[k]).abs() < 1e-6, "{p:?} vs {want:?}");
        }
    }

    #[test]
    fn the_south_false_northing_mirrors_the_north() {
        let north = MapSystem::Utm {
            zone: 33,
            south: false,
        }
        .to_lon_lat(612_345.0, 3_000_000.0);
        let south = MapSystem::Utm {
            zone: 33,
            south: true,
        }
        .to_lon_lat(612_345.0, 7_000_000.0);
        assert!((north.0 - south.0).abs() < 1e-14);
        assert!((north.1 + south.1).abs() < 1e-14);
    }

    #[test]
    fn the_up_axis_is_the_ellipsoid_normal_and_the_frame_is_orthonormal() {
        let frame = Frame::east_north_up(MapSystem::LonLat, 0.3, 0.7, 0.0);
        let Frame::Globe { axes, .. } = &frame else {
            unreachable!()
        };
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        for i in 0..3 {
            for j in 0..3 {
                let want = if i == j { 1.0 } else { 0.0 };
                assert!((dot(axes[i], axes[j]) - want).abs() < 1e-15);
            }
        }
        // A point 100 m above the origin is 100 m up in the frame.
        let up = frame.place([0.3f64.to_degrees(), 0.7f64.to_degrees(), 100.0]);
        assert!(up[0].abs() < 1e-6 && up[1].abs() < 1e-6 && (up[2] - 100.0).abs() < 1e-6);
    }

    #[test]
    fn only_wgs84_geographic_and_utm_codes_are_placed() {
        assert_eq!(MapSystem::from_epsg(4326), Some(MapSystem::LonLat));
        for code in [4326, 32614, 32760] {
            let system = MapSystem::from_epsg(code).unwrap();
            assert!(system.to_string().starts_with(&format!("EPSG:{code} ")));
        }
        assert_eq!(
            MapSystem::from_epsg(32614),
            Some(MapSystem::Utm {
                zone: 14,
                south: false
            })
        );
        assert_eq!(
            MapSystem::from_epsg(32760),
            Some(MapSystem::Utm {
                zone: 60,
                south: true
            })
        );
        for code in [2193, 32600, 32661, 32700, 26914, 3857] {
            assert_eq!(MapSystem::from_epsg(code), None, "EPSG:{code}");
        }
    }
}
