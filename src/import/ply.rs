//! PLY meshes: `ascii`, `binary_little_endian` and `binary_big_endian`.
//!
//! Reads the `vertex` element's `x`, `y`, `z` and the `face` element's `vertex_indices` (or
//! `vertex_index`) list; polygons are split into fans of triangles; other elements and properties
//! are skipped. Before anything is allocated, the header's counts are checked against
//! [`MAX_VERTICES`](super::triangle_mesh::MAX_VERTICES) / [`MAX_TRIANGLES`] and against the smallest number of bytes they need.
//! A `float` property is read as f32 and widened, so a PLY written from an f32 grid gives back
//! exactly the same values. An ASCII file has one element per line (as the format says).
//!
//! Hand-written rather than a crate: the maintained crate (`ply-rs-bw`) does not check claimed
//! counts against a limit and the file size, and a PLY header is simple enough to check fully here.

use super::error::ImportError;
use super::triangle_mesh::{MAX_TRIANGLES, TriangleMesh, check_counts};

const FORMAT: &str = "PLY";
/// The header must end within this many bytes (real headers are a few hundred).
const MAX_HEADER: usize = 1 << 16;

fn malformed(message: impl Into<String>) -> ImportError {
    ImportError::Malformed {
        format: FORMAT,
        message: message.into(),
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &str) -> Option<Self> {
        Some(match name {
            "char" | "int8" => Self::I8,
            "uchar" | "uint8" => Self::U8,
            "short" | "int16" => Self::I16,
            "ushort" | "uint16" => Self::U16,
            "int" | "int32" => Self::I32,
            "uint" | "uint32" => Self::U32,
            "float" | "float32" => Self::F32,
            "double" | "float64" => Self::F64,
            _ => return None,
        })
    }
    fn size(self) -> usize {
        match self {
            Self::I8 | Self::U8 => 1,
            Self::I16 | Self::U16 => 2,
            Self::I32 | Self::U32 | Self::F32 => 4,
            Self::F64 => 8,
        }
    }
    /// Range of an integer type; `None` for floats.
    fn int_range(self) -> Option<(i64, i64)> {
        Some(match self {
            Self::I8 => (i8::MIN.into(), i8::MAX.into()),
            Self::U8 => (0, u8::MAX.into()),
            Self::I16 => (i16::MIN.into(), i16::MAX.into()),
            Self::U16 => (0, u16::MAX.into()),
            Self::I32 => (i32::MIN.into(), i32::MAX.into()),
            Self::U32 => (0, u32::MAX.into()),
            Self::F32 | Self::F64 => return None,
        })
    }
}

#[derive(Clone, Copy, Debug)]
enum Kind {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

#[derive(Debug)]
struct Property {
    name: String,
    kind: Kind,
}

#[derive(Debug)]
struct Element {
    name: String,
    count: u64,
    properties: Vec<Property>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Encoding {
    Ascii,
    Binary { big_endian: bool },
}

/// The parsed header and the byte offset where the body starts.
fn parse_header(bytes: &[u8]) -> Result<(Encoding, Vec<Element>, usize), ImportError> {
    if !(bytes.starts_with(b"ply\n") || bytes.starts_with(b"ply\r\n")) {
        return Err(malformed("it does not start with the line \"ply\""));
    }
    let window = &bytes[..bytes.len().min(MAX_HEADER)];
    let end = find_header_end(window).ok_or_else(|| {
        if bytes.len() < MAX_HEADER {
            ImportError::Truncated {
                format: FORMAT,
                message: "the header has no end_header line".into(),
            }
        } else {
            malformed(format!(
                "no end_header line in the first {MAX_HEADER} bytes"
            ))
        }
    })?;
    let text =
        std::str::from_utf8(&bytes[..end]).map_err(|_| malformed("the header is not text"))?;
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    for (number, line) in text.lines().enumerate().skip(1) {
        let words: Vec<&str> = line.split_whitespace().collect();
        let at = |what: &str| malformed(format!("header line {}: {what}: {line:?}", number + 1));
        match words.as_slice() {
            [] | ["comment", ..] | ["obj_info", ..] | ["end_header"] => {}
            ["format", kind, _version] => {
                encoding = Some(match *kind {
                    "ascii" => Encoding::Ascii,
                    "binary_little_endian" => Encoding::Binary { big_endian: false },
                    "binary_big_endian" => Encoding::Binary { big_endian: true },
                    _ => return Err(at("unknown format")),
                });
            }
            ["element", name, count] => elements.push(Element {
                name: name.to_string(),
                count: count
                    .parse()
                    .map_err(|_| at("the element count is not a whole number"))?,
                properties: Vec::new(),
            }),
            ["property", "list", count, item, name] => {
                let element = elements
                    .last_mut()
                    .ok_or_else(|| at("property before any element"))?;
                let (Some(count), Some(item)) = (Scalar::parse(count), Scalar::parse(item)) else {
                    return Err(at("unknown property type"));
                };
                if count.int_range().is_none() {
                    return Err(at("a list count must have an integer type"));
                }
                element.properties.push(Property {
                    name: name.to_string(),
                    kind: Kind::List { count, item },
                });
            }
            ["property", kind, name] => {
                let element = elements
                    .last_mut()
                    .ok_or_else(|| at("property before any element"))?;
                let kind = Scalar::parse(kind).ok_or_else(|| at("unknown property type"))?;
                element.properties.push(Property {
                    name: name.to_string(),
                    kind: Kind::Scalar(kind),
                });
            }
            _ => return Err(at("not a PLY header line")),
        }
    }
    let encoding = encoding.ok_or_else(|| malformed("the header has no format line"))?;
    Ok((encoding, elements, end))
}

/// Offset just past the `end_header` line.
fn find_header_end(window: &[u8]) -> Option<usize> {
    let mut start = 0;
    for (i, &b) in window.iter().enumerate() {
        if b == b'\n' {
            if window[start..i].trim_ascii() == b"end_header" {
                return Some(i + 1);
            }
            start = i + 1;
        }
    }
    None
}

/// The body of the file, read one element instance at a time.
enum Body<'a> {
    Ascii {
        lines: std::iter::Peekable<std::str::Lines<'a>>,
        line_number: usize,
    },
    Binary {
        data: &'a [u8],
        pos: usize,
        big_endian: bool,
    },
}

/// Why an element instance could not be read.
enum ReadError {
    Truncated,
    /// ASCII: the line does not hold the values the element's properties need.
    Tokens {
        line: usize,
        message: String,
    },
    /// A value is out of its type's range or not a number.
    Value(String),
}

/// Reads `element`'s properties in order with `next` (which decodes one value of a type):
/// scalars into `scalars` (a list gives 0 there) and the items of the list at `wanted_list` into
/// `list`. Shared by the ASCII and binary bodies, which differ only in `next`.
fn read_properties(
    element: &Element,
    wanted_list: Option<usize>,
    scalars: &mut Vec<f64>,
    list: &mut Vec<f64>,
    mut next: impl FnMut(Scalar) -> Result<f64, ReadError>,
) -> Result<(), ReadError> {
    for (p, property) in element.properties.iter().enumerate() {
        match property.kind {
            Kind::Scalar(t) => scalars.push(next(t)?),
            Kind::List { count, item } => {
                scalars.push(0.0);
                let n = list_length(next(count)?)?;
                for _ in 0..n {
                    let v = next(item)?;
                    if wanted_list == Some(p) {
                        list.push(v);
                    }
                }
            }
        }
    }
    Ok(())
}

impl<'a> Body<'a> {
    /// Reads one instance of `element`: scalar values into `scalars` (by property position,
    /// lists give 0) and the items of the list at `wanted_list` into `list`.
    fn read(
        &mut self,
        element: &Element,
        scalars: &mut Vec<f64>,
        wanted_list: Option<usize>,
        list: &mut Vec<f64>,
    ) -> Result<(), ReadError> {
        scalars.clear();
        list.clear();
        match self {
            Body::Ascii { lines, line_number } => {
                let line = loop {
                    *line_number += 1;
                    match lines.next() {
                        None => return Err(ReadError::Truncated),
                        Some(l) if l.trim().is_empty() => continue,
                        Some(l) => break l,
                    }
                };
                let mut tokens = line.split_whitespace();
                let number = *line_number;
                // A short last line is where a cut file ends; a short line inside is a mismatch.
                let last = lines.clone().all(|l| l.trim().is_empty());
                let next = |t: Scalar| -> Result<f64, ReadError> {
                    let token = tokens.next().ok_or_else(|| {
                        if last {
                            ReadError::Truncated
                        } else {
                            ReadError::Tokens {
                                line: number,
                                message: format!("too few values for a {}", element.name),
                            }
                        }
                    })?;
                    parse_token(token, t)
                };
                read_properties(element, wanted_list, scalars, list, next)?;
                if tokens.next().is_some() {
                    return Err(ReadError::Tokens {
                        line: number,
                        message: format!("more values than a {} has", element.name),
                    });
                }
                Ok(())
            }
            Body::Binary {
                data,
                pos,
                big_endian,
            } => {
                let next = |t: Scalar| -> Result<f64, ReadError> {
                    let bytes = data
                        .get(*pos..*pos + t.size())
                        .ok_or(ReadError::Truncated)?;
                    *pos += t.size();
                    let v = decode(bytes, t, *big_endian);
                    Ok(v)
                };
                read_properties(element, wanted_list, scalars, list, next)?;
                Ok(())
            }
        }
    }

    /// Describes anything left after the last element, if there is any.
    fn leftover(&mut self) -> Option<String> {
        match self {
            Body::Ascii { lines, .. } => {
                let extra = lines.filter(|l| !l.trim().is_empty()).count();
                (extra > 0).then(|| format!("{extra} more non-empty lines"))
            }
            Body::Binary { data, pos, .. } => {
                let extra = data.len() - *pos;
                (extra > 0).then(|| format!("{extra} more bytes"))
            }
        }
    }
}

fn list_length(v: f64) -> Result<usize, ReadError> {
    if v < 0.0 {
        return Err(ReadError::Value(format!(
            "a list has a negative length {v}"
        )));
    }
    Ok(v as usize)
}

fn parse_token(token: &str, t: Scalar) -> Result<f64, ReadError> {
    let bad = || ReadError::Value(format!("{token:?} is not a valid {t:?} value"));
    match t.int_range() {
        Some((lo, hi)) => {
            let v: i64 = token.parse().map_err(|_| bad())?;
            if v < lo || v > hi {
                return Err(bad());
            }
            Ok(v as f64)
        }
        None if t == Scalar::F32 => token.parse::<f32>().map(f64::from).map_err(|_| bad()),
        None => token.parse::<f64>().map_err(|_| bad()),
    }
}

fn decode(b: &[u8], t: Scalar, big_endian: bool) -> f64 {
    macro_rules! num {
        ($ty:ty, $n:expr) => {{
            let mut a = [0u8; $n];
            a.copy_from_slice(b);
            if big_endian {
                <$ty>::from_be_bytes(a) as f64
            } else {
                <$ty>::from_le_bytes(a) as f64
            }
        }};
    }
    match t {
        Scalar::I8 => num!(i8, 1),
        Scalar::U8 => num!(u8, 1),
        Scalar::I16 => num!(i16, 2),
        Scalar::U16 => num!(u16, 2),
        Scalar::I32 => num!(i32, 4),
        Scalar::U32 => num!(u32, 4),
        Scalar::F32 => num!(f32, 4),
        Scalar::F64 => num!(f64, 8),
    }
}

/// The fewest bytes one instance of `element` can take in `encoding`.
fn min_bytes(element: &Element, encoding: Encoding) -> u64 {
    element
        .properties
        .iter()
        .map(|p| match (encoding, p.kind) {
            // A value and a separator ("0 ").
            (Encoding::Ascii, _) => 2,
            (Encoding::Binary { .. }, Kind::Scalar(t)) => t.size() as u64,
            (Encoding::Binary { .. }, Kind::List { count, .. }) => count.size() as u64,
        })
        .sum()
}

/// Parses a PLY file into a validated mesh. Never panics: every bad input is an [`ImportError`].
pub fn parse(bytes: &[u8]) -> Result<TriangleMesh, ImportError> {
    let (encoding, elements, body_start) = parse_header(bytes)?;
    let Layout {
        vertex_at,
        face_at,
        xyz,
        index_list,
    } = layout(&elements)?;
    let vertex_count = elements[vertex_at].count;
    let face_count = face_at.map_or(0, |f| elements[f].count);
    // Every element's claimed count against the bytes that are really there, before allocating.
    check_claimed_sizes(&elements, encoding, (bytes.len() - body_start) as u64)?;
    let mut body = body(bytes, body_start, encoding)?;
    let mut mesh = TriangleMesh {
        vertices: Vec::with_capacity(vertex_count as usize),
        triangles: Vec::with_capacity((face_count as usize).min(1 << 20)),
    };
    let (mut scalars, mut list) = (Vec::new(), Vec::new());
    for (e, element) in elements.iter().enumerate() {
        let wanted_list = if Some(e) == face_at { index_list } else { None };
        for i in 0..element.count {
            body.read(element, &mut scalars, wanted_list, &mut list)
                .map_err(|err| read_error(err, element, i))?;
            if e == vertex_at {
                mesh.vertices
                    .push([scalars[xyz[0]], scalars[xyz[1]], scalars[xyz[2]]]);
            } else if Some(e) == face_at {
                add_face(&mut mesh.triangles, &list, i, vertex_count)?;
            }
        }
    }
    if let Some(extra) = body.leftover() {
        return Err(ImportError::WrongCount {
            format: FORMAT,
            message: format!(
                "the header declares {vertex_count} vertices and {face_count} faces, but the file has {extra} after them"
            ),
        });
    }
    mesh.validate(FORMAT)?;
    Ok(mesh)
}

/// Where the mesh is among the header's elements: the vertex element and its x, y, z
/// properties, the face element (if any) and its index list.
struct Layout {
    vertex_at: usize,
    face_at: Option<usize>,
    xyz: Vec<usize>,
    index_list: Option<usize>,
}

/// Finds the [`Layout`] in the header's `elements`; an error when a part the mesh needs is
/// missing or the vertex and face counts are over the limits.
fn layout(elements: &[Element]) -> Result<Layout, ImportError> {
    let vertex_at = elements
        .iter()
        .position(|e| e.name == "vertex")
        .ok_or_else(|| malformed("the header declares no vertex element"))?;
    let face_at = elements.iter().position(|e| e.name == "face");
    let face_count = face_at.map_or(0, |f| elements[f].count);
    check_counts(FORMAT, elements[vertex_at].count, face_count)?;
    let xyz: Vec<usize> = ["x", "y", "z"]
        .iter()
        .map(|name| {
            elements[vertex_at]
                .properties
                .iter()
                .position(|p| p.name == *name && matches!(p.kind, Kind::Scalar(_)))
                .ok_or_else(|| {
                    malformed(format!("the vertex element has no scalar property {name}"))
                })
        })
        .collect::<Result<_, _>>()?;
    let index_list = match face_at {
        Some(f) => Some(
            elements[f]
                .properties
                .iter()
                .position(|p| {
                    (p.name == "vertex_indices" || p.name == "vertex_index")
                        && matches!(p.kind, Kind::List { .. })
                })
                .ok_or_else(|| malformed("the face element has no vertex_indices list"))?,
        ),
        None => None,
    };
    Ok(Layout {
        vertex_at,
        face_at,
        xyz,
        index_list,
    })
}

/// Refuses element counts over the limit, or whose instances need more than the `available`
/// bytes after the header.
fn check_claimed_sizes(
    elements: &[Element],
    encoding: Encoding,
    available: u64,
) -> Result<(), ImportError> {
    let mut needed: u64 = 0;
    for e in elements {
        if e.count > MAX_TRIANGLES as u64 {
            return Err(ImportError::OverLimit {
                format: FORMAT,
                what: "elements of one kind",
                claimed: e.count,
                limit: MAX_TRIANGLES as u64,
            });
        }
        needed = needed.saturating_add(e.count.saturating_mul(min_bytes(e, encoding)));
    }
    if needed > available {
        return Err(ImportError::Truncated {
            format: FORMAT,
            message: format!(
                "the header's element counts need at least {needed} bytes after the header, the file has {available}"
            ),
        });
    }
    Ok(())
}

/// The reader of the body that starts at `body_start`.
fn body(bytes: &[u8], body_start: usize, encoding: Encoding) -> Result<Body<'_>, ImportError> {
    Ok(match encoding {
        Encoding::Ascii => Body::Ascii {
            lines: std::str::from_utf8(&bytes[body_start..])
                .map_err(|_| malformed("an ASCII PLY body must be text"))?
                .lines()
                .peekable(),
            line_number: bytes[..body_start].iter().filter(|&&b| b == b'\n').count(),
        },
        Encoding::Binary { big_endian } => Body::Binary {
            data: &bytes[body_start..],
            pos: 0,
            big_endian,
        },
    })
}

/// The import error for a failed read of instance `i` of `element`.
fn read_error(err: ReadError, element: &Element, i: u64) -> ImportError {
    match err {
        ReadError::Truncated => ImportError::Truncated {
            format: FORMAT,
            message: format!("it ends at {} {i} of {}", element.name, element.count),
        },
        ReadError::Tokens { line, message } => ImportError::WrongCount {
            format: FORMAT,
            message: format!(
                "line {line}: {message} ({} {i}); does the header's count match the file?",
                element.name
            ),
        },
        ReadError::Value(message) => malformed(format!("{} {i}: {message}", element.name)),
    }
}

/// Appends face `i` (its vertex indices) as a fan of triangles.
fn add_face(
    triangles: &mut Vec<[u32; 3]>,
    indices: &[f64],
    i: u64,
    vertex_count: u64,
) -> Result<(), ImportError> {
    if indices.len() < 3 {
        return Err(malformed(format!(
            "face {i} has {} vertices; a face needs at least 3",
            indices.len()
        )));
    }
    let mut ids = [0u32; 3];
    for (k, &v) in indices.iter().enumerate() {
        if !(v >= 0.0 && v < vertex_count as f64 && v.fract() == 0.0) {
            return Err(malformed(format!(
                "face {i} uses vertex {v}, but there are only {vertex_count} vertices"
            )));
        }
        let v = v as u32;
        if k == 0 {
            ids[0] = v;
        } else if k == 1 {
            ids[1] = v;
        } else {
            ids[2] = v;
            if triangles.len() >= MAX_TRIANGLES {
                return Err(ImportError::OverLimit {
                    format: FORMAT,
                    what: "triangles",
                    claimed: triangles.len() as u64 + 1,
                    limit: MAX_TRIANGLES as u64,
                });
            }
            triangles.push(ids);
            ids[1] = v;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_a_quad_as_two_triangles() {
        // One square face: the fan gives (0,1,2) and (0,2,3).
        let text = b"ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n";
        let mesh = parse(text).unwrap();
        assert_eq!(mesh.triangles, vec![[0, 1, 2], [0, 2, 3]]);
        assert_eq!(mesh.vertices[2], [1.0, 1.0, 0.0]);
    }

    #[test]
    fn vertex_limit_is_checked_before_reading() {
        // 2^24 + 1 vertices claimed in a tiny file: OverLimit, not an allocation.
        let text = b"ply\nformat binary_little_endian 1.0\nelement vertex 16777217\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
        assert!(matches!(
            parse(text),
            Err(ImportError::OverLimit {
                what: "vertices",
                claimed: 16_777_217,
                ..
            })
        ));
    }
}
