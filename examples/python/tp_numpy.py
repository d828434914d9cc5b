"""The NPM3D TP4 shading written plainly in numpy (float64): the reference the Python examples and
benchmarks hold pointshade's `tp` preset to, and the numpy side of `cargo bench --bench normalmap`
(benches/normalmap_numpy.py imports it).

It implements the `tp` preset's formulas exactly as ../shared/notes/tp-assignment.md states them,
vectorised over the whole image the way a numpy user would write them: one array operation per
term, every pixel (background included) computed, float64 throughout.

    import tp_numpy
    lo = tp_numpy.shade(rgb, "cook-torrance")   # rgb: (H, W, 3) uint8 → L_o, (H, W, 3) float64
    img = tp_numpy.to_8bit(lo)                  # the assignment's 8-bit output, (H, W, 3) uint8

Run directly, it shades a small synthetic image and checks the documented degenerate values
(`python3 examples/python/tp_numpy.py`).
"""

import numpy as np

BRDFS = ("lambert", "blinn-phong", "cook-torrance")

# The report's parameter values (the tp preset's defaults).
LIGHT_POSITION = np.array([0.0, 1.0, 1.0])
LIGHT_COLOR = np.array([0.5, 0.5, 0.5])
LIGHT_INTENSITY = 1.0
ALBEDO = np.array([0.4, 0.7, 0.4])
KD = 1.0
KS = 1.0
SHININESS = 1.0
CAMERA = np.array([1.0, 300.0, 1.0])
ALPHA = 0.7
METALLIC = True
SPECULAR_COLOR = np.array([0.98, 0.82, 0.76])
FRESNEL_INDEX = 5.0
# Pixels whose largest 8-bit channel is at most this are background: n = 0 (shared/data/README.md).
BACKGROUND_LEVEL = 4


def normalize(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def dot(a, b):
    return np.sum(a * b, axis=-1)


def background_level(dtype):
    """BACKGROUND_LEVEL/255 of full scale in the image's own levels: 4 for 8 bits, 1028 for 16."""
    return BACKGROUND_LEVEL * (np.iinfo(dtype).max // 255)


def shade(rgb, brdf):
    """L_o for every pixel of the normal image `rgb` ((H, W, 3) uint8 or uint16, the samples as
    the PNG stores them) with the report's `brdf` ("lambert", "blinn-phong", "cook-torrance"):
    (H, W, 3) float64."""
    if brdf not in BRDFS:
        raise ValueError(f"unknown brdf {brdf!r} (expected one of {', '.join(BRDFS)})")
    rgb = np.asarray(rgb)[..., :3]
    c = rgb.astype(np.float64)
    # Convention 1: one global min-max over the RGB array, used as the normal without decoding.
    n = c - c.min()
    n = n / n.max()
    n[rgb.max(axis=-1) <= background_level(rgb.dtype)] = 0.0
    # Convention 2: pixel (row, col) is the point (row, col, 0).
    h, w, _ = rgb.shape
    rows, cols = np.meshgrid(np.arange(h, dtype=np.float64), np.arange(w, dtype=np.float64), indexing="ij")
    x = np.stack([rows, cols, np.zeros_like(rows)], axis=-1)
    # ω_i from the light towards the point, ω_o from the point towards the camera.
    wi = normalize(x - LIGHT_POSITION)
    wo = normalize(CAMERA - x)
    li = LIGHT_COLOR * LIGHT_INTENSITY
    # Convention 3: every dot product clamped to [0, 1].
    n_wi = np.clip(dot(n, wi), 0.0, 1.0)
    f = np.broadcast_to(KD * ALBEDO / np.pi, c.shape)
    if brdf == "blinn-phong":
        wh = normalize(wo + wi)
        n_wh = np.clip(dot(n, wh), 0.0, 1.0)
        f = f + (KS * n_wh**SHININESS)[..., None]
    elif brdf == "cook-torrance":
        wh = normalize(wo + wi)
        n_wh = np.clip(dot(n, wh), 0.0, 1.0)
        n_wo = np.clip(dot(n, wo), 0.0, 1.0)
        wi_wh = np.clip(dot(wi, wh), 0.0, 1.0)
        a2 = ALPHA * ALPHA
        d = a2 / (np.pi * (1.0 + (a2 - 1.0) * n_wh**2) ** 2)
        f0 = SPECULAR_COLOR if METALLIC else np.full(3, ((FRESNEL_INDEX - 1) / (FRESNEL_INDEX + 1)) ** 2)
        fr = f0 + (1.0 - f0) * ((1.0 - np.maximum(0.0, wi_wh)) ** 5)[..., None]
        k = ALPHA * np.sqrt(2.0 / np.pi)
        g = (n_wi / (n_wi * (1.0 - k) + k)) * (n_wo / (n_wo * (1.0 - k) + k))
        denominator = 4.0 * n_wi * n_wo
        denominator[denominator == 0.0] = 1.0
        f = f + (d * g / denominator)[..., None] * fr
    return li * f * n_wi[..., None]


def to_8bit(lo):
    """The assignment's output: L_o min-max normalised to [0, 1] with one min and max over all
    pixels and channels, multiplied by 255 and truncated (not rounded): (H, W, 3) uint8. A uniform
    image (max = min) has no range and is all 0, as pointshade writes it."""
    lo = np.asarray(lo, dtype=np.float64)
    low, high = lo.min(), lo.max()
    if not high > low:
        return np.zeros(lo.shape, dtype=np.uint8)
    return np.clip((lo - low) / (high - low) * 255.0, 0.0, 255.0).astype(np.uint8)


if __name__ == "__main__":
    rng = np.random.default_rng(7)
    image = rng.integers(0, 256, size=(20, 30, 3), dtype=np.uint8)
    image[:4] = 0  # background rows
    image[4, :, :] = [4, 2, 3]  # at the background level: still background
    for name in BRDFS:
        lo = shade(image, name)
        assert lo.shape == (20, 30, 3) and lo.dtype == np.float64 and np.isfinite(lo).all(), name
        assert (lo[:5] == 0).all(), name  # background shades to 0
        assert (lo >= 0).all(), name
        out = to_8bit(lo)
        assert out.dtype == np.uint8 and out.max() == 255 and out.min() == 0, name
    # 16-bit samples of the same levels (v·257) give the same normals, hence the same L_o.
    assert np.array_equal(shade(image.astype(np.uint16) * 257, "cook-torrance"), shade(image, "cook-torrance"))
    # Truncation, not rounding: (2 − 1)/4·255 = 63.75 → 63, (3 − 1)/4·255 = 127.5 → 127.
    assert to_8bit(np.array([[[1.0, 2.0, 3.0]], [[5.0, 4.0, 1.0]]]))[0, 0].tolist() == [0, 63, 127]
    assert not to_8bit(np.ones((2, 2, 3))).any()
    print("tp_numpy.py: checks OK")
