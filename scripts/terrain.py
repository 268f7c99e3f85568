#!/usr/bin/env python3
"""The project's one terrain generator: seeded test surfaces for scripts, benches and examples.

    python3 scripts/terrain.py FAMILY --size N|WxH [--seed S] [--out GRID.f32] [--tif GRID.tif]

Families (each a pure function of its size, seed and parameters; needs numpy only):
- ``fbm``: fractional Brownian motion of value noise, octave k with lattice cells side/4/2^k
  samples wide, amplitude ``--gain``^k; made one block of rows at a time, so any size fits in
  memory, and from additions and multiplications of exact numbers only, so a seed gives the
  same bits everywhere. ``scripts/make-grids.sh`` makes its grids with it.
- ``spectral``: a spectral fractal: random phases, amplitude k^(-beta/2) (``--beta``, 2.8),
  inverse FFT, heights 0..``--relief``. The Python benches use it.
- ``valleys``: eroded terrain: V-shaped valley networks (the zero lines of a smooth field),
  ridged detail away from the valley floors, and terraces (flat treads, steep risers).
- ``urban``: a digital surface model of a town at ``--spacing`` metres (default 1): a street
  grid at a random angle, parcels with flat or gabled buildings 3 to 120 m high whose walls are
  vertical (one grid step from street to roof), and a meandering river with embankments, on a
  gently rolling ground.

Outputs: ``--out NAME.f32`` writes the raw little-endian f32 grid (row-major, index y*W + x)
and its ``NAME.json`` sidecar, as in tests/data; ``--tif NAME.tif`` a single-band float32
GeoTIFF, in 256x256 tiles compressed with zlib by default (``--layout strips`` for 16-row
strips, ``--compression none``, ``--bigtiff``), with ModelPixelScale and ModelTiepoint (its
lower-left corner at ``--origin X Y``) and, given ``--epsg CODE`` (e.g. 32633 for UTM 33N, 4326
for longitude/latitude), the GeoKeys of that system. Grid row 0 is the southern row: the
GeoTIFF's first row is grid row H-1.

As a module (the benches and examples import it from scripts/): ``generate(family, width,
height, seed=..., **parameters)`` returns the heights as a float32 array of shape (H, W).
"""

from __future__ import annotations

import argparse
import json
import pathlib
import struct
import sys
import zlib
from typing import Callable, Iterator

import numpy as np

FAMILIES = ("fbm", "spectral", "valleys", "urban")
# Rows per block when a family is streamed (fbm) or a file written.
BLOCK_ROWS = 64
TILE = 256
STRIP_ROWS = 16

# --- fbm: value noise, bit-exact ---------------------------------------------------------------

_M64 = np.uint64(0xFFFF_FFFF_FFFF_FFFF)


def _mix(x: np.ndarray) -> np.ndarray:
    """SplitMix64's finaliser on uint64 arrays (numpy's uint64 arithmetic wraps)."""
    x = x + np.uint64(0x9E37_79B9_7F4A_7C15)
    x = (x ^ (x >> np.uint64(30))) * np.uint64(0xBF58_476D_1CE4_E5B9)
    x = (x ^ (x >> np.uint64(27))) * np.uint64(0x94D0_49BB_1331_11EB)
    return x ^ (x >> np.uint64(31))


def _lattice(seed: int, octave: int, i: np.ndarray, j: np.ndarray) -> np.ndarray:
    """Lattice values in [-1, 1) at every (j, i) of the outer product of rows j and columns i."""
    inner = _mix(i[None, :] ^ _mix(j)[:, None])
    h = _mix(np.uint64(seed) ^ _mix(np.uint64(octave) ^ inner))
    return (h >> np.uint64(11)).astype(np.float64) * (2.0 / float(1 << 53)) - 1.0


def _fade(t: np.ndarray) -> np.ndarray:
    """The quintic fade 6t^5 - 15t^4 + 10t^3: blends with no crease at lattice lines."""
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0)


def _fbm_octaves(width: int, height: int, gain: float) -> list[tuple[float, float]]:
    octaves, cell, amplitude = [], max(max(width, height) / 4.0, 1.0), 1.0
    while True:
        octaves.append((cell, amplitude))
        if cell <= 1.0:
            return octaves
        cell = max(cell / 2.0, 1.0)
        amplitude *= gain


def fbm_rows(width: int, height: int, seed: int = 1, gain: float = 0.5,
             relief: float = 1000.0) -> Callable[[int, int], np.ndarray]:
    """Rows y0..y1 of the fbm family, made on demand (the whole grid is never held)."""
    if not 0.0 < gain < 1.0:
        raise ValueError("gain must be in (0, 1)")
    octaves = _fbm_octaves(width, height, gain)
    xs = np.arange(width, dtype=np.float64)

    def rows(y0: int, y1: int) -> np.ndarray:
        out = np.zeros((y1 - y0, width))
        ys = np.arange(y0, y1, dtype=np.float64)
        for k, (cell, amplitude) in enumerate(octaves):
            fy = ys / cell
            j = np.floor(fy)
            ty = _fade(fy - j)[:, None]
            j = j.astype(np.int64)
            fx = xs / cell
            i = np.floor(fx)
            tx = _fade(fx - i)
            i = i.astype(np.int64)
            columns = np.arange(int(np.floor(width / cell)) + 2, dtype=np.uint64)
            j0 = int(j[0])
            table = _lattice(seed, k, columns, np.arange(j0, int(j[-1]) + 2, dtype=np.uint64))
            below, above = table[j - j0], table[j - j0 + 1]
            lo = below[:, i] + (below[:, i + 1] - below[:, i]) * tx
            hi = above[:, i] + (above[:, i + 1] - above[:, i]) * tx
            out += amplitude * (lo + (hi - lo) * ty)
        return (out * relief).astype(np.float32)

    return rows


# --- spectral synthesis ------------------------------------------------------------------------


def _spectral_field(width: int, height: int, beta: float, rng: np.random.Generator) -> np.ndarray:
    """A zero-mean Gaussian-like field with power spectrum k^-beta, not yet scaled."""
    ky = np.fft.fftfreq(height)[:, None]
    kx = np.fft.rfftfreq(width)[None, :]
    k = np.hypot(kx, ky)
    k[0, 0] = 1.0
    spectrum = k ** (-beta / 2) * np.exp(2j * np.pi * rng.random(k.shape))
    spectrum[0, 0] = 0.0
    return np.fft.irfft2(spectrum, s=(height, width))


def _unit(z: np.ndarray) -> np.ndarray:
    """`z` scaled to [0, 1]."""
    return (z - z.min()) / (z.max() - z.min())


def spectral(width: int, height: int, seed: int = 1, beta: float = 2.8,
             relief: float = 1000.0) -> np.ndarray:
    """The spectral fractal, heights 0..relief."""
    z = _spectral_field(width, height, beta, np.random.default_rng(seed))
    return (relief * (z - z.min()) / (z.max() - z.min())).astype(np.float32)


# --- eroded valleys with terraces --------------------------------------------------------------


def valleys(width: int, height: int, seed: int = 1, relief: float = 1000.0,
            terraces: int = 8) -> np.ndarray:
    """Valley networks, ridged slopes and terraces, heights 0..relief."""
    rng = np.random.default_rng(seed)
    broad = _spectral_field(width, height, 4.0, rng)
    detail = _spectral_field(width, height, 3.2, rng)
    tilt = _spectral_field(width, height, 4.5, rng)
    broad /= np.abs(broad).max()
    detail /= np.abs(detail).max()
    # |broad| is zero along a network of lines: V-shaped valley floors between rounded ridges.
    carved = np.abs(broad) ** 0.75
    z = _unit(0.7 * carved + 0.4 * _unit(tilt))
    if terraces > 0:
        # Each band is a flat tread for three quarters of its height and a steep riser after.
        t = z * terraces
        band = np.floor(t)
        riser = np.clip((t - band - 0.75) / 0.25, 0.0, 1.0)
        stepped = (band + riser * riser * (3.0 - 2.0 * riser)) / terraces
        z = 0.9 * stepped + 0.1 * z
    # Ridged detail (sharp crests where `detail` crosses zero) grows away from the floors,
    # as erosion leaves valley floors smooth and slopes rough.
    z = z + 0.08 * (1.0 - np.abs(detail)) ** 3 * carved
    return (relief * _unit(z)).astype(np.float32)


# --- urban surface model -----------------------------------------------------------------------


def _cuts(length: float, rng: np.random.Generator, block: tuple[float, float],
          street: tuple[float, float]) -> tuple[np.ndarray, np.ndarray]:
    """Block starts and ends along one axis (metres), streets between them, covering `length`."""
    starts, ends, at = [], [], -rng.uniform(0.0, block[1])
    while at < length:
        width = rng.uniform(*block)
        starts.append(at)
        ends.append(at + width)
        at += width + rng.uniform(*street)
    return np.array(starts), np.array(ends)


def urban(width: int, height: int, seed: int = 1, spacing: float = 1.0) -> np.ndarray:
    """A town's surface model in metres (spacing in metres per grid step)."""
    rng = np.random.default_rng(seed)
    x = np.arange(width) * spacing
    y = np.arange(height) * spacing
    X, Y = np.meshgrid(x, y)
    ground = 40.0 + 15.0 * _unit(_spectral_field(width, height, 3.6, rng))

    # Streets at a random angle: block coordinates (u, v) are the map's rotated.
    angle = rng.uniform(0.0, np.pi / 2)
    u = X * np.cos(angle) + Y * np.sin(angle)
    v = -X * np.sin(angle) + Y * np.cos(angle)
    u0, v0 = u.min(), v.min()
    u, v = u - u0, v - v0
    bu0, bu1 = _cuts(u.max() + 1.0, rng, (50.0, 140.0), (8.0, 22.0))
    bv0, bv1 = _cuts(v.max() + 1.0, rng, (40.0, 110.0), (8.0, 18.0))
    iu = np.clip(np.searchsorted(bu0, u, side="right") - 1, 0, len(bu0) - 1)
    iv = np.clip(np.searchsorted(bv0, v, side="right") - 1, 0, len(bv0) - 1)
    in_block = (u < bu1[iu]) & (v < bv1[iv])

    # Parcels: each block split into 1-4 by 1-3; each parcel's attributes drawn up front.
    shape = (len(bu0), len(bv0))
    nu = rng.integers(1, 5, size=shape)
    nv = rng.integers(1, 4, size=shape)
    pu_size = (bu1 - bu0)[:, None] / nu
    pv_size = (bv1 - bv0)[None, :] / nv
    fu = (u - bu0[iu]) / pu_size[iu, iv]
    fv = (v - bv0[iv]) / pv_size[iu, iv]
    pu = np.minimum(np.floor(fu), nu[iu, iv] - 1).astype(np.int64)
    pv = np.minimum(np.floor(fv), nv[iu, iv] - 1).astype(np.int64)
    attributes = shape + (4, 3)
    built = rng.random(attributes) < 0.8
    storeys = np.clip(rng.lognormal(np.log(12.0), 0.6, attributes), 3.0, 120.0)
    setback = rng.uniform(1.0, 5.0, attributes)
    gabled = rng.random(attributes) < 0.3
    ridge_along_u = rng.random(attributes) < 0.5
    parcel = (iu, iv, pu, pv)
    # Distances (metres) from the parcel's edges, across u and across v.
    du = np.minimum(fu - pu, pu + 1 - fu) * pu_size[iu, iv]
    dv = np.minimum(fv - pv, pv + 1 - fv) * pv_size[iu, iv]
    footprint = in_block & built[parcel] & (np.minimum(du, dv) >= setback[parcel])

    # The river: a meandering band across the town, its water flat, with sloped embankments.
    span = height * spacing
    centre = span * rng.uniform(0.3, 0.7) + span * 0.12 * np.sin(
        2 * np.pi * X / (width * spacing * rng.uniform(0.5, 1.2)) + rng.uniform(0, 2 * np.pi))
    half = rng.uniform(10.0, 20.0)
    across = np.abs(Y - centre)
    bank = np.clip((across - half) / 8.0, 0.0, 1.0)
    water = ground.min() - 4.0

    # One flat roof level per parcel: the parcel's mean ground plus its height.
    key = np.ravel_multi_index(parcel, attributes)
    counts = np.bincount(key[footprint], minlength=np.prod(attributes))
    sums = np.bincount(key[footprint], weights=ground[footprint], minlength=np.prod(attributes))
    base = (sums / np.maximum(counts, 1)).reshape(attributes)
    roof = base[parcel] + storeys[parcel]
    # A gabled roof rises 0.4 m per metre from the eaves to a ridge along the parcel's middle.
    pitch = np.where(ridge_along_u[parcel], dv - setback[parcel], du - setback[parcel])
    roof = roof + np.where(gabled[parcel], 0.4 * np.minimum(pitch, 8.0), 0.0)

    street = ground - np.where(in_block, 0.0, 0.2)
    z = np.where(footprint, roof, street)
    z = np.where(across < half + 8.0, water + (z - water) * bank, z)
    return z.astype(np.float32)


# --- one entry point ---------------------------------------------------------------------------


def generate(family: str, width: int, height: int, seed: int = 1, **parameters) -> np.ndarray:
    """The heights of `family` as a float32 array of shape (height, width); row 0 is south."""
    if width < 2 or height < 2:
        raise ValueError("a grid needs at least 2x2 points")
    if family == "fbm":
        return fbm_rows(width, height, seed, **parameters)(0, height)
    makers = {"spectral": spectral, "valleys": valleys, "urban": urban}
    if family not in makers:
        raise ValueError(f"unknown family {family!r}; one of {', '.join(FAMILIES)}")
    return makers[family](width, height, seed, **parameters)


def _blocks(rows: Callable[[int, int], np.ndarray], height: int, step: int,
            north_first: bool = False) -> Iterator[np.ndarray]:
    """The grid in blocks of `step` rows, south first, or north first as a GeoTIFF stores it."""
    starts = range(0, height, step)
    if not north_first:
        yield from (rows(y0, min(y0 + step, height)) for y0 in starts)
        return
    for top in range(height, 0, -step):
        yield rows(max(top - step, 0), top)[::-1]


def write_f32(z, path, spacing: float | None = None, source: str = "generated terrain",
              derivation: str = "", units: str = "m", width: int = 0, height: int = 0) -> None:
    """`path` (.f32) and its .json sidecar. `z` is an (H, W) array, or a function of (y0, y1)
    giving those rows with `width` and `height` named."""
    path = pathlib.Path(path)
    if isinstance(z, np.ndarray):
        height, width = z.shape
        array = z
        z = lambda y0, y1: array[y0:y1]  # noqa: E731
    lo, hi = np.inf, -np.inf
    with open(path, "wb") as f:
        for block in _blocks(z, height, BLOCK_ROWS):
            block = np.asarray(block, dtype="<f4")
            lo, hi = min(lo, float(block.min())), max(hi, float(block.max()))
            f.write(block.tobytes())
    sidecar = {"width": width, "height": height, "dtype": "float32 little-endian",
               "order": "row-major, index = y*width + x", "zmin": lo, "zmax": hi}
    if spacing is not None:
        sidecar["spacing"] = [spacing, spacing]
    sidecar.update({"units": units, "source": source})
    if derivation:
        sidecar["derivation"] = derivation
    path.with_suffix(".json").write_text(json.dumps(sidecar, indent=1) + "\n")


def write_geotiff(z, path, spacing: float, origin: tuple[float, float] = (0.0, 0.0),
                  epsg: int = 0, layout: str = "tiles", compression: str = "zlib",
                  bigtiff: bool = False, width: int = 0, height: int = 0) -> None:
    """A single-band float32 GeoTIFF of `z` (an array, or rows on demand as for `write_f32`),
    its lower-left corner at `origin` in map units, pixel is area."""
    if isinstance(z, np.ndarray):
        height, width = z.shape
        array = z
        z = lambda y0, y1: array[y0:y1]  # noqa: E731
    if layout not in ("tiles", "strips") or compression not in ("zlib", "none"):
        raise ValueError("layout is tiles or strips, compression zlib or none")
    pack = (lambda b: zlib.compress(b, 6)) if compression == "zlib" else bytes
    offset_type, inline = (16, 8) if bigtiff else (4, 4)
    offsets, counts = [], []
    with open(path, "wb") as f:
        f.write(b"II" + (struct.pack("<HHHQ", 43, 8, 0, 0) if bigtiff else struct.pack("<HI", 42, 0)))

        def chunk(data: bytes) -> None:
            offsets.append(f.tell())
            counts.append(len(data))
            f.write(data)

        if layout == "strips":
            for block in _blocks(z, height, STRIP_ROWS, north_first=True):
                chunk(pack(np.ascontiguousarray(block, dtype="<f4").tobytes()))
        else:
            across = -(-width // TILE)
            for block in _blocks(z, height, TILE, north_first=True):
                padded = np.zeros((TILE, across * TILE), dtype="<f4")
                padded[:block.shape[0], :width] = block
                for t in range(across):
                    chunk(pack(padded[:, t * TILE:(t + 1) * TILE].tobytes()))
        # Tags: (tag, TIFF type, values); written in tag order with out-of-line values first.
        top = origin[1] + height * spacing
        tags = [(256, 4, [width]), (257, 4, [height]), (258, 3, [32]),
                (259, 3, [8 if compression == "zlib" else 1]), (262, 3, [1]), (277, 3, [1]),
                (284, 3, [1]), (339, 3, [3]),
                (33550, 12, [spacing, spacing, 0.0]),
                (33922, 12, [0.0, 0.0, 0.0, origin[0], top, 0.0])]
        if layout == "strips":
            tags += [(273, offset_type, offsets), (278, 4, [STRIP_ROWS]), (279, offset_type, counts)]
        else:
            tags += [(322, 4, [TILE]), (323, 4, [TILE]), (324, offset_type, offsets),
                     (325, offset_type, counts)]
        if epsg:
            geographic = 4000 <= epsg < 5000
            keys = [(1024, 2 if geographic else 1), (1025, 1), (2048 if geographic else 3072, epsg)]
            directory = [1, 1, 0, len(keys)]
            for key, value in keys:
                directory += [key, 0, 1, value]
            tags.append((34735, 3, directory))
        tags.sort()
        formats = {3: "H", 4: "I", 12: "d", 16: "Q"}
        encoded = []
        for tag, kind, values in tags:
            data = struct.pack(f"<{len(values)}{formats[kind]}", *values)
            if len(data) > inline:
                f.write(b"\0" * (-f.tell() % 8))
                at = f.tell()
                f.write(data)
                data = struct.pack("<Q" if bigtiff else "<I", at)
            encoded.append((tag, kind, len(values), data.ljust(inline, b"\0")))
        f.write(b"\0" * (-f.tell() % 8))
        ifd = f.tell()
        entry = "<HHQ" if bigtiff else "<HHI"
        f.write(struct.pack("<Q" if bigtiff else "<H", len(encoded)))
        for tag, kind, count, data in encoded:
            f.write(struct.pack(entry, tag, kind, count) + data)
        f.write(b"\0" * (8 if bigtiff else 4))
        f.seek(8 if bigtiff else 4)
        f.write(struct.pack("<Q" if bigtiff else "<I", ifd))


def _size(text: str) -> tuple[int, int]:
    w, _, h = text.lower().partition("x")
    return int(w), int(h or w)


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(
        prog="terrain.py", description=__doc__.split("\n\n")[0],
        formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("family", choices=FAMILIES)
    parser.add_argument("--size", type=_size, required=True, help="N or WxH grid points")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--relief", type=float, help="height range (fbm: scale), not urban")
    parser.add_argument("--gain", type=float, help="fbm: amplitude ratio between octaves")
    parser.add_argument("--beta", type=float, help="spectral: spectral slope")
    parser.add_argument("--terraces", type=int, help="valleys: number of terrace bands (0: none)")
    parser.add_argument("--spacing", type=float,
                        help="grid step in map units (default 30; urban 1)")
    parser.add_argument("--out", type=pathlib.Path, help="raw GRID.f32 and its GRID.json")
    parser.add_argument("--tif", type=pathlib.Path, help="a GeoTIFF")
    parser.add_argument("--layout", choices=("tiles", "strips"), default="tiles")
    parser.add_argument("--compression", choices=("zlib", "none"), default="zlib")
    parser.add_argument("--bigtiff", action="store_true")
    parser.add_argument("--epsg", type=int, default=0, help="the GeoTIFF's EPSG code")
    parser.add_argument("--origin", type=float, nargs=2, default=(0.0, 0.0), metavar=("X", "Y"),
                        help="the GeoTIFF's lower-left corner in map units")
    args = parser.parse_args(argv)
    if args.out is None and args.tif is None:
        parser.error("give --out and/or --tif")
    width, height = args.size
    if width < 2 or height < 2:
        parser.error("--size must be at least 2x2")
    allowed = {"fbm": ("relief", "gain"), "spectral": ("relief", "beta"),
               "valleys": ("relief", "terraces"), "urban": ("spacing",)}[args.family]
    parameters = {}
    for name in ("relief", "gain", "beta", "terraces", "spacing"):
        value = getattr(args, name)
        if value is not None and name in allowed:
            parameters[name] = value
        elif value is not None and name != "spacing":
            parser.error(f"--{name} does not apply to the {args.family} family")
    spacing = args.spacing if args.spacing is not None else (1.0 if args.family == "urban" else 30.0)
    if spacing <= 0:
        parser.error("--spacing must be positive")
    if args.family == "fbm":
        rows = fbm_rows(width, height, args.seed, **parameters)
    else:
        z = generate(args.family, width, height, args.seed, **parameters)
        rows = lambda y0, y1: z[y0:y1]  # noqa: E731
    words = [args.family, f"--size {width}x{height}", f"--seed {args.seed}"]
    words += [f"--{k} {v}" for k, v in parameters.items() if k != "spacing"]
    derivation = "scripts/terrain.py " + " ".join(words) + f" --spacing {spacing}"
    if args.out:
        write_f32(rows, args.out, spacing=spacing, source=f"{args.family} terrain (scripts/terrain.py)",
                  derivation=derivation, width=width, height=height)
    if args.tif:
        write_geotiff(rows, args.tif, spacing, origin=tuple(args.origin), epsg=args.epsg,
                      layout=args.layout, compression=args.compression, bigtiff=args.bigtiff,
                      width=width, height=height)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
