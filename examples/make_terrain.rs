//! A deterministic fractal terrain: the grids the benchmarks and docs/performance.md use, made
//! from a seed so that any clone can make them again.
//!
//! ```sh
//! cargo run --release --example make_terrain -- --size 2048 --seed 1 --out fractal_2048.f32
//! cargo run --release --example make_terrain -- --size 3601 --seed 1 --tif fractal_3601.tif
//! ```
//!
//! The surface is fractional Brownian motion of value noise: octave k has lattice cells
//! `side / 4 / 2ᵏ` samples wide down to one sample, amplitude `gain^k` (default 0.5, a spectral
//! slope β ≈ 3 like real terrain), values from a hash of (seed, octave, lattice point) blended
//! with a quintic fade. Only additions and multiplications of exactly represented numbers go
//! into a height, so the same seed gives the same bits on every platform. Rows are made one at a
//! time and streamed to the files, so memory stays at a few rows whatever the size.
//!
//! Outputs: `--out NAME.f32` writes the raw little-endian f32 grid and its `NAME.json` sidecar
//! (width, height, spacing, z range, how it was made); `--tif NAME.tif` writes a georeferenced
//! single-band float32 GeoTIFF in strips (`--bigtiff` for BigTIFF, `--deflate` to compress).

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::PathBuf;
use tiff::encoder::{Compression, TiffEncoder, TiffKind, colortype};
use tiff::tags::Tag;

/// What to make, from the command line.
struct Options {
    width: usize,
    height: usize,
    seed: u64,
    gain: f64,
    relief: f64,
    spacing: f64,
    raw: Option<PathBuf>,
    tif: Option<PathBuf>,
    bigtiff: bool,
    deflate: bool,
}

const USAGE: &str = "usage: make_terrain --size N|WxH [--seed S] [--gain G] [--relief METRES] \
[--spacing METRES] [--out GRID.f32] [--tif GRID.tif] [--bigtiff] [--deflate]";

fn parse_args() -> Result<Options, String> {
    let mut o = Options {
        width: 0,
        height: 0,
        seed: 1,
        gain: 0.5,
        relief: 1000.0,
        spacing: 30.0,
        raw: None,
        tif: None,
        bigtiff: false,
        deflate: false,
    };
    let mut args = std::env::args().skip(1);
    while let Some(flag) = args.next() {
        let mut value = || args.next().ok_or(format!("{flag} needs a value; {USAGE}"));
        let number = |v: String| {
            v.parse::<f64>()
                .map_err(|_| format!("{flag}: {v:?} is not a number"))
        };
        match flag.as_str() {
            "--size" => {
                let v = value()?;
                let (w, h) = v.split_once(['x', 'X']).unwrap_or((&v, &v));
                let side = |s: &str| {
                    s.trim()
                        .parse::<usize>()
                        .map_err(|_| format!("--size {v:?}"))
                };
                (o.width, o.height) = (side(w)?, side(h)?);
            }
            "--seed" => {
                o.seed = value()?
                    .parse()
                    .map_err(|_| "--seed needs a whole number")?
            }
            "--gain" => o.gain = number(value()?)?,
            "--relief" => o.relief = number(value()?)?,
            "--spacing" => o.spacing = number(value()?)?,
            "--out" => o.raw = Some(value()?.into()),
            "--tif" => o.tif = Some(value()?.into()),
            "--bigtiff" => o.bigtiff = true,
            "--deflate" => o.deflate = true,
            _ => return Err(format!("unknown argument {flag:?}; {USAGE}")),
        }
    }
    if o.width < 2 || o.height < 2 {
        return Err(format!("--size must be at least 2x2; {USAGE}"));
    }
    if o.raw.is_none() && o.tif.is_none() {
        return Err(format!("give --out and/or --tif; {USAGE}"));
    }
    if !(o.gain > 0.0 && o.gain < 1.0 && o.spacing > 0.0 && o.relief > 0.0) {
        return Err("--gain must be in (0, 1), --spacing and --relief positive".into());
    }
    Ok(o)
}

/// SplitMix64's finaliser: a well-mixed 64-bit hash of `x`.
fn mix(mut x: u64) -> u64 {
    x = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    x ^ (x >> 31)
}

/// The lattice value of octave `octave` at lattice point (i, j), in [−1, 1).
fn lattice(seed: u64, octave: u64, i: u64, j: u64) -> f64 {
    let h = mix(seed ^ mix(octave ^ mix(i ^ mix(j))));
    (h >> 11) as f64 * (2.0 / (1u64 << 53) as f64) - 1.0
}

/// The quintic fade 6t⁵ − 15t⁴ + 10t³: smooth blends with no creases at lattice lines.
fn fade(t: f64) -> f64 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// The terrain, one row at a time.
struct Terrain {
    width: usize,
    seed: u64,
    /// Per octave: cell width in samples and amplitude.
    octaves: Vec<(f64, f64)>,
    /// Per octave: the lattice row pair cached for the current row, and its index.
    rows: Vec<(u64, Vec<f64>, Vec<f64>)>,
}

impl Terrain {
    fn new(o: &Options) -> Self {
        let mut octaves = Vec::new();
        let mut cell = (o.width.max(o.height) as f64 / 4.0).max(1.0);
        let mut amplitude = 1.0;
        loop {
            octaves.push((cell, amplitude));
            if cell <= 1.0 {
                break;
            }
            cell = (cell / 2.0).max(1.0);
            amplitude *= o.gain;
        }
        let rows = octaves
            .iter()
            .map(|_| (u64::MAX, Vec::new(), Vec::new()))
            .collect();
        Self {
            width: o.width,
            seed: o.seed,
            octaves,
            rows,
        }
    }

    /// Heights of row `y` (unscaled), into `out`.
    fn row(&mut self, y: usize, out: &mut [f64]) {
        out.iter_mut().for_each(|v| *v = 0.0);
        for (k, &(cell, amplitude)) in self.octaves.iter().enumerate() {
            let fy = y as f64 / cell;
            let j = fy.floor();
            let ty = fade(fy - j);
            let j = j as u64;
            let columns = (self.width as f64 / cell).floor() as usize + 2;
            let (cached, below, above) = &mut self.rows[k];
            if *cached != j {
                *cached = j;
                *below = (0..columns as u64)
                    .map(|i| lattice(self.seed, k as u64, i, j))
                    .collect();
                *above = (0..columns as u64)
                    .map(|i| lattice(self.seed, k as u64, i, j + 1))
                    .collect();
            }
            for (x, v) in out.iter_mut().enumerate() {
                let fx = x as f64 / cell;
                let i = fx.floor();
                let tx = fade(fx - i);
                let i = i as usize;
                let lo = below[i] + (below[i + 1] - below[i]) * tx;
                let hi = above[i] + (above[i + 1] - above[i]) * tx;
                *v += amplitude * (lo + (hi - lo) * ty);
            }
        }
    }
}

fn tiff_error(e: tiff::TiffError) -> String {
    format!("writing the GeoTIFF: {e}")
}

/// Streams the terrain into the GeoTIFF `path` in strips of 16 rows; returns the z range.
fn write_tiff<K: TiffKind>(
    encoder: TiffEncoder<BufWriter<File>, K>,
    o: &Options,
    terrain: &mut Terrain,
) -> Result<(), String> {
    let mut encoder = encoder;
    let mut image = encoder
        .new_image::<colortype::Gray32Float>(o.width as u32, o.height as u32)
        .map_err(tiff_error)?;
    let rows_per_strip = 16;
    image.rows_per_strip(rows_per_strip).map_err(tiff_error)?;
    // Pixel is area: the tie point is the upper-left corner of the first pixel.
    let top = o.height as f64 * o.spacing;
    image
        .encoder()
        .write_tag(Tag::ModelPixelScaleTag, &[o.spacing, o.spacing, 0.0][..])
        .map_err(tiff_error)?;
    image
        .encoder()
        .write_tag(Tag::ModelTiepointTag, &[0.0, 0.0, 0.0, 0.0, top, 0.0][..])
        .map_err(tiff_error)?;
    let mut heights = vec![0.0; o.width];
    let mut strip = Vec::with_capacity(o.width * rows_per_strip as usize);
    // The file's first row is the northern one: grid row H−1.
    for file_row in 0..o.height {
        terrain.row(o.height - 1 - file_row, &mut heights);
        strip.extend(heights.iter().map(|&v| (v * o.relief) as f32));
        if strip.len() == image.next_strip_sample_count() as usize {
            image.write_strip(&strip).map_err(tiff_error)?;
            strip.clear();
        }
    }
    image.finish().map_err(tiff_error)
}

fn run() -> Result<(), String> {
    let o = parse_args()?;
    let mut terrain = Terrain::new(&o);
    let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
    if let Some(path) = &o.raw {
        let create = |p: &PathBuf| File::create(p).map_err(|e| format!("{}: {e}", p.display()));
        let mut out = BufWriter::new(create(path)?);
        let mut heights = vec![0.0; o.width];
        for y in 0..o.height {
            terrain.row(y, &mut heights);
            for &v in &heights {
                let z = (v * o.relief) as f32;
                (lo, hi) = (lo.min(z), hi.max(z));
                out.write_all(&z.to_le_bytes()).map_err(|e| e.to_string())?;
            }
        }
        out.flush().map_err(|e| e.to_string())?;
        let sidecar = serde_json::json!({
            "width": o.width,
            "height": o.height,
            "dtype": "float32 little-endian",
            "order": "row-major, index = y*width + x",
            "zmin": lo,
            "zmax": hi,
            "spacing": [o.spacing, o.spacing],
            "units": "m",
            "source": "fractal terrain (examples/make_terrain.rs)",
            "derivation": format!(
                "make_terrain --size {}x{} --seed {} --gain {} --relief {} --spacing {}",
                o.width, o.height, o.seed, o.gain, o.relief, o.spacing
            ),
        });
        let json = path.with_extension("json");
        std::fs::write(
            &json,
            serde_json::to_string_pretty(&sidecar).unwrap() + "\n",
        )
        .map_err(|e| format!("{}: {e}", json.display()))?;
    }
    if let Some(path) = &o.tif {
        let file = File::create(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let compression = if o.deflate {
            Compression::Deflate(Default::default())
        } else {
            Compression::Uncompressed
        };
        let mut terrain = Terrain::new(&o);
        if o.bigtiff {
            let encoder = TiffEncoder::new_big(BufWriter::new(file)).map_err(tiff_error)?;
            write_tiff(encoder.with_compression(compression), &o, &mut terrain)?;
        } else {
            let encoder = TiffEncoder::new(BufWriter::new(file)).map_err(tiff_error)?;
            write_tiff(encoder.with_compression(compression), &o, &mut terrain)?;
        }
    }
    Ok(())
}

fn main() {
    if let Err(e) = run() {
        eprintln!("make_terrain: {e}");
        std::process::exit(2);
    }
}
