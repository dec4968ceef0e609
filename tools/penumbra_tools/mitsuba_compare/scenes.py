"""What the comparison reads from a Penumbra scene file: film size, spp, and whether the
Mitsuba translation calls back into Python (tools/penumbra_tools/mitsuba_penumbra.py's plugins)."""
import json


def load_scene(path, width=None, height=None):
    with open(path) as f:
        scene = json.load(f)
    if width:
        scene.setdefault("film", {})["width"] = width
        scene["film"]["height"] = height
    return scene


def film_size(scene):
    f = scene.get("film", {})
    return int(f.get("width", 512)), int(f.get("height", 512))


def scene_spp(scene):
    return int(scene.get("sampler", {}).get("spp", 16))


def uses_python_plugins(scene):
    """True when the translated scene calls back into Python (phong or ao), which makes
    Mitsuba's scalar variant slow."""
    if scene.get("integrator", {}).get("type") == "ao":
        return True
    return any(m.get("type") in ("phong", "pbr") for m in scene.get("materials", {}).values()) or \
        any(s.get("type") == "gltf" for s in scene.get("shapes", []))
