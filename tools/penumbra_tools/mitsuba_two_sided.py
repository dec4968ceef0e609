"""What Penumbra's BRDFs translated as Python Mitsuba plugins share (penumbra_phong in
tools/penumbra_tools/mitsuba_penumbra.py, penumbra_pbr in mitsuba_pbr.py): Penumbra's materials are
two-sided, so both directions are mirrored onto the viewer's side of the surface before
the BRDF is evaluated, and every sample is one of two reflection lobes (0: diffuse,
1: glossy). A subclass defines _eval_pdf(wi, wo) -> (f cos, pdf) in the local frame with
wi towards the viewer, and sample(), which ends with _sampled()."""
import drjit as dr
import mitsuba as mi


class TwoSidedBsdf(mi.BSDF):
    def __init__(self, props):
        mi.BSDF.__init__(self, props)
        sides = mi.BSDFFlags.FrontSide | mi.BSDFFlags.BackSide
        self.m_components = [mi.BSDFFlags.DiffuseReflection | sides, mi.BSDFFlags.GlossyReflection | sides]
        self.m_flags = self.m_components[0] | self.m_components[1]

    # Both directions onto the side of the surface that wi (towards the viewer) is on.
    @staticmethod
    def _to_front(si, wo):
        flip = mi.Frame3f.cos_theta(si.wi) < 0
        wi = mi.Vector3f(si.wi.x, si.wi.y, dr.select(flip, -si.wi.z, si.wi.z))
        wo = mi.Vector3f(wo.x, wo.y, dr.select(flip, -wo.z, wo.z))
        return wi, wo, flip

    def eval(self, ctx, si, wo, active=True):
        wi, wo, _ = self._to_front(si, wo)
        return self._eval_pdf(wi, wo)[0]

    def pdf(self, ctx, si, wo, active=True):
        wi, wo, _ = self._to_front(si, wo)
        return self._eval_pdf(wi, wo)[1]

    def eval_pdf(self, ctx, si, wo, active=True):
        wi, wo, _ = self._to_front(si, wo)
        return self._eval_pdf(wi, wo)

    def _sampled(self, wi, wo, flip, glossy):
        """The BSDFSample3f and weight of direction wo (local, viewer's side) drawn from the
        glossy lobe where `glossy`, else the diffuse one; the pdf is the full mixture's."""
        value, pdf = self._eval_pdf(wi, wo)
        bs = mi.BSDFSample3f()
        bs.wo = mi.Vector3f(wo.x, wo.y, dr.select(flip, -wo.z, wo.z))
        bs.pdf = pdf
        bs.eta = 1.0
        bs.sampled_component = dr.select(glossy, mi.UInt32(1), mi.UInt32(0))
        bs.sampled_type = dr.select(glossy, mi.UInt32(+mi.BSDFFlags.GlossyReflection),
                                    mi.UInt32(+mi.BSDFFlags.DiffuseReflection))
        return bs, dr.select(pdf > 0, value / dr.maximum(pdf, 1e-30), 0.0)

    def traverse(self, callback):
        pass

    def parameters_changed(self, keys):
        pass
