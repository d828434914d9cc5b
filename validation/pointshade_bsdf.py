"""pointshade's BRDF models as a Mitsuba 3 BSDF plugin named "pointshade".

Mitsuba has no BSDF for Blinn-Phong, for the assignment's Schlick-Smith masking, for Schlick
Fresnel, for a diffuse + specular sum or for glTF's metallic-roughness BRDF, so this plugin re-implements pointshade's models from
their published formulas (docs/scene-format.md, "Materials and BRDFs") in Dr.Jit. It is written separately
from the Rust code and in the textbook forms (tangent-form Smith G1, plain GGX denominator,
G / (4 cos cos) without cancelling), so agreement between the two is evidence for both.

Conventions (Mitsuba's): `si.wi` points to the viewer (pointshade's omega_o) and the `wo`
argument of eval() to the light (pointshade's omega_i), both in the shading frame (z = n_s).
eval() returns f_r * cos(theta_light). One-sided: zero unless both cosines are positive
(two-sidedness comes from wrapping in Mitsuba's `twosided`, except for glTF materials with a
normal texture, which turn their mapped normal themselves). glTF textures are looked up by
pointshade_textures.py, which also registers the `pointshade_emission` texture for the radiance
of area emitters (the emissive factor times the emissive texture). Only eval() matters for the
`direct` integrator with bsdf_samples = 0 and delta lights; sample() returns no sample.
"""

import drjit as dr
import mitsuba as mi

import pointshade_light as light
import pointshade_textures as textures

MIN_ALPHA = 1e-4


def _color(props, name, default):
    return mi.Color3f(props[name]) if props.has_property(name) else mi.Color3f(default)


def _floats(props, name, default):
    if not props.has_property(name):
        return [float(default)] * 3
    c = props[name]
    return [float(c[0]), float(c[1]), float(c[2])]


def _float(props, name, default):
    return float(props[name]) if props.has_property(name) else float(default)


def register():
    """Registers the plugin, with the texture and light plugins (pointshade_textures.py,
    pointshade_light.py); call after mi.set_variant() and before loading a scene."""

    class PointshadeBSDF(mi.BSDF):
        def __init__(self, props):
            mi.BSDF.__init__(self, props)
            self.model = props["model"] if props.has_property("model") else "lambert"
            if self.model not in ("lambert", "blinn-phong", "cook-torrance", "gltf-pbr"):
                raise ValueError(f"pointshade BSDF: unknown model {self.model!r}")
            self.albedo = _color(props, "albedo", 0.8)
            self.kd = _float(props, "kd", 1.0)
            self.ks = _float(props, "ks", 1.0)
            self.shininess = _float(props, "shininess", 32.0)
            self.specular_color = _color(props, "specular_color", 1.0)
            self.alpha = max(_float(props, "alpha", 0.7), MIN_ALPHA)
            self.d = props["d"] if props.has_property("d") else "ggx"
            self.g = props["g"] if props.has_property("g") else "schlick-smith"
            self.f = props["f"] if props.has_property("f") else "schlick"
            self.metallic = bool(props["metallic"]) if props.has_property("metallic") else True
            self.ior = _float(props, "ior", 5.0)
            # Per-channel Python floats: fresnel_conductor takes one complex index at a time.
            self.eta = _floats(props, "eta", 0.0)
            self.k = _floats(props, "k", 1.0)
            # gltf-pbr: the base colour is `albedo`; alpha = roughness^2. Textures (base colour,
            # metallic-roughness, normal) modulate the factors per point (pointshade_textures.py).
            self.gltf_metallic = _float(props, "metallic", 0.0) if self.model == "gltf-pbr" else 0.0
            self.images = {}
            if self.model == "gltf-pbr":
                self.roughness = _float(props, "roughness", 1.0)
                self.alpha = max(self.roughness**2, MIN_ALPHA)
                self.images = {
                    slot: textures.Image(props, slot, srgb=slot == "base_color")
                    for slot in ("base_color", "metallic_roughness", "normal")
                    if textures.Image.present(props, slot)
                }
            # The other models: an albedo texture (MTL map_Kd, sRGB) multiplies `albedo` per point.
            self.albedo_image = None
            if self.model != "gltf-pbr" and textures.Image.present(props, "albedo"):
                self.albedo_image = textures.Image(props, "albedo", srgb=True)
            self.normal_scale = _float(props, "normal_scale", 1.0)
            # With a normal texture the plugin handles two-sidedness itself (pointshade turns the
            # *mapped* normal to face the viewer; Mitsuba's `twosided` would turn the interpolated one).
            self.two_sided = bool(props["two_sided"]) if props.has_property("two_sided") else False
            flags = mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.FrontSide
            if self.two_sided:
                flags = flags | mi.BSDFFlags.BackSide
            self.m_components = [flags]
            self.m_flags = flags

        # --- terms ---------------------------------------------------------------------------
        def _distribution(self, nh):
            a2 = self.alpha * self.alpha
            if self.d == "ggx":
                return a2 / (dr.pi * dr.square(1.0 + (a2 - 1.0) * nh * nh))
            if self.d == "beckmann":
                cos2 = nh * nh
                tan2 = (1.0 - cos2) / cos2
                return dr.select(nh > 0, dr.exp(-tan2 / a2) / (dr.pi * a2 * cos2 * cos2), 0.0)
            raise ValueError(f"pointshade BSDF: unknown D {self.d!r}")

        def _masking(self, ci, co):
            a = self.alpha
            if self.g in ("schlick-smith", "schlick-karis"):
                k = a * dr.sqrt(2.0 / dr.pi) if self.g == "schlick-smith" else a / 2.0

                def g1(c):
                    return c / (c * (1.0 - k) + k)

                return g1(ci) * g1(co)
            if self.g == "smith-ggx":

                def g1(c):
                    tan2 = (1.0 - c * c) / (c * c)
                    return 2.0 / (1.0 + dr.sqrt(1.0 + a * a * tan2))

                return g1(ci) * g1(co)
            if self.g == "smith-ggx-correlated":
                a2 = a * a
                v = 0.5 / (ci * dr.sqrt(co * co * (1.0 - a2) + a2) + co * dr.sqrt(ci * ci * (1.0 - a2) + a2))
                return 4.0 * ci * co * v
            raise ValueError(f"pointshade BSDF: unknown G {self.g!r}")

        def _fresnel(self, ih):
            c = dr.clip(ih, 0.0, 1.0)
            if self.f in ("schlick", "schlick-sg"):
                if self.metallic:
                    f0 = self.specular_color
                else:
                    f0 = mi.Color3f(((self.ior - 1.0) / (self.ior + 1.0)) ** 2)
                if self.f == "schlick":
                    w = dr.power(1.0 - c, 5.0)
                else:
                    w = dr.exp2((-5.55473 * c - 6.98316) * c)
                return f0 + (1.0 - f0) * w
            if self.f == "conductor":
                # Mitsuba's own exact conductor Fresnel, per channel.
                channels = [
                    mi.fresnel_conductor(c, mi.Complex2f(self.eta[i], self.k[i])) for i in range(3)
                ]
                return mi.Color3f(channels[0], channels[1], channels[2]) * self.specular_color
            if self.f == "constant":
                return mi.Color3f(self.specular_color)
            raise ValueError(f"pointshade BSDF: unknown F {self.f!r}")

        def _gltf_pbr(self, ci, co, nh, ih, base, m, alpha):
            # The glTF 2.0 specification's reference BRDF (Appendix B): a Lambert lobe for the
            # non-metallic share, weighted by 1 - F, plus GGX with the height-correlated Smith
            # visibility V = G / (4 cos cos) and Schlick's F from F0 = lerp(0.04, base, metallic).
            a2 = alpha * alpha
            d = a2 / (dr.pi * dr.square(nh * nh * (a2 - 1.0) + 1.0))
            v = 0.5 / (ci * dr.sqrt(co * co * (1.0 - a2) + a2) + co * dr.sqrt(ci * ci * (1.0 - a2) + a2))
            f0 = 0.04 * (1.0 - m) + base * m
            f = f0 + (1.0 - f0) * dr.power(1.0 - dr.clip(ih, 0.0, 1.0), 5.0)
            return (1.0 - f) * base * ((1.0 - m) / dr.pi) + f * (d * v)

        def _mapped_normal(self, si, n, active):
            # The glTF tangent frame: T = the interpolated vertex tangent made orthogonal to n,
            # B = sign(w) (n x T); the texel (r, g, b) is the tangent-space normal
            # ((2r - 1) scale, (2g - 1) scale, 2b - 1). Kept unmapped where the vertices have no
            # tangent (w = 0) or the frame or the result has no length.
            t = mi.Vector3f(si.shape.eval_attribute_3("vertex_tangent", si, active))
            w = si.shape.eval_attribute_1("vertex_handedness", si, active)
            t = t - n * dr.dot(n, t)
            t_len = dr.norm(t)
            tangent = t / dr.select(t_len > 0.0, t_len, 1.0)
            bitangent = dr.sign(w) * dr.cross(n, tangent)
            texel = self.images["normal"].sample(si, active)
            x = (2.0 * texel.x - 1.0) * self.normal_scale
            y = (2.0 * texel.y - 1.0) * self.normal_scale
            z = 2.0 * texel.z - 1.0
            p = x * tangent + y * bitangent + z * n
            p_len = dr.norm(p)
            ok = (w != 0.0) & (t_len > 0.0) & (p_len > 0.0) & dr.isfinite(p_len)
            return dr.select(ok, p / dr.select(p_len > 0.0, p_len, 1.0), n)

        def _eval_textured_gltf(self, si, wo, active):
            # World-space vectors, since the normal texture moves the normal off Mitsuba's frame.
            base, m, roughness = self.albedo, mi.Float(self.gltf_metallic), mi.Float(self.roughness)
            if "base_color" in self.images:
                base = base * self.images["base_color"].sample(si, active)
            if "metallic_roughness" in self.images:
                mr = self.images["metallic_roughness"].sample(si, active)
                m, roughness = m * mr.z, roughness * mr.y
            alpha = dr.maximum(roughness * roughness, MIN_ALPHA)
            n = si.sh_frame.n
            wi_w, wo_w = si.sh_frame.to_world(si.wi), si.sh_frame.to_world(wo)
            if "normal" in self.images:
                n = self._mapped_normal(si, n, active)
            if self.two_sided:
                n = dr.select(dr.dot(n, wi_w) < 0.0, -n, n)
            co, ci = dr.dot(n, wi_w), dr.dot(n, wo_w)
            h = dr.normalize(wi_w + wo_w)
            value = self._gltf_pbr(ci, co, dr.clip(dr.dot(n, h), 0.0, 1.0), dr.dot(wo_w, h), base, m, alpha)
            return dr.select(active & (ci > 0.0) & (co > 0.0), value * ci, 0.0)

        # --- BSDF interface --------------------------------------------------------------------
        def eval(self, ctx, si, wo, active=True):
            if self.images:
                return self._eval_textured_gltf(si, wo, active)
            wi = si.wi
            co = mi.Frame3f.cos_theta(wi)
            ci = mi.Frame3f.cos_theta(wo)
            active = active & (ci > 0.0) & (co > 0.0)
            if self.model == "gltf-pbr":
                h = dr.normalize(wi + wo)
                nh = dr.clip(mi.Frame3f.cos_theta(h), 0.0, 1.0)
                value = self._gltf_pbr(ci, co, nh, dr.dot(wo, h), self.albedo, self.gltf_metallic, self.alpha)
                return dr.select(active, value * ci, 0.0)
            albedo = self.albedo
            if self.albedo_image is not None:
                albedo = albedo * self.albedo_image.sample(si, active)
            value = albedo * (self.kd / dr.pi)
            if self.model != "lambert":
                h = dr.normalize(wi + wo)
                nh = mi.Frame3f.cos_theta(h)
                if self.model == "blinn-phong":
                    value = value + self.specular_color * (self.ks * dr.power(dr.clip(nh, 0.0, 1.0), self.shininess))
                else:
                    ih = dr.dot(wo, h)
                    d = self._distribution(dr.clip(nh, 0.0, 1.0))
                    g = self._masking(ci, co)
                    f = self._fresnel(ih)
                    value = value + f * (d * g / (4.0 * ci * co))
            return dr.select(active, value * ci, 0.0)

        def pdf(self, ctx, si, wo, active=True):
            return mi.Float(0.0)

        def eval_pdf(self, ctx, si, wo, active=True):
            return self.eval(ctx, si, wo, active), mi.Float(0.0)

        def sample(self, ctx, si, sample1, sample2, active=True):
            return mi.BSDFSample3f(), mi.Color3f(0.0)

        def traverse(self, callback):
            pass

        def to_string(self):
            return f"PointshadeBSDF[model={self.model}]"

    mi.register_bsdf("pointshade", lambda props: PointshadeBSDF(props))
    textures.register()
    light.register()
