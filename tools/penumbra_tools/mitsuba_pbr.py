"""Penumbra's `pbr` material as a Mitsuba 3 BSDF written in Python (`penumbra_pbr`), for
tools/penumbra_tools/mitsuba_penumbra.py: glTF 2.0 metallic-roughness exactly as docs/SCENE_FORMAT.md and
shaders/bsdf/pbr.glsl define it (the glTF specification, Appendix B):

  f = (1 - metallic) [ (1 - F(0.04)) base/pi + F(0.04) D V ] + metallic F(base) D V

with alpha = max(roughness^2, 1e-4), D the GGX distribution, V the height-correlated Smith
visibility and Schlick's F at v.h; two-sided (both directions are mirrored onto the viewer's
side, as Penumbra does). Sampling is Penumbra's: the specular lobe with probability
pbrSpecularProbability, by GGX visible normals (Mitsuba's own sampler of the same
distribution, Heitz 2018), else cosine-weighted; the pdf is always the full mixture.
Import after mi.set_variant()."""
import drjit as dr
import mitsuba as mi

from penumbra_tools.mitsuba_two_sided import TwoSidedBsdf

MIN_ALPHA = 1e-4  # PBR_MIN_ALPHA of shaders/shared/types.h
DIELECTRIC_F0 = 0.04  # glTF Appendix B's f0 of the dielectric layer


def _schlick_weight(c):
    x = dr.clip(1.0 - c, 0.0, 1.0)
    x2 = x * x
    return x2 * x2 * x


def _smith_root(cos_t, a2):
    return dr.sqrt(cos_t * cos_t + a2 * (1.0 - cos_t * cos_t))


class PenumbraPbr(TwoSidedBsdf):
    def __init__(self, props):
        TwoSidedBsdf.__init__(self, props)
        base = [float(props.get("base_" + c, 0.8)) for c in "rgb"]
        self.base = mi.Color3f(*base)
        self.base_mean = sum(base) / 3.0
        self.metallic = float(props.get("metallic", 0.0))
        rough = float(props.get("roughness", 0.5))
        self.alpha = max(rough * rough, MIN_ALPHA)
        self.f0 = DIELECTRIC_F0
        self.distr = mi.MicrofacetDistribution(mi.MicrofacetType.GGX, self.alpha, True)

    def _p_specular(self, cos_v):
        """pbrSpecularProbability: each lobe's share of a Fresnel estimate at n.v."""
        w = _schlick_weight(cos_v)
        diel = self.f0 + (1.0 - self.f0) * w
        base_f = dr.mean(self.base + (mi.Color3f(1.0) - self.base) * w)
        specular = (1.0 - self.metallic) * diel + self.metallic * base_f
        diffuse = (1.0 - self.metallic) * (1.0 - diel) * self.base_mean
        return dr.select(diffuse > 0, specular / (specular + diffuse), 1.0)

    def _eval_pdf(self, v, l):
        """f cos and the mixture pdf, v towards the viewer and l towards the light (local)."""
        cos_v, cos_l = mi.Frame3f.cos_theta(v), mi.Frame3f.cos_theta(l)
        valid = (cos_v > 0) & (cos_l > 0)
        p_spec = self._p_specular(cos_v)
        s = v + l
        ln = dr.norm(s)
        h = s / dr.maximum(ln, 1e-30)
        a2 = self.alpha * self.alpha
        cos_h = h.z
        d_brk = a2 * cos_h * cos_h + (h.x * h.x + h.y * h.y)
        D = a2 / (dr.pi * d_brk * d_brk)
        denom = cos_l * _smith_root(cos_v, a2) + cos_v * _smith_root(cos_l, a2)
        V = dr.select(denom > 1e-30, 0.5 / dr.maximum(denom, 1e-30), 0.0)
        spec = D * V
        w = _schlick_weight(0.5 * ln)  # v.h = |v + l| / 2
        diel = self.f0 + (1.0 - self.f0) * w
        metal_f = self.base + (mi.Color3f(1.0) - self.base) * w
        f = (1.0 - self.metallic) * ((1.0 - diel) * self.base * dr.inv_pi + diel * spec) + \
            self.metallic * metal_f * spec
        spec_pdf = D / (2.0 * (cos_v + _smith_root(cos_v, a2)))
        pdf = (1.0 - p_spec) * cos_l * dr.inv_pi + dr.select(ln > 0, p_spec * spec_pdf, 0.0)
        f = dr.select(ln > 0, f, 0.0)
        return dr.select(valid, f * cos_l, 0.0), dr.select(valid, pdf, 0.0)

    def eval_diffuse_reflectance(self, si, active=True):
        return self.base * (1.0 - self.metallic)

    def sample(self, ctx, si, sample1, sample2, active=True):
        v, _, flip = self._to_front(si, mi.Vector3f(0, 0, 1))
        p_spec = self._p_specular(mi.Frame3f.cos_theta(v))
        specular = sample1 < p_spec
        m, _ = self.distr.sample(v, sample2)
        l_spec = mi.reflect(v, m)
        l_diff = mi.warp.square_to_cosine_hemisphere(sample2)
        l = dr.select(specular, l_spec, l_diff)
        return self._sampled(v, l, flip, specular)

    def to_string(self):
        return f"PenumbraPbr[metallic={self.metallic}, alpha={self.alpha}]"


def pbr_dict(base_color, metallic, roughness):
    """The translated dict of a `pbr` material with constant fields."""
    d = {"type": "penumbra_pbr", "metallic": float(metallic), "roughness": float(roughness)}
    for i, c in enumerate("rgb"):
        d["base_" + c] = float(base_color[i])
    return d
