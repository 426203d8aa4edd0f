#!/usr/bin/env python3
"""Figures of qjulia's EXRs for closing notes and the book, from the command line.

Needs numpy and OpenEXR (pip install numpy OpenEXR), and pyoidn for `oidn`; none of the tests
use it.

  scripts/exr_stats.py mean PART.exr [--streams] ...
      the image's mean Rec. 709 luminance and its standard error, from a partial EXR's
      (`render --tile 0/1 --hdr`) luminance.M2 and samples channels; --streams: the pixels
      sampled adaptively, their mean holding half the samples taken (stream 1's)
  scripts/exr_stats.py variance PART.exr ...
      the mean, 99th percentile and largest variance of the pixels' mean luminance
  scripts/exr_stats.py rmse REFERENCE.exr IMAGE.exr ...
      the linear RMSE over every channel and pixel against REFERENCE, and with the worst 0.5% of
      pixels left out (as src/report/monte_carlo.rs computes them)
  scripts/exr_stats.py png-rmse REFERENCE IMAGE ...
      each IMAGE's linear RMSE (IMAGE.exr against REFERENCE.exr) and the RMSE of its 8-bit PNG
      (IMAGE.png against REFERENCE.png, values over 255): "IMAGE LINEAR png PNG"
  scripts/exr_stats.py oidn REFERENCE.exr DENOISED.exr ...
      for a render with `image.denoise = "atrous"` and --hdr: the RMSE of its noisy layer, of
      ours, and of Intel Open Image Denoise run on the same noisy colour, albedo and normal
"""
import sys

import numpy as np
import OpenEXR

WEIGHTS = np.array([0.2126, 0.7152, 0.0722])
TRIM = 0.005


def channels(path):
    return OpenEXR.File(path).parts[0].channels


def rgb(ch, name="RGB"):
    return np.asarray(ch[name].pixels, dtype=np.float64)


def rmse(a, b):
    return np.sqrt(((a - b) ** 2).mean())


def trimmed(a, b):
    e = np.sort(((a - b) ** 2).mean(axis=2).ravel())
    return np.sqrt(e[: int(len(e) * (1 - TRIM))].mean())


def pixel_variance(ch, streams=False):
    m2 = np.asarray(ch["luminance.M2"].pixels, dtype=np.float64)
    n = np.asarray(ch["samples"].pixels, dtype=np.float64)
    if streams:
        n = np.floor(n / 2)
    return np.where(n > 1, m2 / np.maximum(n * (n - 1), 1), 0.0)


def png_rgb(path):
    """An 8-bit, non-interlaced RGB or RGBA PNG's pixels as float RGB (what qjulia writes)."""
    import struct
    import zlib

    data = open(path, "rb").read()
    at, idat = 8, b""
    while at < len(data):
        (length,) = struct.unpack(">I", data[at : at + 4])
        kind, body = data[at + 4 : at + 8], data[at + 8 : at + 8 + length]
        if kind == b"IHDR":
            width, height, depth, colour = struct.unpack(">IIBB", body[:10])
            assert depth == 8 and colour in (2, 6), f"{path}: not 8-bit RGB(A)"
            channels = 3 if colour == 2 else 4
        elif kind == b"IDAT":
            idat += body
        at += 12 + length
    raw, stride = zlib.decompress(idat), width * channels
    out = np.zeros((height, stride), dtype=np.int64)
    for y in range(height):
        f, row = raw[y * (stride + 1)], np.frombuffer(raw, np.uint8, stride, y * (stride + 1) + 1)
        up = out[y - 1] if y > 0 else np.zeros(stride, dtype=np.int64)
        line = out[y]
        for x in range(stride):
            a = line[x - channels] if x >= channels else 0
            c = up[x - channels] if x >= channels else 0
            b = up[x]
            if f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pred = a if pa <= pb and pa <= pc else b if pb <= pc else c
            else:
                pred = [0, a, b, (a + b) // 2][f]
            line[x] = (int(row[x]) + pred) & 255
    return out.reshape(height, width, channels)[:, :, :3] / 255.0


def main(argv):
    what, args = argv[0], argv[1:]
    if what == "mean":
        streams = "--streams" in args
        for path in (a for a in args if a != "--streams"):
            ch = channels(path)
            lum = rgb(ch) @ WEIGHTS
            error = np.sqrt(pixel_variance(ch, streams).sum()) / lum.size
            print(f"{path}: mean luminance {lum.mean():.5f} +- {error:.5f}")
    elif what == "variance":
        for path in args:
            v = pixel_variance(channels(path))
            print(f"{path}: mean {v.mean():.3e}, p99 {np.percentile(v, 99):.3e}, max {v.max():.3e}")
    elif what == "rmse":
        reference = rgb(channels(args[0]))
        for path in args[1:]:
            image = rgb(channels(path))
            print(f"{path}: RMSE {rmse(image, reference):.5f}, trimmed {trimmed(image, reference):.5f}")
    elif what == "png-rmse":
        reference, png_reference = rgb(channels(args[0] + ".exr")), png_rgb(args[0] + ".png")
        for stem in args[1:]:
            linear = rmse(rgb(channels(stem + ".exr")), reference)
            print(f"{stem} {linear:.6f} png {rmse(png_rgb(stem + '.png'), png_reference):.6f}")
    elif what == "oidn":
        import pyoidn

        reference = rgb(channels(args[0]))
        for path in args[1:]:
            ch = channels(path)
            ours, noisy = rgb(ch), rgb(ch, "noisy").astype(np.float32)
            albedo = np.clip(rgb(ch, "albedo"), 0, 1).astype(np.float32)
            normal = np.stack([rgb(ch, c) for c in ("N.X", "N.Y", "N.Z")], axis=2)
            normal = np.nan_to_num(normal).astype(np.float32)
            oidn = np.asarray(pyoidn.denoise(noisy, albedo, normal, hdr=True), dtype=np.float64)
            print(
                f"{path}: noisy {rmse(noisy, reference):.5f} ({trimmed(noisy, reference):.5f}), "
                f"ours {rmse(ours, reference):.5f} ({trimmed(ours, reference):.5f}), "
                f"OIDN {rmse(oidn, reference):.5f} ({trimmed(oidn, reference):.5f}); "
                f"ours / OIDN {rmse(ours, reference) / rmse(oidn, reference):.3f}"
            )
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main(sys.argv[1:] or ["help"])
