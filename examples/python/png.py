"""A minimal PNG reader and writer on numpy and zlib, so the Python examples need no imaging package.

Reads non-interlaced RGB and RGBA PNGs of 8 or 16 bits per channel (what a normal image is, and what
pointshade itself accepts apart from palettes) into a (H, W, 3|4) uint8 or uint16 array, the samples
exactly as the file stores them. Writes (H, W, 3|4) uint8 arrays as RGB(A) PNGs.

    import png
    rgba = png.read_png("normal.png")     # (451, 768, 4) uint8 for the assignment's normal.png
    png.write_png("copy.png", rgba[..., :3])

Run directly, it checks itself on a random image (`python3 examples/python/png.py`).
"""

import struct
import zlib

import numpy as np

SIGNATURE = b"\x89PNG\r\n\x1a\n"
CHANNELS = {2: 3, 6: 4}  # colour type → samples per pixel (RGB, RGBA)


def _chunks(data):
    pos = len(SIGNATURE)
    while pos + 8 <= len(data):
        length, kind = struct.unpack(">I4s", data[pos : pos + 8])
        yield kind, data[pos + 8 : pos + 8 + length]
        pos += 12 + length  # length, type, data, CRC


def _unfilter(filtered, kinds):
    """Undoes the five PNG row filters. `filtered` is (H, W, B) (B bytes per pixel), `kinds` the
    filter byte of each row. A byte depends on its left, upper and upper-left neighbours only, so
    every anti-diagonal (row + column constant) is decoded in one vectorised step."""
    h, w, _ = filtered.shape
    # One row of zeros above and one column on the left: the neighbours outside the image are 0.
    out = np.zeros((h + 1, w + 1, filtered.shape[2]), dtype=np.int32)
    kinds = kinds.astype(np.int32)
    for t in range(h + w - 1):
        r = np.arange(max(0, t - w + 1), min(h, t + 1))
        x = t - r
        raw = filtered[r, x].astype(np.int32)
        a, b, c = out[r + 1, x], out[r, x + 1], out[r, x]
        p = a + b - c
        pa, pb, pc = np.abs(p - a), np.abs(p - b), np.abs(p - c)
        paeth = np.where((pa <= pb) & (pa <= pc), a, np.where(pb <= pc, b, c))
        k = kinds[r][:, None]
        predictor = np.select([k == 1, k == 2, k == 3, k == 4], [a, b, (a + b) // 2, paeth], 0)
        out[r + 1, x + 1] = (raw + predictor) & 0xFF
    return out[1:, 1:].astype(np.uint8)


def read_png(path):
    """The samples of a non-interlaced 8- or 16-bit RGB/RGBA PNG: (H, W, 3|4) uint8 or uint16."""
    with open(path, "rb") as f:
        data = f.read()
    if not data.startswith(SIGNATURE):
        raise ValueError(f"{path}: not a PNG file")
    header, idat = None, []
    for kind, body in _chunks(data):
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat.append(body)
        elif kind == b"IEND":
            break
    if header is None:
        raise ValueError(f"{path}: no IHDR chunk")
    width, height, depth, colour, _, _, interlace = header
    if colour not in CHANNELS or depth not in (8, 16) or interlace != 0:
        raise ValueError(
            f"{path}: only non-interlaced 8/16-bit RGB or RGBA PNGs are supported "
            f"(colour type {colour}, {depth} bits, interlace {interlace})"
        )
    pixel_bytes = CHANNELS[colour] * depth // 8
    raw = np.frombuffer(zlib.decompress(b"".join(idat)), dtype=np.uint8)
    stride = 1 + width * pixel_bytes
    if raw.size < height * stride:
        raise ValueError(f"{path}: image data is truncated")
    rows = raw[: height * stride].reshape(height, stride)
    if rows[:, 0].max() > 4:
        raise ValueError(f"{path}: unknown row filter {rows[:, 0].max()}")
    pixels = _unfilter(rows[:, 1:].reshape(height, width, pixel_bytes), rows[:, 0])
    if depth == 16:  # big-endian sample pairs
        pixels = pixels.reshape(height, width, -1, 2).astype(np.uint16)
        return np.ascontiguousarray((pixels[..., 0] << 8) | pixels[..., 1])
    return pixels


def _chunk(kind, body):
    return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF)


def write_png(path, image):
    """Writes a (H, W, 3|4) uint8 array as an 8-bit RGB or RGBA PNG (rows unfiltered)."""
    image = np.asarray(image)
    if image.dtype != np.uint8 or image.ndim != 3 or image.shape[2] not in (3, 4):
        raise ValueError(f"write_png needs a (H, W, 3|4) uint8 array, got {image.dtype} {image.shape}")
    h, w, n = image.shape
    rows = np.zeros((h, 1 + w * n), dtype=np.uint8)  # filter byte 0 (None) on each row
    rows[:, 1:] = image.reshape(h, w * n)
    header = struct.pack(">IIBBBBB", w, h, 8, 2 if n == 3 else 6, 0, 0, 0)
    with open(path, "wb") as f:
        f.write(SIGNATURE)
        f.write(_chunk(b"IHDR", header))
        f.write(_chunk(b"IDAT", zlib.compress(rows.tobytes(), 6)))
        f.write(_chunk(b"IEND", b""))


def _filtered_for_test(image, kinds):
    """PNG rows of `image` filtered with the given filter type per row, byte by byte: an
    independent (scalar) encoder for the self-test of the vectorised decoder."""
    h, w, n = image.shape
    flat = image.reshape(h, w * n).astype(int)
    out = bytearray()
    for r in range(h):
        out.append(kinds[r])
        for i in range(w * n):
            a = flat[r, i - n] if i >= n else 0
            b = flat[r - 1, i] if r > 0 else 0
            c = flat[r - 1, i - n] if r > 0 and i >= n else 0
            p = a + b - c
            pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
            paeth = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
            predictor = [0, a, b, (a + b) // 2, paeth][kinds[r]]
            out.append((flat[r, i] - predictor) & 0xFF)
    return bytes(out)


if __name__ == "__main__":
    import os
    import tempfile

    rng = np.random.default_rng(1)
    smooth = np.cumsum(rng.integers(0, 3, size=(37, 53, 4)), axis=1).astype(np.uint8)
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "t.png")
        write_png(path, smooth[..., :3])
        assert np.array_equal(read_png(path), smooth[..., :3])
        write_png(path, smooth)
        assert np.array_equal(read_png(path), smooth)
        # Every filter type, in 8 and 16 bits.
        kinds = [k % 5 for k in range(smooth.shape[0])]
        for depth, image in ((8, smooth), (16, smooth.astype(np.uint16) * 257 + 3)):
            samples = image.astype(">u2").view(np.uint8) if depth == 16 else image
            h, w = image.shape[:2]
            body = zlib.compress(_filtered_for_test(samples.reshape(h, w, -1), kinds))
            with open(path, "wb") as f:
                f.write(SIGNATURE + _chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, depth, 6, 0, 0, 0)))
                f.write(_chunk(b"IDAT", body) + _chunk(b"IEND", b""))
            decoded = read_png(path)
            assert decoded.dtype == image.dtype and np.array_equal(decoded, image), depth
    print("png.py: round trips OK (unfiltered rows; filters 0-4 in 8 and 16 bits)")
