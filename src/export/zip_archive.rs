//! A zip archive of deflated entries, written directly: the browser build's 3MF package and 3D
//! Tiles pyramid, where the `zip` crate is left out to keep the wasm small. Deflate is
//! miniz_oxide's and the checksum crc32fast's, both already in the build for PNG.

/// The date stamp of every entry: 1980-01-01, the format's earliest, so that the same parts
/// always give the same bytes.
const DOS_DATE: u16 = (1 << 5) | 1;
/// The zip version needed to extract a deflated entry (2.0).
const VERSION: u16 = 20;
/// The compression method "deflate".
const DEFLATE: u16 = 8;

/// A zip archive holding `parts` (name, contents) in order, each deflated. Archives of 4 GiB or
/// more (which would need zip64) are refused.
pub(crate) fn deflated_zip(parts: &[(&str, &[u8])]) -> Result<Vec<u8>, String> {
    let too_big = || "the zip archive would be 4 GiB or more, beyond a plain zip".to_owned();
    let small = |n: usize| u32::try_from(n).map_err(|_| too_big());
    let mut out = Vec::new();
    let mut central = Vec::new();
    for (name, data) in parts {
        let packed = miniz_oxide::deflate::compress_to_vec(data, 6);
        let crc = crc32fast::hash(data);
        let offset = small(out.len())?;
        let fields = |header: &mut Vec<u8>| -> Result<(), String> {
            for v in [VERSION, 0, DEFLATE, 0, DOS_DATE] {
                header.extend_from_slice(&v.to_le_bytes());
            }
            for v in [crc, small(packed.len())?, small(data.len())?] {
                header.extend_from_slice(&v.to_le_bytes());
            }
            header.extend_from_slice(&(name.len() as u16).to_le_bytes());
            header.extend_from_slice(&0u16.to_le_bytes());
            Ok(())
        };
        out.extend_from_slice(&0x0403_4b50u32.to_le_bytes());
        fields(&mut out)?;
        out.extend_from_slice(name.as_bytes());
        out.extend_from_slice(&packed);

        central.extend_from_slice(&0x0201_4b50u32.to_le_bytes());
        central.extend_from_slice(&VERSION.to_le_bytes());
        fields(&mut central)?;
        // Comment length, disk number, internal and external attributes, then the offset.
        central.extend_from_slice(&[0; 10]);
        central.extend_from_slice(&offset.to_le_bytes());
        central.extend_from_slice(name.as_bytes());
    }
    let start = small(out.len())?;
    let size = small(central.len())?;
    out.extend_from_slice(&central);
    out.extend_from_slice(&0x0605_4b50u32.to_le_bytes());
    let count = parts.len() as u16;
    for v in [0, 0, count, count] {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out.extend_from_slice(&size.to_le_bytes());
    out.extend_from_slice(&start.to_le_bytes());
    out.extend_from_slice(&0u16.to_le_bytes());
    small(out.len())?;
    Ok(out)
}
