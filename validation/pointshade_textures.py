"""glTF textures as pointshade samples them, in Dr.Jit, for the pointshade BSDF plugin.

pointshade exports each image it renders with as the texels it decoded (raw RGBA, 8 bits per
channel, row 0 at the top: `{prefix}.image{k}.rgba`), so both renderers start from the same
texels whatever JPEG or PNG decoder each would use. This module looks them up with pointshade's
conventions (docs/gltf.md, "Textures"; written here from those rules, not from the Rust code):

* (u, v) = (0, 0) is the image's top-left corner, v grows downwards; texel (i, j) has its centre
  at ((i + 1/2)/W, (j + 1/2)/H);
* sRGB textures (base colour, emissive) are decoded per texel *before* filtering;
* bilinear filtering of the four nearest texels, or the nearest texel; wrap modes repeat,
  mirrored repeat and clamp to edge, per axis; non-finite coordinates read as 0;
* KHR_texture_transform as a 2x3 matrix applied to the coordinates first (`{slot}_transform`:
  u' = m0 u + m1 v + m2, v' = m3 u + m4 v + m5).

Texture coordinates come from the mesh attributes `vertex_uv0` / `vertex_uv1` that pointshade
writes into its PLY parts (`uv0_x, uv0_y, uv0_z`; Mitsuba reads groups of one or three values),
interpolated by Mitsuba at the hit, so Mitsuba's own (u, v) conventions play no part.
"""

import drjit as dr
import mitsuba as mi
import numpy as np

SLOTS = ("base_color", "metallic_roughness", "normal", "emissive")


def _srgb_decode(codes):
    c = codes.astype(np.float64) / 255.0
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4).astype(np.float32)


class Image:
    """One texture slot of a material: texels, size, coordinate set, wrap and filter."""

    def __init__(self, props, slot, srgb):
        path = props[f"{slot}_file"]
        resolved = str(mi.Thread.thread().file_resolver().resolve(path))
        self.width = int(props[f"{slot}_width"])
        self.height = int(props[f"{slot}_height"])
        codes = np.fromfile(resolved, dtype=np.uint8)
        if codes.size != self.width * self.height * 4:
            raise ValueError(f"{resolved}: {codes.size} bytes, expected {self.width}x{self.height} RGBA")
        codes = codes.reshape(-1, 4)
        rgb = _srgb_decode(codes[:, :3]) if srgb else codes[:, :3].astype(np.float32) / 255.0
        self.channels = [mi.Float(np.ascontiguousarray(rgb[:, c])) for c in range(3)]
        self.attribute = f"vertex_uv{int(props[f'{slot}_set'])}"
        self.wrap = props[f"{slot}_wrap"].split()
        self.filter = props[f"{slot}_filter"]
        key = f"{slot}_transform"
        self.transform = [float(v) for v in props[key].split()] if props.has_property(key) else None

    @staticmethod
    def present(props, slot):
        return props.has_property(f"{slot}_file")

    def uv(self, si, active):
        return si.shape.eval_attribute_3(self.attribute, si, active)

    def sample(self, si, active=True):
        """RGB at the hit `si` (a Color3f)."""
        uv = self.uv(si, active)
        u, v = uv.x, uv.y
        if self.transform is not None:
            m = self.transform
            u, v = m[0] * u + m[1] * v + m[2], m[3] * u + m[4] * v + m[5]
        x = self._texel_coordinate(u, self.width)
        y = self._texel_coordinate(v, self.height)
        if self.filter == "nearest":
            return self._texel(dr.floor(x + 0.5), dr.floor(y + 0.5), active)
        x0, y0 = dr.floor(x), dr.floor(y)
        fx, fy = x - x0, y - y0
        top = dr.lerp(self._texel(x0, y0, active), self._texel(x0 + 1.0, y0, active), fx)
        bottom = dr.lerp(self._texel(x0, y0 + 1.0, active), self._texel(x0 + 1.0, y0 + 1.0, active), fx)
        return dr.lerp(top, bottom, fy)

    @staticmethod
    def _texel_coordinate(c, n):
        c = dr.select(dr.isfinite(c), c, 0.0)
        return dr.clip(c * n - 0.5, -1e9, 1e9)

    @staticmethod
    def _wrap(i, n, mode):
        # i is an integer-valued Float; |i| ≤ 1e9 + 1, and every step below stays exact on
        # integers of that size in double precision.
        i = mi.Float64(i)
        if mode == "clamp":
            return dr.clip(i, 0.0, n - 1.0)
        if mode == "repeat":
            return i - n * dr.floor(i / n)
        if mode == "mirrored-repeat":
            m = i - 2.0 * n * dr.floor(i / (2.0 * n))
            return dr.select(m < n, m, 2.0 * n - 1.0 - m)
        raise ValueError(f"pointshade texture: unknown wrap mode {mode!r}")

    def _texel(self, i, j, active):
        col = self._wrap(i, self.width, self.wrap[0])
        row = self._wrap(j, self.height, self.wrap[1])
        index = mi.UInt32(row) * self.width + mi.UInt32(col)
        return mi.Color3f(*(dr.gather(mi.Float, ch, index, active) for ch in self.channels))


def register():
    """Registers the `pointshade_emission` texture: a glTF material's emitted radiance (emissive
    factor x sRGB emissive texture), for the radiance of an `area` emitter."""

    class EmissionTexture(mi.Texture):
        def __init__(self, props):
            mi.Texture.__init__(self, props)
            factor = props["factor"]
            self.factor_mean = (float(factor[0]) + float(factor[1]) + float(factor[2])) / 3.0
            self.factor = mi.Color3f(factor)
            self.image = Image(props, "emissive", srgb=True) if Image.present(props, "emissive") else None

        def eval(self, si, active=True):
            if self.image is None:
                return mi.Color3f(self.factor)
            return self.factor * self.image.sample(si, active)

        def eval_1(self, si, active=True):
            c = self.eval(si, active)
            return (c.x + c.y + c.z) / 3.0

        def mean(self):
            return self.factor_mean

        def traverse(self, callback):
            pass

        def to_string(self):
            return "PointshadeEmission[]"

    mi.register_texture("pointshade_emission", lambda props: EmissionTexture(props))
