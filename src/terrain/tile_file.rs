//! One quantized-mesh-1.0 `.terrain` tile: the 88-byte header, the zig-zag-delta vertex data,
//! the high-water-mark index data, the four edge index lists and the extensions (oct-encoded
//! normals, water mask, metadata), all little-endian, and its decoding (to check the encoding
//! against the spec by round trips).

use super::codec::{high_water_mark, un_high_water_mark, unzigzag_deltas, zigzag_deltas};

/// Extension ids of quantized-mesh-1.0.
const NORMALS: u8 = 1;
const WATER_MASK: u8 = 2;
const METADATA: u8 = 4;

/// The largest quantized coordinate: u, v and heights run over 0..=32767.
pub(crate) const QUANTIZED_MAX: u16 = 32767;

/// The header: where the tile is and what bounds it, all in Earth-centred, Earth-fixed metres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Header {
    /// The tile's centre.
    pub center: [f64; 3],
    /// The lowest and highest heights over the ellipsoid in the tile.
    pub min_height: f32,
    pub max_height: f32,
    /// A sphere holding every vertex: centre and radius.
    pub sphere_center: [f64; 3],
    pub sphere_radius: f64,
    /// The horizon occlusion point, in the ellipsoid-scaled frame.
    pub horizon_occlusion: [f64; 3],
}

/// The water mask: one byte for a tile all land (0) or all water (255), else 256 × 256 bytes,
/// row by row from the north-west corner.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum WaterMask {
    Uniform(u8),
    Grid(Vec<u8>),
}

/// A tile's content. Vertices are numbered in the order the triangles first use them (the
/// high-water-mark coding needs it; [`TerrainTile::encode`] checks it).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct TerrainTile {
    pub header: Header,
    /// Per vertex: u (west to east), v (south to north) and height, each 0..=32767.
    pub u: Vec<u16>,
    pub v: Vec<u16>,
    pub height: Vec<u16>,
    /// Triangles, counter-clockwise seen from above.
    pub triangles: Vec<[u32; 3]>,
    /// The vertices on the west, south, east and north edges.
    pub edges: [Vec<u32>; 4],
    /// Oct-encoded unit normals (ECEF), one per vertex.
    pub normals: Option<Vec<[u8; 2]>>,
    pub water: Option<WaterMask>,
    /// The metadata extension's JSON.
    pub metadata: Option<String>,
}

fn put_f64(out: &mut Vec<u8>, v: f64) {
    out.extend_from_slice(&v.to_le_bytes());
}

impl TerrainTile {
    /// The tile's bytes (before gzip).
    pub(super) fn encode(&self) -> Vec<u8> {
        let n = self.u.len();
        assert!(self.v.len() == n && self.height.len() == n);
        let mut out = Vec::with_capacity(88 + n * 8 + self.triangles.len() * 6);
        let h = &self.header;
        for v in h.center {
            put_f64(&mut out, v);
        }
        out.extend_from_slice(&h.min_height.to_le_bytes());
        out.extend_from_slice(&h.max_height.to_le_bytes());
        for v in h.sphere_center {
            put_f64(&mut out, v);
        }
        put_f64(&mut out, h.sphere_radius);
        for v in h.horizon_occlusion {
            put_f64(&mut out, v);
        }
        out.extend_from_slice(&(n as u32).to_le_bytes());
        for list in [&self.u, &self.v, &self.height] {
            for c in zigzag_deltas(list) {
                out.extend_from_slice(&c.to_le_bytes());
            }
        }
        let wide = n > 65536;
        let put_index = |out: &mut Vec<u8>, i: u32| {
            if wide {
                out.extend_from_slice(&i.to_le_bytes());
            } else {
                out.extend_from_slice(&(i as u16).to_le_bytes());
            }
        };
        // The index data is aligned to its index size.
        let align = if wide { 4 } else { 2 };
        while out.len() % align != 0 {
            out.push(0);
        }
        out.extend_from_slice(&(self.triangles.len() as u32).to_le_bytes());
        let flat: Vec<u32> = self.triangles.iter().flatten().copied().collect();
        for c in high_water_mark(&flat) {
            assert!(
                c as usize <= n,
                "vertices must be numbered in first-use order"
            );
            put_index(&mut out, c);
        }
        for edge in &self.edges {
            out.extend_from_slice(&(edge.len() as u32).to_le_bytes());
            for &i in edge {
                put_index(&mut out, i);
            }
        }
        let mut extension = |id: u8, data: &[u8]| {
            out.push(id);
            out.extend_from_slice(&(data.len() as u32).to_le_bytes());
            out.extend_from_slice(data);
        };
        if let Some(normals) = &self.normals {
            extension(NORMALS, &normals.concat());
        }
        match &self.water {
            Some(WaterMask::Uniform(b)) => extension(WATER_MASK, &[*b]),
            Some(WaterMask::Grid(g)) => extension(WATER_MASK, g),
            None => {}
        }
        if let Some(json) = &self.metadata {
            let mut data = (json.len() as u32).to_le_bytes().to_vec();
            data.extend_from_slice(json.as_bytes());
            extension(METADATA, &data);
        }
        out
    }

    /// Reads a tile's bytes (before gzip); the error says where the data ends too soon.
    pub(super) fn decode(bytes: &[u8]) -> Result<Self, String> {
        let mut r = Reader { bytes, at: 0 };
        let center = [r.f64("header")?, r.f64("header")?, r.f64("header")?];
        let min_height = f32::from_le_bytes(r.array("header")?);
        let max_height = f32::from_le_bytes(r.array("header")?);
        let sphere_center = [r.f64("header")?, r.f64("header")?, r.f64("header")?];
        let sphere_radius = r.f64("header")?;
        let horizon_occlusion = [r.f64("header")?, r.f64("header")?, r.f64("header")?];
        let n = r.u32("vertex count")? as usize;
        let mut lists = Vec::new();
        for what in ["u", "v", "heights"] {
            let codes: Vec<u16> = r
                .take(2 * n, what)?
                .chunks_exact(2)
                .map(|c| u16::from_le_bytes([c[0], c[1]]))
                .collect();
            lists.push(unzigzag_deltas(&codes));
        }
        let wide = n > 65536;
        let size = if wide { 4 } else { 2 };
        let pad = (size - r.at % size) % size;
        r.take(pad, "padding")?;
        let count = r.u32("triangle count")? as usize;
        let flat = un_high_water_mark(&r.indices(3 * count, wide, "indices")?);
        let triangles = flat.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
        let mut edges: [Vec<u32>; 4] = Default::default();
        for edge in &mut edges {
            let k = r.u32("edge indices")? as usize;
            *edge = r.indices(k, wide, "edge indices")?;
        }
        let (mut normals, mut water, mut metadata) = (None, None, None);
        while r.at < bytes.len() {
            let id = r.take(1, "extension header")?[0];
            let len = r.u32("extension header")? as usize;
            let data = r.take(len, "extension")?;
            match id {
                NORMALS => normals = Some(data.chunks_exact(2).map(|c| [c[0], c[1]]).collect()),
                WATER_MASK if len == 1 => water = Some(WaterMask::Uniform(data[0])),
                WATER_MASK => water = Some(WaterMask::Grid(data.to_vec())),
                METADATA => {
                    let mut m = Reader { bytes: data, at: 0 };
                    let k = m.u32("metadata")? as usize;
                    let text = m.take(k, "metadata")?;
                    metadata = Some(String::from_utf8(text.to_vec()).map_err(|e| e.to_string())?);
                }
                other => return Err(format!("unknown extension {other}")),
            }
        }
        let height = lists.pop().expect("three lists");
        let v = lists.pop().expect("three lists");
        let u = lists.pop().expect("three lists");
        Ok(Self {
            header: Header {
                center,
                min_height,
                max_height,
                sphere_center,
                sphere_radius,
                horizon_occlusion,
            },
            u,
            v,
            height,
            triangles,
            edges,
            normals,
            water,
            metadata,
        })
    }
}

/// Little-endian reading with the place the data ends too soon in its error.
struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, len: usize, what: &str) -> Result<&'a [u8], String> {
        let slice = self.bytes.get(self.at..self.at + len).ok_or_else(|| {
            format!(
                "the tile ends at byte {} inside its {what}",
                self.bytes.len()
            )
        })?;
        self.at += len;
        Ok(slice)
    }

    fn array<const N: usize>(&mut self, what: &str) -> Result<[u8; N], String> {
        Ok(self.take(N, what)?.try_into().expect("N bytes"))
    }

    fn f64(&mut self, what: &str) -> Result<f64, String> {
        Ok(f64::from_le_bytes(self.array(what)?))
    }

    fn u32(&mut self, what: &str) -> Result<u32, String> {
        Ok(u32::from_le_bytes(self.array(what)?))
    }

    fn indices(&mut self, k: usize, wide: bool, what: &str) -> Result<Vec<u32>, String> {
        let size = if wide { 4 } else { 2 };
        Ok(self
            .take(k * size, what)?
            .chunks_exact(size)
            .map(|c| {
                if wide {
                    u32::from_le_bytes([c[0], c[1], c[2], c[3]])
                } else {
                    u32::from(u16::from_le_bytes([c[0], c[1]]))
                }
            })
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tile() -> TerrainTile {
        TerrainTile {
            header: Header {
                center: [1.0, 2.0, 3.0],
                min_height: -5.5,
                max_height: 120.25,
                sphere_center: [1.5, 2.5, 3.5],
                sphere_radius: 1000.0,
                horizon_occlusion: [0.1, 0.2, 0.3],
            },
            // A square with a centre point: first-use order 0, 1, 2, then 3, then 4.
            u: vec![0, 32767, 16000, 32767, 0],
            v: vec![0, 0, 16000, 32767, 32767],
            height: vec![0, 10, 32767, 20, 5],
            triangles: vec![[0, 1, 2], [1, 3, 2], [3, 4, 2], [4, 0, 2]],
            edges: [vec![0, 4], vec![0, 1], vec![1, 3], vec![4, 3]],
            normals: Some(vec![[128, 128]; 5]),
            water: Some(WaterMask::Uniform(255)),
            metadata: Some(r#"{"available":[[{"startX":0,"startY":0,"endX":1,"endY":1}]]}"#.into()),
        }
    }

    #[test]
    fn the_header_and_vertex_data_sit_where_the_spec_puts_them() {
        let t = tile();
        let bytes = t.encode();
        assert_eq!(f64::from_le_bytes(bytes[0..8].try_into().unwrap()), 1.0);
        assert_eq!(f32::from_le_bytes(bytes[24..28].try_into().unwrap()), -5.5);
        assert_eq!(
            f32::from_le_bytes(bytes[28..32].try_into().unwrap()),
            120.25
        );
        assert_eq!(
            f64::from_le_bytes(bytes[56..64].try_into().unwrap()),
            1000.0
        );
        assert_eq!(f64::from_le_bytes(bytes[80..88].try_into().unwrap()), 0.3);
        assert_eq!(u32::from_le_bytes(bytes[88..92].try_into().unwrap()), 5);
        // u: 0, then +32767 zig-zagged is 65534.
        assert_eq!(u16::from_le_bytes(bytes[92..94].try_into().unwrap()), 0);
        assert_eq!(u16::from_le_bytes(bytes[94..96].try_into().unwrap()), 65534);
        // Vertex data ends at 92 + 30 = 122, already 2-aligned: the triangle count follows.
        assert_eq!(u32::from_le_bytes(bytes[122..126].try_into().unwrap()), 4);
        // First triangle 0, 1, 2 is written 0, 0, 0.
        assert_eq!(&bytes[126..132], &[0, 0, 0, 0, 0, 0]);
    }

    #[test]
    fn a_tile_round_trips_through_its_bytes() {
        let t = tile();
        assert_eq!(TerrainTile::decode(&t.encode()).unwrap(), t);
        let mut grid = tile();
        grid.water = Some(WaterMask::Grid(
            (0..65536).map(|i| (i % 251) as u8).collect(),
        ));
        grid.normals = None;
        grid.metadata = None;
        assert_eq!(TerrainTile::decode(&grid.encode()).unwrap(), grid);
    }

    #[test]
    fn more_than_65536_vertices_take_32_bit_indices() {
        let n = 70_000u32;
        let mut t = tile();
        t.u = (0..n).map(|i| (i % 32768) as u16).collect();
        t.v = (0..n).map(|i| (i / 32768) as u16).collect();
        t.height = vec![0; n as usize];
        t.normals = None;
        t.triangles = (0..n / 3).map(|k| [3 * k, 3 * k + 1, 3 * k + 2]).collect();
        t.edges = [vec![0], vec![1], vec![n - 1], vec![]];
        let bytes = t.encode();
        // 92 + 6n bytes of vertices, padded to 4.
        let start = (92 + 6 * n as usize).div_ceil(4) * 4;
        assert_eq!(
            u32::from_le_bytes(bytes[start..start + 4].try_into().unwrap()),
            n / 3
        );
        assert_eq!(TerrainTile::decode(&bytes).unwrap(), t);
    }

    #[test]
    fn a_truncated_tile_says_where_it_ends() {
        let bytes = tile().encode();
        let err = TerrainTile::decode(&bytes[..100]).unwrap_err();
        assert!(err.contains("inside its u"), "{err}");
    }
}
