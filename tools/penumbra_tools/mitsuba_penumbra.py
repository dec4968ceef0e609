"""Penumbra scene JSON -> Mitsuba 3 scene dict, plus the Penumbra features Mitsuba lacks,
written as Mitsuba plugins in Python: the normalized Phong BRDF of docs/SCENE_FORMAT.md
(`penumbra_phong`), the ambient-occlusion integrator (`penumbra_ao`), and, in their own
files under penumbra_tools/, the `pbr` BRDF and the `spot` light. Used by tools/penumbra_tools/mitsuba_compare/ (run through tools/mitsuba/mitsuba_compare.py);
import after mi.set_variant().

Mapping (see docs/design/benchmarks.md):
  camera      -> perspective, fov_axis 'y', fov = fov_y, to_world = look_at(eye, target, up)
  film        -> hdrfilm width x height, rfilter box, pixel_format rgb
  sampler     -> independent, sample_count = spp, seed = seed
  diffuse     -> twosided(diffuse) (Penumbra materials are two-sided, Mitsuba's diffuse is not)
  phong       -> penumbra_phong (two-sided inside the plugin)
  no material -> twosided(diffuse 0.8) (Mitsuba's default would be 0.5)
  sphere      -> sphere (normals outward)
  quad        -> rectangle when edge_u is orthogonal to edge_v (to_world columns edge_u/2,
                 edge_v/2, normalize(edge_u x edge_v), origin + (edge_u+edge_v)/2), else two triangles
  mesh        -> mi.Mesh filled from positions/indices (+ vertex normals when given); with a
                 PLY `file`: Mitsuba's ply plugin, face normals unless the file has normals
                 (OBJ files are unsupported: their usemtl materials have no counterpart here)
  to_world    -> unsupported on shapes
  emission    -> area emitter (one-sided, front face), radiance = emission or converted power
  point       -> point, intensity = power/(4 pi) or intensity
  directional -> directional, direction, irradiance
  environment -> constant, radiance; with `file`: envmap of a scaled, texel-replicated copy
                 (penumbra_tools/mitsuba_envmap.py), weight 4 pi^2 R^2 L_mean
  pbr         -> penumbra_pbr (penumbra_tools/mitsuba_pbr.py), two-sided inside the plugin
  spot        -> penumbra_spot (penumbra_tools/mitsuba_spot.py): Penumbra's s^2 falloff
  gltf        -> one mi.Mesh per triangle primitive (penumbra_tools/gltf_meshes.py), pbr
                 from the file's factors; textures and the file's lights are not read
  textures    -> unsupported
  direct      -> direct, emitter_samples = light_samples, bsdf_samples = bsdf_samples
                 (strategy light: bsdf_samples 0; bsdf: emitter_samples 0); Mitsuba always
                 uses the power heuristic on n_i * p_i, which is Penumbra's "mis"+"power".
                 light_selection -> each emitter's sampling_weight (1, or its power).
  ao          -> penumbra_ao
"""
import math
import os

import drjit as dr
import mitsuba as mi

from penumbra_tools.mitsuba_pbr import PenumbraPbr, pbr_dict
from penumbra_tools.mitsuba_two_sided import TwoSidedBsdf
from penumbra_tools.mitsuba_spot import PenumbraSpot, spot_dict
from penumbra_tools.vec import cross, dot, length, sub


# ---------------------------------------------------------------------------------------
# Normalized Phong: f = kd/pi + ks (n+2)/(2 pi) max(0, cos a)^n, a = angle(wo, reflect(wi)).
# Sampling picks the diffuse lobe with probability mean(kd)/(mean(kd)+mean(ks)), else the
# cos^n lobe around the mirror direction; the pdf is always the full two-lobe mixture.
# ---------------------------------------------------------------------------------------
class PenumbraPhong(TwoSidedBsdf):
    def __init__(self, props):
        TwoSidedBsdf.__init__(self, props)
        kd = [props.get("kd_" + c, 0.5) for c in "rgb"]
        ks = [props.get("ks_" + c, 0.5) for c in "rgb"]
        self.kd = mi.Color3f(*kd)
        self.ks = mi.Color3f(*ks)
        self.n = float(props.get("exponent", 20.0))
        md, ms = sum(kd) / 3.0, sum(ks) / 3.0
        self.p_diffuse = md / (md + ms) if md + ms > 0 else 1.0

    def _cos_pow(self, cos_a):
        if self.n == 0.0:
            return dr.select(cos_a > 0, mi.Float(1.0), mi.Float(0.0))
        return dr.select(cos_a > 0, dr.power(dr.maximum(cos_a, 1e-30), self.n), 0.0)

    def _eval_pdf(self, wi, wo):
        cos_o = mi.Frame3f.cos_theta(wo)
        valid = (mi.Frame3f.cos_theta(wi) > 0) & (cos_o > 0)
        refl = mi.Vector3f(-wi.x, -wi.y, wi.z)
        lobe = self._cos_pow(dr.dot(refl, wo))
        f = self.kd * dr.inv_pi + self.ks * ((self.n + 2.0) * 0.5 * dr.inv_pi) * lobe
        pdf = self.p_diffuse * cos_o * dr.inv_pi + (1.0 - self.p_diffuse) * ((self.n + 1.0) * 0.5 * dr.inv_pi) * lobe
        return dr.select(valid, f * cos_o, 0.0), dr.select(valid, pdf, 0.0)

    def eval_diffuse_reflectance(self, si, active=True):
        return self.kd

    def sample(self, ctx, si, sample1, sample2, active=True):
        wi, _, flip = self._to_front(si, mi.Vector3f(0, 0, 1))
        diffuse = sample1 < self.p_diffuse
        wo_d = mi.warp.square_to_cosine_hemisphere(sample2)
        refl = mi.Vector3f(-wi.x, -wi.y, wi.z)
        cos_a = dr.power(sample2.x, 1.0 / (self.n + 1.0))
        sin_a = dr.safe_sqrt(1.0 - cos_a * cos_a)
        s, c = dr.sincos(2.0 * dr.pi * sample2.y)
        wo_g = mi.Frame3f(refl).to_world(mi.Vector3f(sin_a * c, sin_a * s, cos_a))
        wo = dr.select(diffuse, wo_d, wo_g)
        return self._sampled(wi, wo, flip, sample1 >= self.p_diffuse)

    def to_string(self):
        return f"PenumbraPhong[n={self.n}]"


# ---------------------------------------------------------------------------------------
# Ambient occlusion as Penumbra defines it: L = albedo/pi * int V cos over the hemisphere on
# the side facing the viewer, one direction per pixel sample; camera rays that miss see 1.
# ---------------------------------------------------------------------------------------
class PenumbraAO(mi.SamplingIntegrator):
    def __init__(self, props):
        mi.SamplingIntegrator.__init__(self, props)
        self.cosine = props.get("sampling", "cosine") == "cosine"
        self.max_distance = float(props.get("max_distance", 1e30))

    def sample(self, scene, sampler, ray, medium=None, active=True):
        si = scene.ray_intersect(ray, active)
        hit = active & si.is_valid()
        bsdf = si.bsdf(ray)
        albedo = bsdf.eval_diffuse_reflectance(si, hit)
        n = mi.Vector3f(si.sh_frame.n)
        n = dr.select(dr.dot(n, ray.d) > 0, -n, n)
        u = sampler.next_2d(hit)
        if self.cosine:
            local = mi.warp.square_to_cosine_hemisphere(u)
            weight = mi.Float(1.0)
        else:
            local = mi.warp.square_to_uniform_hemisphere(u)
            weight = 2.0 * local.z
        d = mi.Frame3f(n).to_world(local)
        # Offset from the side the ray goes out on (the shading frame may face away).
        ng = mi.Vector3f(si.n)
        ng = dr.select(dr.dot(ng, d) < 0, -ng, ng)
        origin = si.p + ng * (1e-4 * dr.maximum(1.0, dr.max(dr.abs(si.p))))
        shadow = mi.Ray3f(mi.Point3f(origin), d)
        shadow.maxt = mi.Float(self.max_distance)
        occluded = scene.ray_test(shadow, hit)
        radiance = dr.select(hit, mi.Color3f(albedo) * dr.select(occluded, 0.0, weight), mi.Color3f(1.0))
        return mi.Spectrum(radiance), mi.Bool(True), []

    def aov_names(self):
        return []

    def to_string(self):
        return "PenumbraAO[]"


_registered = False


def register_plugins():
    global _registered
    if not _registered:
        mi.register_bsdf("penumbra_phong", lambda props: PenumbraPhong(props))
        mi.register_integrator("penumbra_ao", lambda props: PenumbraAO(props))
        mi.register_bsdf("penumbra_pbr", lambda props: PenumbraPbr(props))
        mi.register_emitter("penumbra_spot", lambda props: PenumbraSpot(props))
        _registered = True


# ---------------------------------------------------------------------------------------
# Scene translation
# ---------------------------------------------------------------------------------------
class Unsupported(Exception):
    pass


def _v(a):
    return [float(x) for x in a]


def _colour(x):
    """A colour field: three numbers, or one number meaning grey."""
    return [float(x)] * 3 if isinstance(x, (int, float)) else _v(x)


def _rgb(v):
    return {"type": "rgb", "value": _v(v)}


def _bsdf(mat):
    if mat is None:
        return {"type": "twosided", "inner": {"type": "diffuse", "reflectance": _rgb([0.8] * 3)}}
    t = mat.get("type", "diffuse")
    textured = [k for k, v in mat.items() if isinstance(v, dict)]
    if textured:
        raise Unsupported(f"textured material field {textured[0]!r}")
    if t == "diffuse":
        return {"type": "twosided", "inner": {"type": "diffuse", "reflectance": _rgb(mat.get("albedo", [0.8] * 3))}}
    if t == "phong":
        kd, ks = mat.get("kd", [0.5] * 3), mat.get("ks", [0.5] * 3)
        d = {"type": "penumbra_phong", "exponent": float(mat.get("exponent", 20))}
        for i, c in enumerate("rgb"):
            d["kd_" + c] = float(kd[i])
            d["ks_" + c] = float(ks[i])
        return d
    if t == "pbr":
        return pbr_dict(mat.get("base_color", [0.8] * 3), mat.get("metallic", 0.0), mat.get("roughness", 0.5))
    raise Unsupported(f"material type {t!r}")


def _mesh_area(pos, idx):
    import numpy as np
    p = np.asarray(pos, dtype=np.float64).reshape(-1, 3)
    t = np.asarray(idx, dtype=np.int64).reshape(-1, 3)
    c = np.cross(p[t[:, 1]] - p[t[:, 0]], p[t[:, 2]] - p[t[:, 0]])
    return 0.5 * float(np.linalg.norm(c, axis=1).sum())


def _make_mesh(name, pos, idx, normals, bsdf, emitter):
    import numpy as np
    p = np.asarray(pos, dtype=np.float32)
    f = np.asarray(idx, dtype=np.uint32)
    props = mi.Properties()
    props["bsdf"] = mi.load_dict(bsdf)
    if emitter is not None:
        props["emitter"] = mi.load_dict(emitter)
    mesh = mi.Mesh(name, len(p) // 3, len(f) // 3, props=props, has_vertex_normals=normals is not None)
    params = mi.traverse(mesh)
    # The buffers' own types: mi.Float in the JIT variants, a dynamic array in scalar ones.
    params["vertex_positions"] = type(params["vertex_positions"])(p)
    params["faces"] = type(params["faces"])(f)
    if normals is not None:
        params["vertex_normals"] = type(params["vertex_normals"])(np.asarray(normals, dtype=np.float32))
    params.update()
    return mesh


def _ply_dict(shape, base_dir):
    """Mitsuba's ply plugin for a mesh `file`. Penumbra shades a mesh without normals with its
    faces' normals, where Mitsuba would compute smooth vertex normals: face_normals is set
    unless the file has normals of its own (then both interpolate them)."""
    path = os.path.join(base_dir, shape["file"])
    if not path.lower().endswith(".ply"):
        raise Unsupported(f"mesh file {shape['file']!r} (only PLY files are translated)")
    with open(path, "rb") as f:
        header = f.read(4096).split(b"end_header")[0].split()
    return {"type": "ply", "filename": path, "face_normals": b"nx" not in header}


def _ply_mesh(shape, base_dir):
    """The loaded mesh of a PLY `file` (its area and bounds)."""
    return mi.load_dict(_ply_dict(shape, base_dir))


def _scalar(x):
    """A one-element Dr.Jit array (JIT variants) or a Python float (scalar ones) as a float."""
    return float(x[0]) if dr.is_array_v(x) else float(x)


def _gltf_meshes(shape, base_dir):
    from penumbra_tools.gltf_meshes import read_gltf
    try:
        return read_gltf(os.path.join(base_dir, shape["file"]))
    except NotImplementedError as e:
        raise Unsupported(str(e))


def _bounds(scene, base_dir):
    lo, hi = [math.inf] * 3, [-math.inf] * 3

    def add(p):
        for i in range(3):
            lo[i] = min(lo[i], p[i])
            hi[i] = max(hi[i], p[i])

    for s in scene.get("shapes", []):
        t = s["type"]
        if t == "sphere":
            c, r = s["center"], s["radius"]
            add([c[i] - r for i in range(3)])
            add([c[i] + r for i in range(3)])
        elif t == "quad":
            o, u, v = s["origin"], s["edge_u"], s["edge_v"]
            for a in (0, 1):
                for b in (0, 1):
                    add([o[i] + a * u[i] + b * v[i] for i in range(3)])
        elif t == "mesh" and "file" in s:
            box = _ply_mesh(s, base_dir).bbox()
            add([_scalar(x) for x in box.min])
            add([_scalar(x) for x in box.max])
        elif t in ("mesh", "gltf"):
            import numpy as np
            ps = [np.asarray(s["positions"], dtype=np.float64).reshape(-1, 3)] if t == "mesh" else \
                [m[0] for m in _gltf_meshes(s, base_dir)]
            for p in ps:
                add(list(p.min(axis=0)))
                add(list(p.max(axis=0)))
    if lo[0] > hi[0]:
        return [0, 0, 0], 1.0
    c = [(lo[i] + hi[i]) / 2 for i in range(3)]
    return c, 0.5 * length(sub(hi, lo))


def translate(scene, spp=None, seed=None, sampler="independent", base_dir="."):
    """Returns a dict for mi.load_dict. Raises Unsupported for features Mitsuba cannot match.
    `sampler` is the Mitsuba sampler plugin (independent by default; ldsampler for the
    low-discrepancy time-to-error comparison); base_dir is the scene file's folder (files
    named in the scene are relative to it)."""
    register_plugins()
    cam = scene.get("camera", {})
    film = scene.get("film", {})
    smp = scene.get("sampler", {})
    integ = scene.get("integrator", {"type": "direct"})
    mats = scene.get("materials", {})
    W, H = int(film.get("width", 512)), int(film.get("height", 512))
    spp = int(spp if spp is not None else smp.get("spp", 16))
    seed = int(seed if seed is not None else smp.get("seed", 0))
    out = {
        "type": "scene",
        "sensor": {
            "type": "perspective",
            "fov_axis": "y",
            "fov": float(cam.get("fov_y", 40)),
            "to_world": mi.ScalarTransform4f().look_at(origin=_v(cam.get("eye", [0, 1, 5])),
                                                       target=_v(cam.get("target", [0, 1, 0])),
                                                       up=_v(cam.get("up", [0, 1, 0]))),
            "film": {"type": "hdrfilm", "width": W, "height": H, "rfilter": {"type": "box"},
                     "pixel_format": "rgb"},
            "sampler": {"type": sampler, "sample_count": spp, "seed": seed},
        },
    }
    if integ.get("type", "direct") == "ao":
        out["integrator"] = {"type": "penumbra_ao", "sampling": integ.get("sampling", "cosine"),
                             "max_distance": float(integ.get("max_distance", 1e30))}
        power_weights = False
    else:
        strategy = integ.get("strategy", "mis")
        if integ.get("heuristic", "power") != "power" and strategy == "mis":
            raise Unsupported("Mitsuba's direct integrator has only the power heuristic")
        if strategy == "mixture":
            raise Unsupported("Mitsuba's direct integrator has no one-sample mixture strategy")
        ls, bs = int(integ.get("light_samples", 1)), int(integ.get("bsdf_samples", 1))
        if strategy == "light":
            bs = 0
        elif strategy == "bsdf":
            ls = 0  # note: Mitsuba then drops delta lights, Penumbra still samples them
        out["integrator"] = {"type": "direct", "emitter_samples": ls, "bsdf_samples": bs}
        power_weights = integ.get("light_selection", "power") == "power"

    center, radius = _bounds(scene, base_dir)

    def weight(p):
        return max(sum(p) / 3.0, 1e-12) if power_weights else 1.0

    for k, s in enumerate(scene.get("shapes", [])):
        t = s["type"]
        if t == "gltf":
            _add_gltf(out, f"shape{k:03d}", s, mats, base_dir, weight)
            continue
        mname = s.get("material")
        bsdf = _bsdf(mats[mname] if mname is not None else None)
        if s.get("two_sided") and ("emission" in s or "power" in s):
            raise Unsupported("two-sided area lights (Mitsuba's area emitter is one-sided)")
        if s.get("to_world") is not None:
            raise Unsupported(f"{t} shape with to_world")
        ply = _ply_mesh(s, base_dir) if t == "mesh" and "file" in s else None
        # Radiance and emitted power (for the emitter's selection weight).
        if t == "sphere":
            area = 4 * math.pi * s["radius"] ** 2
        elif t == "quad":
            area = length(cross(s["edge_u"], s["edge_v"]))
        elif ply is not None:
            area = _scalar(ply.surface_area())
        elif t == "mesh":
            area = _mesh_area(s["positions"], s["indices"])
        else:
            raise Unsupported(f"shape type {t!r}")
        emitter = None
        if "power" in s:
            P = _colour(s["power"])
            Le = [p / (4 * math.pi ** 2 * s["radius"] ** 2) for p in P] if t == "sphere" else \
                 [p / (math.pi * area) for p in P]
        else:
            Le = _colour(s.get("emission", [0, 0, 0]))
        if max(Le) > 0:
            P = [l * math.pi * area for l in Le]
            emitter = {"type": "area", "radiance": _rgb(Le), "sampling_weight": weight(P)}
        name = f"shape{k:03d}"
        if t == "sphere":
            d = {"type": "sphere", "center": _v(s["center"]), "radius": float(s["radius"]), "bsdf": bsdf}
        elif t == "quad":
            o, u, v = _v(s["origin"]), _v(s["edge_u"]), _v(s["edge_v"])
            n = cross(u, v)
            nn = length(n)
            if abs(dot(u, v)) <= 1e-6 * length(u) * length(v):
                n = [x / nn for x in n]
                c = [o[i] + 0.5 * (u[i] + v[i]) for i in range(3)]
                m = [[0.5 * u[0], 0.5 * v[0], n[0], c[0]],
                     [0.5 * u[1], 0.5 * v[1], n[1], c[1]],
                     [0.5 * u[2], 0.5 * v[2], n[2], c[2]],
                     [0, 0, 0, 1]]
                d = {"type": "rectangle", "to_world": mi.ScalarTransform4f(m), "bsdf": bsdf}
            else:
                pos = o + [o[i] + u[i] for i in range(3)] + [o[i] + u[i] + v[i] for i in range(3)] + \
                      [o[i] + v[i] for i in range(3)]
                out[name] = _make_mesh(name, pos, [0, 1, 2, 0, 2, 3], None, bsdf, emitter)
                continue
        elif ply is not None:
            d = _ply_dict(s, base_dir)
            d["bsdf"] = bsdf
        else:
            out[name] = _make_mesh(name, s["positions"], s["indices"], s.get("normals"), bsdf, emitter)
            continue
        if emitter is not None:
            d["emitter"] = emitter
        out[name] = d

    for k, l in enumerate(scene.get("lights", [])):
        t = l["type"]
        name = f"light{k:03d}"
        if t == "point":
            I = _colour(l["intensity"]) if "intensity" in l else [p / (4 * math.pi) for p in _colour(l["power"])]
            out[name] = {"type": "point", "position": _v(l["position"]), "intensity": _rgb(I),
                         "sampling_weight": weight([4 * math.pi * i for i in I])}
        elif t == "spot":
            out[name] = spot_dict(l, weight)
        elif t == "directional":
            E = _v(l["irradiance"])
            out[name] = {"type": "directional", "direction": _v(l["direction"]), "irradiance": _rgb(E),
                         "sampling_weight": weight([math.pi * radius ** 2 * e for e in E])}
        elif t == "environment":
            L = _v(l.get("radiance", [1, 1, 1]))
            if "file" in l:
                from penumbra_tools.mitsuba_envmap import envmap_dict
                out[name] = envmap_dict(os.path.join(base_dir, l["file"]), L, radius, power_weights)
                continue
            out[name] = {"type": "constant", "radiance": _rgb(L),
                         "sampling_weight": weight([4 * math.pi ** 2 * radius ** 2 * x for x in L])}
        else:
            raise Unsupported(f"light type {t!r}")
    return out


def _emitter(Le, area, weight):
    if max(Le) <= 0:
        return None
    return {"type": "area", "radiance": _rgb(Le), "sampling_weight": weight([x * math.pi * area for x in Le])}


def _add_gltf(out, name, s, mats, base_dir, weight):
    """A `gltf` shape: one mesh per triangle primitive. The shape's own `material` or
    `emission`/`power` replaces the file's for all its primitives (docs/SCENE_FORMAT.md)."""
    if s.get("two_sided") or s.get("to_world") is not None:
        raise Unsupported("gltf shape with two_sided or to_world")
    meshes = _gltf_meshes(s, base_dir)
    own_bsdf = _bsdf(mats[s["material"]]) if "material" in s else None
    total_area = sum(_mesh_area(p, i) for p, i, _, _ in meshes)
    for j, (p, idx, n, factors) in enumerate(meshes):
        area = _mesh_area(p, idx)
        if own_bsdf is not None:
            bsdf = own_bsdf
        elif factors is None:
            bsdf = _bsdf(None)
        else:
            bsdf = pbr_dict(*factors[:3])
        if "power" in s:  # the shape's power is spread over all its primitives' area
            Le = [x / (math.pi * total_area) for x in _colour(s["power"])]
        elif "emission" in s:
            Le = _colour(s["emission"])
        else:
            Le = factors[3] if factors is not None else [0.0] * 3
            if factors is not None and factors[4] and max(Le) > 0:
                raise Unsupported("double-sided emissive glTF material (Mitsuba's area emitter is one-sided)")
        mname = f"{name}_{j:03d}"
        out[mname] = _make_mesh(mname, p.reshape(-1), idx.reshape(-1), None if n is None else n.reshape(-1),
                                bsdf, _emitter(Le, area, weight))
