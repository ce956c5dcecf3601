"""What the node needs to know about a model's description beyond the physics core: the visual
geometry of each link (for the world MarkerArray), collision names and inertial origins (for
get_model_properties / get_link_properties). Parsed from the URDF or SDF text (pure, no rospy).

A visual is ``Visual(link, origin, kind, size, filename, scale, rgba)`` with ``origin`` the pose of
the geometry in the LINK frame, kind one of box / cylinder / sphere / mesh / plane.
"""
import collections
import xml.etree.ElementTree as ET

from modrob_sim.gazebo_ros import transforms as tf

Visual = collections.namedtuple("Visual", "link origin kind size filename scale rgba")
LinkInfo = collections.namedtuple("LinkInfo", "visuals collision_names inertial_origin")

DEFAULT_RGBA = (0.7, 0.7, 0.7, 1.0)

#: Colours of Gazebo's stock materials (Gazebo/<Name>), as gzclient shows them.
GAZEBO_MATERIALS = {
    "Gazebo/White": (1.0, 1.0, 1.0, 1.0), "Gazebo/Grey": (0.7, 0.7, 0.7, 1.0),
    "Gazebo/Gray": (0.7, 0.7, 0.7, 1.0), "Gazebo/DarkGrey": (0.35, 0.35, 0.35, 1.0),
    "Gazebo/DarkGray": (0.35, 0.35, 0.35, 1.0), "Gazebo/Black": (0.05, 0.05, 0.05, 1.0),
    "Gazebo/Red": (1.0, 0.0, 0.0, 1.0), "Gazebo/RedBright": (0.87, 0.26, 0.07, 1.0),
    "Gazebo/Green": (0.0, 1.0, 0.0, 1.0), "Gazebo/Blue": (0.0, 0.0, 1.0, 1.0),
    "Gazebo/SkyBlue": (0.53, 0.81, 0.92, 1.0), "Gazebo/Yellow": (1.0, 1.0, 0.0, 1.0),
    "Gazebo/Orange": (1.0, 0.5, 0.09, 1.0), "Gazebo/Purple": (0.5, 0.0, 0.5, 1.0),
    "Gazebo/Turquoise": (0.0, 0.8, 0.8, 1.0), "Gazebo/Wood": (0.55, 0.37, 0.2, 1.0),
    "Gazebo/WoodFloor": (0.6, 0.45, 0.3, 1.0), "Gazebo/Indigo": (0.29, 0.0, 0.51, 1.0),
    "Gazebo/ZincYellow": (0.9, 0.85, 0.0, 1.0), "Gazebo/Residential": (0.85, 0.8, 0.7, 1.0),
}


def _floats(text, n, default):
    if text is None:
        return default
    try:
        vals = tuple(float(v) for v in text.split())
    except ValueError:
        return default
    return vals if len(vals) == n else default


def _urdf_origin(elem):
    o = elem.find("origin") if elem is not None else None
    if o is None:
        return tf.IDENTITY
    xyz = _floats(o.get("xyz"), 3, (0.0, 0.0, 0.0))
    rpy = _floats(o.get("rpy"), 3, (0.0, 0.0, 0.0))
    return (xyz, tf.quat_from_rpy(*rpy))


def _sdf_pose(elem):
    p = elem.find("pose") if elem is not None else None
    if p is None or not (p.text or "").strip():
        return tf.IDENTITY
    v = _floats(p.text, 6, (0.0,) * 6)
    return (v[:3], tf.quat_from_rpy(*v[3:]))


def _geometry(geom):
    """(kind, size, filename, scale) of a URDF or SDF <geometry>, or None."""
    if geom is None:
        return None
    for child in geom:
        tag = child.tag
        if tag == "box":
            size = child.get("size") or (child.findtext("size") or "")
            return ("box", _floats(size, 3, (0.1, 0.1, 0.1)), None, (1.0, 1.0, 1.0))
        if tag == "cylinder":
            r = child.get("radius") or child.findtext("radius") or "0.05"
            length = child.get("length") or child.findtext("length") or "0.1"
            return ("cylinder", (float(r), float(length)), None, (1.0, 1.0, 1.0))
        if tag == "sphere":
            r = child.get("radius") or child.findtext("radius") or "0.05"
            return ("sphere", (float(r),), None, (1.0, 1.0, 1.0))
        if tag == "mesh":
            filename = child.get("filename") or (child.findtext("uri") or "").strip()
            scale = child.get("scale") or child.findtext("scale")
            return ("mesh", (), filename, _floats(scale, 3, (1.0, 1.0, 1.0)))
        if tag == "plane":
            size = _floats(child.findtext("size"), 2, (100.0, 100.0))
            return ("plane", size, None, (1.0, 1.0, 1.0))
    return None


def _urdf_links(root):
    materials = {}
    for m in root.findall("material"):
        c = m.find("color")
        if m.get("name") and c is not None:
            materials[m.get("name")] = _floats(c.get("rgba"), 4, DEFAULT_RGBA)
    gazebo_material = {}
    for g in root.findall("gazebo"):
        ref = g.get("reference")
        mat = (g.findtext("material") or "").strip()
        if ref and mat:
            gazebo_material[ref] = GAZEBO_MATERIALS.get(mat)
    links = collections.OrderedDict()
    for link in root.findall("link"):
        name = link.get("name")
        visuals = []
        for vis in link.findall("visual"):
            g = _geometry(vis.find("geometry"))
            if g is None:
                continue
            rgba = None
            m = vis.find("material")
            if m is not None:
                c = m.find("color")
                rgba = _floats(c.get("rgba"), 4, None) if c is not None else materials.get(m.get("name"))
            if gazebo_material.get(name) is not None:
                rgba = gazebo_material[name]
            visuals.append(Visual(name, _urdf_origin(vis), g[0], g[1], g[2], g[3], rgba or DEFAULT_RGBA))
        collisions = []
        for i, col in enumerate(link.findall("collision")):
            default = "%s_collision" % name if i == 0 else "%s_collision_%d" % (name, i)
            collisions.append(col.get("name") or default)
        links[name] = LinkInfo(visuals, collisions, _urdf_origin(link.find("inertial")))
    return links


def _sdf_rgba(vis):
    mat = vis.find("material")
    if mat is None:
        return DEFAULT_RGBA
    for tag in ("diffuse", "ambient"):
        v = _floats(mat.findtext(tag), 4, None)
        if v is not None:
            return v
    name = (mat.findtext("script/name") or "").strip()
    return GAZEBO_MATERIALS.get(name, DEFAULT_RGBA)


def _sdf_model_links(model):
    links = collections.OrderedDict()
    for link in model.findall("link"):
        name = link.get("name")
        visuals = []
        for vis in link.findall("visual"):
            g = _geometry(vis.find("geometry"))
            if g is None:
                continue
            visuals.append(Visual(name, _sdf_pose(vis), g[0], g[1], g[2], g[3], _sdf_rgba(vis)))
        collisions = [c.get("name") or "collision" for c in link.findall("collision")]
        links[name] = LinkInfo(visuals, collisions, _sdf_pose(link.find("inertial")))
    return links


#: Models that Gazebo's <include> of model://NAME brings, for the ones we know.
BUILTIN_INCLUDES = {
    "ground_plane": {"link": LinkInfo(
        [Visual("link", tf.IDENTITY, "plane", (100.0, 100.0), None, (1.0, 1.0, 1.0), (0.8, 0.8, 0.8, 1.0))],
        ["collision"], tf.IDENTITY)},
    "sun": {},
}


def parse_links(xml_text, model_name=None):
    """``{link_name: LinkInfo}`` of a URDF ``<robot>`` or of the SDF model called ``model_name``
    (searched in ``<sdf>``, ``<world>`` or a bare ``<model>``). Unknown or unparsable text gives {}."""
    try:
        root = ET.fromstring(xml_text)
    except (ET.ParseError, TypeError, ValueError):
        return {}
    if root.tag == "robot":
        return _urdf_links(root)
    models = [root] if root.tag == "model" else list(root.iter("model"))
    for m in models:
        if model_name is None or m.get("name") == model_name:
            return _sdf_model_links(m)
    for inc in root.iter("include"):
        uri = (inc.findtext("uri") or "").strip()
        base = uri.split("://", 1)[-1].strip("/")
        name = (inc.findtext("name") or "").strip() or base
        if (model_name is None or name == model_name) and base in BUILTIN_INCLUDES:
            return dict(BUILTIN_INCLUDES[base])
    if len(models) == 1 and model_name is not None:
        return _sdf_model_links(models[0])
    return {}


def xml_kind(xml_text):
    """"urdf" for a <robot>, "sdf" for <sdf>/<model>/<world>, None when not XML of either kind."""
    try:
        root = ET.fromstring(xml_text)
    except (ET.ParseError, TypeError, ValueError):
        return None
    if root.tag == "robot":
        return "urdf"
    if root.tag in ("sdf", "model", "world"):
        return "sdf"
    return None
