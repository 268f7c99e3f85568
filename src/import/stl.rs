//! STL meshes, binary and ASCII.
//!
//! Binary: an 80-byte header, a little-endian u32 triangle count, then 50 bytes per triangle
//! (normal, three corners as f32, a 2-byte attribute). A file is binary when its size is exactly
//! what its count says — even when its header begins with "solid", as some exporters write;
//! otherwise a file beginning with "solid" is ASCII. Corners shared by several triangles become
//! one vertex (exact equality), in order of first appearance.
//!
//! Hand-written rather than the `stl_io` crate: stl_io decides ASCII by the "solid " prefix
//! alone, so it misreads such binary files, and it does not check the count against the size.

use super::error::ImportError;
use super::triangle_mesh::{MAX_TRIANGLES, TriangleMesh, check_counts};
use std::collections::HashMap;

const FORMAT: &str = "STL";
const HEADER: usize = 84;
const RECORD: usize = 50;

fn malformed(message: impl Into<String>) -> ImportError {
    ImportError::Malformed {
        format: FORMAT,
        message: message.into(),
    }
}

/// Builds an indexed mesh from triangle corners, merging bit-identical corners.
struct Indexer {
    mesh: TriangleMesh,
    seen: HashMap<[u64; 3], u32>,
}

impl Indexer {
    fn new(triangles: usize) -> Self {
        Self {
            mesh: TriangleMesh {
                vertices: Vec::with_capacity(triangles.min(1 << 20)),
                triangles: Vec::with_capacity(triangles.min(1 << 20)),
            },
            seen: HashMap::new(),
        }
    }
    fn add(&mut self, corners: [[f64; 3]; 3]) -> Result<(), ImportError> {
        let mut ids = [0u32; 3];
        for (k, p) in corners.into_iter().enumerate() {
            if p.iter().any(|c| !c.is_finite()) {
                return Err(ImportError::NotFinite {
                    format: FORMAT,
                    message: format!(
                        "triangle {} has the corner {p:?}",
                        self.mesh.triangles.len()
                    ),
                });
            }
            // +0.0 for -0.0 so that the two zeros are one vertex.
            let key = p.map(|c| (c + 0.0).to_bits());
            let next = self.mesh.vertices.len() as u32;
            ids[k] = *self.seen.entry(key).or_insert(next);
            if ids[k] == next {
                self.mesh.vertices.push(p);
            }
        }
        if self.mesh.triangles.len() >= MAX_TRIANGLES {
            return Err(ImportError::OverLimit {
                format: FORMAT,
                what: "triangles",
                claimed: self.mesh.triangles.len() as u64 + 1,
                limit: MAX_TRIANGLES as u64,
            });
        }
        self.mesh.triangles.push(ids);
        Ok(())
    }
}

/// Parses binary or ASCII STL into a validated mesh. Never panics: every bad input is an
/// [`ImportError`].
pub fn parse(bytes: &[u8]) -> Result<TriangleMesh, ImportError> {
    let claimed = (bytes.len() >= HEADER)
        .then(|| u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64);
    let binary_size = claimed.map(|n| HEADER as u64 + RECORD as u64 * n);
    let looks_ascii = bytes.trim_ascii_start().starts_with(b"solid");
    let mesh = if binary_size == Some(bytes.len() as u64) || !looks_ascii {
        parse_binary(bytes)?
    } else {
        parse_ascii(bytes)?
    };
    mesh.validate(FORMAT)?;
    Ok(mesh)
}

fn parse_binary(bytes: &[u8]) -> Result<TriangleMesh, ImportError> {
    if bytes.len() < HEADER {
        return Err(ImportError::Truncated {
            format: FORMAT,
            message: format!(
                "a binary STL has an {HEADER}-byte header, the file has {} bytes",
                bytes.len()
            ),
        });
    }
    let count = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64;
    check_counts(FORMAT, 0, count)?;
    let needed = HEADER as u64 + RECORD as u64 * count;
    let found = bytes.len() as u64;
    if found < needed {
        return Err(ImportError::Truncated {
            format: FORMAT,
            message: format!(
                "the header promises {count} triangles ({needed} bytes), the file has {found} bytes"
            ),
        });
    }
    if found > needed {
        return Err(ImportError::WrongCount {
            format: FORMAT,
            message: format!(
                "the header promises {count} triangles ({needed} bytes), but the file has {found} bytes"
            ),
        });
    }
    if count == 0 {
        return Err(ImportError::EmptyMesh { format: FORMAT });
    }
    let mut indexer = Indexer::new(count as usize);
    for record in bytes[HEADER..].chunks_exact(RECORD) {
        let f = |k: usize| {
            let o = 12 + 4 * k;
            f32::from_le_bytes([record[o], record[o + 1], record[o + 2], record[o + 3]]) as f64
        };
        indexer.add([[f(0), f(1), f(2)], [f(3), f(4), f(5)], [f(6), f(7), f(8)]])?;
    }
    Ok(indexer.mesh)
}

fn parse_ascii(bytes: &[u8]) -> Result<TriangleMesh, ImportError> {
    let text = std::str::from_utf8(bytes).map_err(|_| {
        malformed(
            "it begins with \"solid\" but is not text, and its size does not fit a binary STL",
        )
    })?;
    let mut indexer = Indexer::new(0);
    let mut corners: Vec<[f64; 3]> = Vec::with_capacity(3);
    let mut in_facet = false;
    let mut ended = false;
    for (number, line) in text.lines().enumerate() {
        let words: Vec<&str> = line.split_whitespace().collect();
        let at = |what: &str| malformed(format!("line {}: {what}: {line:?}", number + 1));
        match words.first().copied() {
            None => {}
            Some("solid") if number == 0 || ended => ended = false,
            Some("facet") => {
                if in_facet {
                    return Err(at("a facet inside a facet"));
                }
                in_facet = true;
                corners.clear();
            }
            Some("outer") | Some("endloop") => {}
            Some("vertex") => {
                if !in_facet || words.len() != 4 {
                    return Err(at("expected \"vertex x y z\" inside a facet"));
                }
                let mut p = [0.0; 3];
                for (k, w) in words[1..].iter().enumerate() {
                    p[k] = w
                        .parse::<f32>()
                        .map_err(|_| at("a coordinate is not a number"))?
                        .into();
                }
                corners.push(p);
            }
            Some("endfacet") => {
                if corners.len() != 3 {
                    return Err(ImportError::WrongCount {
                        format: FORMAT,
                        message: format!(
                            "line {}: a facet has {} vertices; it needs 3",
                            number + 1,
                            corners.len()
                        ),
                    });
                }
                indexer.add([corners[0], corners[1], corners[2]])?;
                in_facet = false;
            }
            Some("endsolid") => ended = true,
            Some(_) => return Err(at("not an ASCII STL line")),
        }
    }
    if in_facet || !ended {
        return Err(ImportError::Truncated {
            format: FORMAT,
            message: format!(
                "it ends {}without \"endsolid\"",
                if in_facet { "inside a facet, " } else { "" }
            ),
        });
    }
    if indexer.mesh.triangles.is_empty() {
        return Err(ImportError::EmptyMesh { format: FORMAT });
    }
    Ok(indexer.mesh)
}
