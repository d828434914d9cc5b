"""pointshade's positional lights as a Mitsuba 3 emitter plugin named "pointshade_light".

Mitsuba's `point` and `spot` emitters fall off as 1/d², and its `spot` is linear in the angle
between its beam width and its cutoff. pointshade's lights also fall off without the inverse
square (`falloff = "none"`), within a KHR_lights_punctual range window, and its spot lights
have KHR_lights_punctual's cone by default. The export names this plugin for those lights; it
re-implements them from their published definitions (docs/scene-format.md, "Lights"; the glTF
KHR_lights_punctual specification), written apart from the Rust code.

A delta light, as `point` is: sample_direction() gives the direction towards the light with
pdf 1 and the radiance reaching the point, intensity x profile x falloff. The `direct`
integrator with one emitter sample needs nothing else (its BSDF samples cannot hit a point).

Properties: position (point), intensity (rgb, W/sr), falloff ("inverse-square", "none" or
"range"), range (float, for "range"); a spot adds direction (vector, where it points),
cos_inner, cos_outer (floats) and profile ("gltf" or "mitsuba").
"""

import drjit as dr
import mitsuba as mi


def register():
    """Registers the plugin; call after mi.set_variant() and before loading a scene."""

    class PointshadeLight(mi.Emitter):
        def __init__(self, props):
            super().__init__(props)
            self.m_flags = mi.EmitterFlags.DeltaPosition
            self.position = mi.ScalarPoint3f(props["position"])
            self.intensity = mi.Color3f(props["intensity"])
            self.falloff = props["falloff"] if props.has_property("falloff") else "inverse-square"
            if self.falloff not in ("inverse-square", "none", "range"):
                raise ValueError(f"pointshade_light: unknown falloff {self.falloff!r}")
            self.range = float(props["range"]) if props.has_property("range") else 0.0
            self.spot = props.has_property("direction")
            if self.spot:
                self.direction = dr.normalize(mi.ScalarVector3f(props["direction"]))
                self.cos_inner = float(props["cos_inner"])
                self.cos_outer = float(props["cos_outer"])
                self.profile = props["profile"] if props.has_property("profile") else "gltf"
                if self.profile not in ("gltf", "mitsuba"):
                    raise ValueError(f"pointshade_light: unknown profile {self.profile!r}")

        def _cone(self, cos_theta):
            """The spot's profile at cos(theta), theta from its direction to the point."""
            if self.profile == "gltf":
                # KHR_lights_punctual: smoothstep-free square of a clamped linear ramp in cos.
                scale = 1.0 / max(self.cos_inner - self.cos_outer, 0.001)
                t = dr.clip((cos_theta - self.cos_outer) * scale, 0.0, 1.0)
                return t * t
            # Mitsuba's spot: 1 inside the beam width, linear in the angle to 0 at the cutoff.
            inner, outer = dr.acos(self.cos_inner), dr.acos(self.cos_outer)
            theta = dr.acos(dr.clip(cos_theta, -1.0, 1.0))
            ramp = dr.clip((outer - theta) / (outer - inner), 0.0, 1.0)
            inside = dr.select(cos_theta >= self.cos_inner, 1.0, ramp)
            return dr.select(cos_theta > self.cos_outer, inside, 0.0)

        def sample_direction(self, it, sample, active=True):
            ds = mi.DirectionSample3f()
            ds.n = mi.Normal3f(0.0)
            ds.uv = mi.Point2f(0.0)
            ds.p = mi.Point3f(self.position)
            ds.pdf = 1.0
            ds.time = it.time
            ds.delta = True
            d = ds.p - it.p
            dist = dr.norm(d)
            inv_dist = dr.rcp(dist)
            ds.d = d * inv_dist
            ds.dist = dist
            if self.falloff == "inverse-square":
                falloff = dr.square(inv_dist)
            elif self.falloff == "none":
                falloff = mi.Float(1.0)
            else:
                r = dist / self.range
                falloff = dr.clip(1.0 - dr.square(dr.square(r)), 0.0, 1.0) * dr.square(inv_dist)
            if self.spot:
                falloff = falloff * self._cone(dr.dot(-ds.d, mi.Vector3f(self.direction)))
            return ds, mi.Spectrum(self.intensity * falloff)

        def pdf_direction(self, it, ds, active=True):
            return mi.Float(0.0)

        def eval_direction(self, it, ds, active=True):
            return mi.Spectrum(0.0)

        def eval(self, si, active=True):
            return mi.Spectrum(0.0)

        def sample_position(self, time, sample, active=True):
            ps = mi.PositionSample3f()
            ps.p = mi.Point3f(self.position)
            ps.pdf = 1.0
            ps.delta = True
            return ps, mi.Float(1.0)

        def sample_wavelengths(self, si, sample, active=True):
            return dr.zeros(mi.Wavelength), mi.UnpolarizedSpectrum(1.0)

        def bbox(self):
            return mi.ScalarBoundingBox3f(self.position, self.position)

        def traverse(self, callback):
            pass

        def to_string(self):
            return f"PointshadeLight[position={self.position}, spot={self.spot}]"

    mi.register_emitter("pointshade_light", lambda props: PointshadeLight(props))
