"""Fractal test terrains for the benchmarks: spectral synthesis with random phases and
amplitude k^(−β/2), written as a raw f32 grid with its JSON sidecar for the CLI."""

import json
import pathlib

import numpy as np


def terrain(width: int, height: int, beta: float = 2.8, seed: int = 1) -> np.ndarray:
    rng = np.random.default_rng(seed)
    ky = np.fft.fftfreq(height)[:, None]
    kx = np.fft.rfftfreq(width)[None, :]
    k = np.hypot(kx, ky)
    k[0, 0] = 1.0
    spectrum = k ** (-beta / 2) * np.exp(2j * np.pi * rng.random(k.shape))
    spectrum[0, 0] = 0.0
    z = np.fft.irfft2(spectrum, s=(height, width))
    return (1000.0 * (z - z.min()) / (z.max() - z.min())).astype(np.float32)


def write_f32(z: np.ndarray, path: pathlib.Path) -> None:
    """`path` (.f32) and its sidecar, as the CLI reads them."""
    height, width = z.shape
    z.astype("<f4").tofile(path)
    path.with_suffix(".json").write_text(json.dumps(
        {"width": width, "height": height, "source": "fractal terrain, beta 2.8"}))
