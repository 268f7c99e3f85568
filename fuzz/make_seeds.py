#!/usr/bin/env python3
"""Writes the small seed corpus in fuzz/seeds/<target>/: a few valid files of every importer's
formats and variants (each under a few KB, so that libFuzzer mutates them quickly), and the
GeoTIFFs through GDAL's gdal_translate (Debian's gdal-bin, a fuzzing-time tool only).

Run from the repository root: python3 fuzz/make_seeds.py. The output is deterministic.
"""

import base64
import json
import os
import shutil
import struct
import subprocess
import tempfile
import zlib

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "seeds")


def write(target, name, data):
    folder = os.path.join(ROOT, target)
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, name), "wb") as f:
        f.write(data)


def bump(w, h):
    """A small smooth bump with a slope, as f32-exact values."""
    return [float((x - w // 2) ** 2 + (y - h // 2) ** 2) * -0.5 + 0.25 * x
            for y in range(h) for x in range(w)]


# Raw f32 grid: a u16 little-endian sidecar length, the JSON sidecar, then the f32 grid.
def raw(name, w, h, meta, values=None):
    sidecar = json.dumps(dict(width=w, height=h, **meta)).encode()
    values = bump(w, h) if values is None else values
    data = b"".join(struct.pack("<f", v) for v in values)
    write("import_raw", name, struct.pack("<H", len(sidecar)) + sidecar + data)


raw("grid_4x3", 4, 3, {})
raw("grid_3x3_spacing_units", 3, 3, {"spacing": [0.5, 2.0], "units": "m",
                                      "source": "seed", "derivation": "bump"})
raw("grid_2x5_wrong_size", 2, 5, {}, values=bump(2, 4))


# PNG heightmaps of every colour type.
def chunk(kind, body):
    return (struct.pack(">I", len(body)) + kind + body
            + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF))


def png(name, w, h, color, depth, rows, palette=None):
    ihdr = struct.pack(">IIBBBBB", w, h, depth, color, 0, 0, 0)
    raw_rows = b"".join(b"\x00" + r for r in rows)
    body = chunk(b"IHDR", ihdr)
    if palette is not None:
        body += chunk(b"PLTE", palette)
    body += chunk(b"IDAT", zlib.compress(raw_rows, 9)) + chunk(b"IEND", b"")
    write("import_png", name, b"\x89PNG\r\n\x1a\n" + body)


png("gray8_4x3.png", 4, 3, 0, 8, [bytes([x * 40 + y * 9 for x in range(4)]) for y in range(3)])
png("gray16_3x3.png", 3, 3, 0, 16,
    [b"".join(struct.pack(">H", x * 9000 + y * 300) for x in range(3)) for y in range(3)])
png("gray1_8x2.png", 8, 2, 0, 1, [b"\xa5", b"\x3c"])
png("graya8_3x2.png", 3, 2, 4, 8,
    [b"".join(bytes([x * 50 + y, 255]) for x in range(3)) for y in range(2)])
png("rgb8_3x2.png", 3, 2, 2, 8,
    [b"".join(bytes([1, x * 60, y * 7]) for x in range(3)) for y in range(2)])
png("rgba16_2x2.png", 2, 2, 6, 16,
    [b"".join(struct.pack(">HHHH", x * 999, y * 777, 5, 65535) for x in range(2)) for y in range(2)])
png("palette4_4x2.png", 4, 2, 3, 4, [b"\x01\x23", b"\x32\x10"],
    palette=bytes([0, 0, 0, 80, 80, 80, 160, 160, 160, 255, 255, 255]))


# Meshes: a 3×3 grid lattice (used as is), a tilted bump (resampled), a closed cube (folds).
GRID = [(x, y, float((x - 1) ** 2 + y)) for y in range(3) for x in range(3)]
GRID_QUADS = [(y * 3 + x, y * 3 + x + 1, (y + 1) * 3 + x + 1, (y + 1) * 3 + x)
              for y in range(2) for x in range(2)]
TILTED = [(0.0, 0.0, 0.0), (2.0, 0.3, 0.5), (0.2, 2.0, 0.7), (2.1, 2.2, 1.9), (1.0, 1.1, 2.5)]
TILTED_TRIS = [(0, 1, 4), (1, 3, 4), (3, 2, 4), (2, 0, 4)]
CUBE = [(x, y, z) for z in (0.0, 1.0) for y in (0.0, 1.0) for x in (0.0, 1.0)]
CUBE_QUADS = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]


def ply_ascii(vertices, faces, index_type="int"):
    head = ("ply\nformat ascii 1.0\ncomment seed\nelement vertex %d\nproperty float x\n"
            "property float y\nproperty float z\nelement face %d\n"
            "property list uchar %s vertex_indices\nend_header\n"
            % (len(vertices), len(faces), index_type))
    body = "".join("%r %r %r\n" % tuple(map(float, v)) for v in vertices)
    body += "".join("%d %s\n" % (len(f), " ".join(map(str, f))) for f in faces)
    return (head + body).encode()


def ply_binary(vertices, faces, big_endian, double=False):
    order = ">" if big_endian else "<"
    kind = "binary_big_endian" if big_endian else "binary_little_endian"
    scalar = "double" if double else "float"
    head = ("ply\nformat %s 1.0\nelement vertex %d\nproperty %s x\nproperty %s y\n"
            "property %s z\nproperty uchar red\nelement face %d\n"
            "property list uchar uint vertex_indices\nend_header\n"
            % (kind, len(vertices), scalar, scalar, scalar, len(faces))).encode()
    fmt = order + ("ddd" if double else "fff") + "B"
    body = b"".join(struct.pack(fmt, *map(float, v), 7) for v in vertices)
    body += b"".join(struct.pack(order + "B" + "I" * len(f), len(f), *f) for f in faces)
    return head + body


write("import_ply", "grid_ascii.ply", ply_ascii(GRID, GRID_QUADS))
write("import_ply", "grid_binary_le.ply", ply_binary(GRID, GRID_QUADS, False))
write("import_ply", "grid_binary_be_double.ply", ply_binary(GRID, GRID_QUADS, True, True))
write("import_ply", "tilted_ascii.ply", ply_ascii(TILTED, TILTED_TRIS, "uint"))
write("import_ply", "cube_binary_le.ply", ply_binary(CUBE, CUBE_QUADS, False))


def obj(vertices, faces, extra=""):
    text = "# seed\no part\n" + extra
    text += "".join("v %r %r %r\n" % tuple(map(float, v)) for v in vertices)
    text += "vn 0 0 1\nvt 0 0\ng faces\n"
    text += "".join("f %s\n" % " ".join(str(i + 1) for i in f) for f in faces)
    return text.encode()


write("import_obj", "grid.obj", obj(GRID, GRID_QUADS))
write("import_obj", "tilted.obj", obj(TILTED, TILTED_TRIS, "mtllib none.mtl\nusemtl a\n"))
write("import_obj", "cube.obj", obj(CUBE, CUBE_QUADS))


def triangles(vertices, faces):
    out = []
    for f in faces:
        for k in range(1, len(f) - 1):
            out.append((vertices[f[0]], vertices[f[k]], vertices[f[k + 1]]))
    return out


def stl_binary(tris, header=b"binary seed"):
    body = b"".join(struct.pack("<3f", 0, 0, 1)
                    + b"".join(struct.pack("<3f", *map(float, p)) for p in t) + b"\0\0"
                    for t in tris)
    return header.ljust(80, b"\0") + struct.pack("<I", len(tris)) + body


def stl_ascii(tris):
    text = "solid seed\n"
    for t in tris:
        text += "  facet normal 0 0 1\n    outer loop\n"
        text += "".join("      vertex %r %r %r\n" % tuple(map(float, p)) for p in t)
        text += "    endloop\n  endfacet\n"
    return (text + "endsolid seed\n").encode()


write("import_stl", "grid_ascii.stl", stl_ascii(triangles(GRID, GRID_QUADS)))
write("import_stl", "tilted_binary.stl", stl_binary(triangles(TILTED, TILTED_TRIS)))
write("import_stl", "grid_binary_solid_header.stl",
      stl_binary(triangles(GRID, GRID_QUADS), b"solid but binary"))
write("import_stl", "cube_binary.stl", stl_binary(triangles(CUBE, CUBE_QUADS)))


# GeoTIFFs through GDAL from a small raw grid with an ENVI header.
def tiffs():
    if shutil.which("gdal_translate") is None:
        raise SystemExit("gdal_translate is needed for the GeoTIFF seeds (apt-get install gdal-bin)")
    w, h = 9, 7
    values = bump(w, h)
    values[3 * w + 4] = -9999.0
    with tempfile.TemporaryDirectory() as tmp:
        src = os.path.join(tmp, "grid.f32")
        with open(src, "wb") as f:
            f.write(b"".join(struct.pack("<f", v) for v in values))
        with open(os.path.join(tmp, "grid.hdr"), "w") as f:
            f.write("ENVI\nsamples = %d\nlines = %d\nbands = 1\nheader offset = 0\n"
                    "file type = ENVI Standard\ndata type = 4\ninterleave = bsq\n"
                    "byte order = 0\n" % (w, h))
        variants = {
            "int16_lzw_nodata_georef.tif": ["-ot", "Int16", "-co", "COMPRESS=LZW",
                                            "-co", "PREDICTOR=2", "-a_nodata", "-9999",
                                            "-a_ullr", "1000", "2070", "1090", "2000"],
            "uint16_packbits_strips.tif": ["-ot", "UInt16", "-co", "COMPRESS=PACKBITS",
                                           "-co", "BLOCKYSIZE=2"],
            "float32_tiled_deflate_point.tif": ["-ot", "Float32", "-co", "TILED=YES",
                                                "-co", "BLOCKXSIZE=16", "-co", "BLOCKYSIZE=16",
                                                "-co", "COMPRESS=DEFLATE",
                                                "-mo", "AREA_OR_POINT=Point",
                                                "-a_ullr", "0", "7", "9", "0"],
            "float64_none.tif": ["-ot", "Float64", "-co", "COMPRESS=NONE"],
            "byte_none_bigendian.tif": ["-ot", "Byte", "-scale", "-co", "ENDIANNESS=BIG"],
            "float32_deflate_nan_nodata.tif": ["-ot", "Float32", "-co", "COMPRESS=DEFLATE",
                                             "-a_nodata", "nan"],
        }
        for name, args in variants.items():
            out = os.path.join(tmp, name)
            subprocess.run(["gdal_translate", "-q", "-of", "GTiff", *args, src, out],
                           check=True)
            with open(out, "rb") as f:
                write("import_tiff", name, f.read())


# Share links (the app's URL fragment): v1.<base64url JSON>[.<base64url zlib f32 grid>].
def b64(data):
    return base64.urlsafe_b64encode(data).rstrip(b"=").decode()


def link(surface, algorithm="nsga2", grid=None, prefix=""):
    settings = {
        "surface": surface, "algorithm": algorithm,
        "params": {"population": 40, "generations": 20, "crossover": "oax",
                   "crossover_probability": 0.8, "mutation_probability": None, "seed": 7},
        "generations_run": 20, "selected": 3,
        "camera": {"yaw": -1.9, "pitch": 0.9, "distance": 1.9, "target": [0.0, 0.0, 0.0]},
        "toggles": {"original": True, "error": False, "kept": False},
    }
    text = prefix + "v1." + b64(json.dumps(settings, separators=(",", ":")).encode())
    if grid is not None:
        text += "." + b64(zlib.compress(b"".join(struct.pack("<f", v) for v in grid), 9))
    return text.encode()


write("share_link", "builtin", link({"kind": "builtin", "name": "volcano_87x61"}))
write("share_link", "builtin_greedy_hash", link({"kind": "builtin", "name": "bunny_65x65"},
                                                "greedy", prefix="#"))
write("share_link", "file_with_import", link({
    "kind": "file", "name": "scan.ply", "size": 45547, "fnv1a64": "0123456789abcdef",
    "import": {"projection": "cylindrical", "width": 65, "height": 33}}))
write("share_link", "embedded_4x3", link({"kind": "embedded", "name": "bump", "width": 4,
                                          "height": 3}, grid=bump(4, 3)))
# An embedded grid with a GeoTIFF's geometry: map origin and spacing, filled nodata cells, the
# georeference tags; and one of a resampled mesh, with its planar placement.
write("share_link", "embedded_4x3_georeferenced", link({
    "kind": "embedded", "name": "dem.tif", "width": 4, "height": 3,
    "geometry": {"origin": [2667405.0, 6478685.0], "spacing": [10.0, 12.5], "filled": 2,
                 "georeference": {"pixel_scale": [10.0, 12.5, 0.0],
                                  "tiepoint": [0.0, 0.0, 0.0, 2667400.0, 6478710.0, 0.0],
                                  "pixel_is_point": True, "nodata": "-9999"}}},
    grid=bump(4, 3)))
write("share_link", "embedded_4x3_planar", link({
    "kind": "embedded", "name": "scan.ply", "width": 4, "height": 3,
    "geometry": {"origin": [-1.5, 0.25], "spacing": [0.5, 0.75],
                 "placement": {"kind": "planar", "origin": [1.0, 2.0, 3.0], "u": [1.0, 0.0, 0.0],
                               "v": [0.0, 0.0, 1.0], "n": [0.0, -1.0, 0.0]}}},
    grid=bump(4, 3)))

tiffs()
