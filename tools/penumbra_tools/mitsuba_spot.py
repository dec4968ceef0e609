"""Penumbra's `spot` light as a Mitsuba 3 emitter written in Python (`penumbra_spot`), for
tools/penumbra_tools/mitsuba_penumbra.py. Mitsuba's own `spot` cannot be used: its falloff is linear in the
angle between beam_width and cutoff_angle, while Penumbra's (shaders/lights/spot.glsl, glTF
KHR_lights_punctual) is s^2 with s = clamp((cos t - cos outer) / (cos inner - cos outer), 0, 1).
A delta light like Mitsuba's `point`: one direction, "pdf" 1, never hit; only what the direct
integrator calls (sample_direction, pdf_direction, eval) is implemented. Import after
mi.set_variant()."""
import math

import drjit as dr
import mitsuba as mi


def falloff_integral(cos_inner, cos_outer):
    """The integral of s^2 over the sphere: power = I times it (docs/SCENE_FORMAT.md `spot`)."""
    return 2 * math.pi * ((1 - cos_inner) + (cos_inner - cos_outer) / 3)


class PenumbraSpot(mi.Emitter):
    def __init__(self, props):
        mi.Emitter.__init__(self, props)
        self.p_list = [float(props.get("p_" + c)) for c in "xyz"]
        self.position = mi.Point3f(*self.p_list)
        axis = [float(props.get("d_" + c)) for c in "xyz"]
        n = math.sqrt(sum(a * a for a in axis))
        self.axis = mi.Vector3f(*[a / n for a in axis])
        self.intensity = mi.Color3f(*[float(props.get("i_" + c)) for c in "rgb"])
        self.cos_inner = float(props.get("cos_inner"))
        self.cos_outer = float(props.get("cos_outer"))
        self.m_flags = mi.EmitterFlags.DeltaPosition

    def _falloff(self, travel):
        s = dr.clip((dr.dot(travel, self.axis) - self.cos_outer) / (self.cos_inner - self.cos_outer), 0.0, 1.0)
        return s * s

    def sample_direction(self, it, sample, active=True):
        ds = mi.DirectionSample3f()
        to_light = self.position - it.p
        d2 = dr.squared_norm(to_light)
        dist = dr.sqrt(d2)
        ds.p = mi.Point3f(self.position)
        ds.n = mi.Vector3f(0.0)
        ds.uv = mi.Point2f(0.0)
        ds.time = it.time
        ds.pdf = mi.Float(1.0)
        ds.delta = mi.Bool(True)
        ds.d = to_light / dist
        ds.dist = dist
        # A pointer array in the JIT variants, the object itself in the scalar ones.
        ds.emitter = mi.EmitterPtr(self) if hasattr(mi, "EmitterPtr") else self
        value = self.intensity * (self._falloff(-ds.d) / d2)
        return ds, mi.Spectrum(dr.select(d2 > 0, value, 0.0))

    def pdf_direction(self, it, ds, active=True):
        return mi.Float(0.0)

    def eval_direction(self, it, ds, active=True):
        d2 = dr.squared_norm(self.position - it.p)
        return mi.Spectrum(self.intensity * (self._falloff(-ds.d) / d2))

    def eval(self, si, active=True):
        return mi.Spectrum(0.0)

    def sample_wavelengths(self, si, sample, active=True):
        return mi.Spectrum(1.0), mi.Spectrum(1.0)

    def bbox(self):
        return mi.ScalarBoundingBox3f(mi.ScalarPoint3f(*self.p_list))

    def traverse(self, callback):
        pass

    def parameters_changed(self, keys):
        pass

    def to_string(self):
        return "PenumbraSpot[]"


def spot_dict(light, weight):
    """The translated dict of a Penumbra `spot` light; weight(power RGB) its sampling weight."""
    cos_inner = math.cos(math.radians(float(light.get("inner_angle", 0.0))))
    cos_outer = math.cos(math.radians(float(light.get("outer_angle", 45.0))))
    if "intensity" in light:
        I = light["intensity"]
        I = [float(I)] * 3 if isinstance(I, (int, float)) else [float(x) for x in I]
    else:
        P = light["power"]
        P = [float(P)] * 3 if isinstance(P, (int, float)) else [float(x) for x in P]
        I = [p / falloff_integral(cos_inner, cos_outer) for p in P]
    d = {"type": "penumbra_spot", "cos_inner": cos_inner, "cos_outer": cos_outer,
         "sampling_weight": weight([i * falloff_integral(cos_inner, cos_outer) for i in I])}
    for i, c in enumerate("xyz"):
        d["p_" + c] = float(light["position"][i])
        d["d_" + c] = float(light["direction"][i])
    for i, c in enumerate("rgb"):
        d["i_" + c] = I[i]
    return d
