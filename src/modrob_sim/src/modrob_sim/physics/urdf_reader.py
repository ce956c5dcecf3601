"""URDF (+ Gazebo extension tags) -> ModelDesc.

Read with ElementTree rather than urdf_parser_py: we need the <gazebo> extension elements (which
urdf_parser_py drops), the <sensor>/<plugin> Elements for plugins, and error messages that name
the model, link and joint (urdf_parser_py prints to stderr and carries on).
"""

from . import limits
from .description import (JOINT_TYPES, GeometryDesc, JointDesc, LinkDesc, ModelDesc,
                          PluginSpec)
from .gripper import read_gripper
from .sdf_reader import collision_surface
from .transforms import IDENTITY_POSE, quat_from_rpy
from .xml_util import Reader, local, parse_xml

# Gazebo extension tags with a physics meaning here (per link), and accepted ones that are only
# stored (per link or joint) so that plugins can read them; anything else is warned about once.
LINK_TAGS = ("mu1", "mu2", "kp", "kd", "maxVel", "minDepth", "fdir1", "maxContacts", "material",
             "selfCollide", "gravity", "turnGravityOff")
LINK_ACCEPTED = ("sensor", "visual", "collision", "dampingFactor",
                 "laserRetro", "velocity_decay", "plugin", "enableWind", "kinematic")
JOINT_ACCEPTED = ("implicitSpringDamper", "provideFeedback", "stopCfm", "stopErp", "cfmDamping",
                  "fudgeFactor", "springStiffness", "springReference", "disableFixedJointLumping",
                  "preserveFixedJoint", "physics", "sensor", "plugin")
MODEL_TAGS = ("plugin", "static", "self_collide", "selfCollide")


def _origin(rd, elem, where):
    o = elem.find("origin") if elem is not None else None
    if o is None:
        return IDENTITY_POSE
    xyz = rd.floats(o.get("xyz", "0 0 0"), 3, where, "<origin xyz>")
    rpy = rd.floats(o.get("rpy", "0 0 0"), 3, where, "<origin rpy>")
    return (xyz, quat_from_rpy(*rpy))


def _geometry(rd, elem, where, tagname):
    geo = elem.find("geometry")
    if geo is None or len(geo) == 0:
        rd.fail(where, "<%s> has no <geometry>" % tagname)
    g = geo[0]
    kind = local(g.tag)
    origin = _origin(rd, elem, where)
    name = elem.get("name")
    if kind == "box":
        size = rd.floats(g.get("size"), 3, where, "<box size>")
        if min(size) <= 0:
            rd.fail(where, "<box size='%s'> must be positive" % g.get("size"))
        return GeometryDesc("box", size, origin, name=name)
    if kind == "cylinder":
        r = rd.float(g.get("radius"), where, "<cylinder radius>")
        length = rd.float(g.get("length"), where, "<cylinder length>")
        if r <= 0 or length <= 0:
            rd.fail(where, "<cylinder radius length> must be positive")
        return GeometryDesc("cylinder", (r, length), origin, name=name)
    if kind == "sphere":
        r = rd.float(g.get("radius"), where, "<sphere radius>")
        if r <= 0:
            rd.fail(where, "<sphere radius> must be positive")
        return GeometryDesc("sphere", (r,), origin, name=name)
    if kind == "mesh":
        uri = g.get("filename")
        if not uri:
            rd.fail(where, "<mesh> needs a filename")
        scale = rd.floats(g.get("scale", "1 1 1"), 3, where, "<mesh scale>")
        if min(abs(s) for s in scale) == 0:
            rd.fail(where, "<mesh scale='%s'> has a zero factor" % g.get("scale"))
        return GeometryDesc("mesh", scale, origin, uri=uri, name=name)
    if kind == "capsule":
        r = rd.float(g.get("radius"), where, "<capsule radius>")
        length = rd.float(g.get("length"), where, "<capsule length>")
        return GeometryDesc("capsule", (r, length), origin, name=name)
    rd.fail(where, "unknown geometry <%s> (box, cylinder, sphere, mesh are supported)" % kind)


def _material_color(elem, materials):
    m = elem.find("material")
    if m is None:
        return None, None
    name = m.get("name")
    c = m.find("color")
    if c is not None and c.get("rgba"):
        try:
            return name, tuple(float(x) for x in c.get("rgba").split())
        except ValueError:
            return name, None
    return name, materials.get(name)


def read_urdf(name, xml_text, warn):
    """Parse URDF text into a ModelDesc. ``warn(key, message)`` logs a message once per key."""
    rd = Reader(name, "URDF")
    root = parse_xml(xml_text, name, "URDF")
    if local(root.tag) != "robot":
        rd.fail("root element", "expected <robot>, found <%s>" % local(root.tag))
    desc = ModelDesc(name, "urdf", xml_text)

    materials = {}
    for m in root.findall("material"):
        c = m.find("color")
        if m.get("name") and c is not None and c.get("rgba"):
            try:
                materials[m.get("name")] = tuple(float(x) for x in c.get("rgba").split())
            except ValueError:
                pass

    for le in root.findall("link"):
        lname = le.get("name")
        if not lname:
            rd.fail("<link>", "a <link> has no name")
        if lname in desc.links:
            rd.fail("link '%s'" % lname, "two links are named '%s'" % lname)
        where = "link '%s'" % lname
        link = LinkDesc(lname)
        ine = le.find("inertial")
        if ine is not None:
            link.has_inertial = True
            me = ine.find("mass")
            link.mass = rd.float(me.get("value") if me is not None else None, where, "<mass value>")
            if link.mass < 0:
                rd.fail(where, "<mass value='%s'> is negative" % me.get("value"))
            link.inertial_origin = _origin(rd, ine, where)
            ie = ine.find("inertia")
            if ie is not None:
                link.inertia = tuple(rd.float(ie.get(k), where, "<inertia %s>" % k, 0.0)
                                     for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"))
        for ce in le.findall("collision"):
            link.collisions.append(_geometry(rd, ce, where, "collision"))
        for ve in le.findall("visual"):
            g = _geometry(rd, ve, where, "visual")
            g.material, g.color = _material_color(ve, materials)
            link.visuals.append(g)
        desc.links[lname] = link

    if not desc.links:
        rd.fail("<robot name='%s'>" % root.get("name", ""), "the URDF has no <link>")

    parents = {}
    for je in root.findall("joint"):
        jname = je.get("name")
        if not jname:
            rd.fail("<joint>", "a <joint> has no name")
        if jname in desc.joints:
            rd.fail("joint '%s'" % jname, "two joints are named '%s'" % jname)
        where = "joint '%s'" % jname
        jtype = je.get("type")
        if jtype not in JOINT_TYPES:
            rd.fail(where, "type '%s' is not one of %s" % (jtype, ", ".join(JOINT_TYPES)))
        pe, ce = je.find("parent"), je.find("child")
        if pe is None or ce is None or not pe.get("link") or not ce.get("link"):
            rd.fail(where, "needs <parent link=...> and <child link=...>")
        parent, child = pe.get("link"), ce.get("link")
        if parent not in desc.links and parent != "world":
            rd.fail(where, "parent link '%s' does not exist" % parent)
        if child not in desc.links:
            rd.fail(where, "child link '%s' does not exist" % child)
        if child in parents:
            rd.fail(where, "link '%s' is the child of two joints ('%s' and '%s')"
                    % (child, parents[child], jname))
        parents[child] = jname
        j = JointDesc(jname, jtype, parent, child)
        j.origin = _origin(rd, je, where)
        ae = je.find("axis")
        if ae is not None:
            axis = rd.floats(ae.get("xyz", "1 0 0"), 3, where, "<axis xyz>")
            if jtype in ("revolute", "continuous", "prismatic", "planar"):
                limits.check_axis(name, where, "<axis xyz>", axis)
                j.axis = limits.normalized_axis(axis)
        le = je.find("limit")
        if le is not None:
            j.effort_limit = rd.float(le.get("effort"), where, "<limit effort>", 0.0)
            j.velocity_limit = rd.float(le.get("velocity"), where, "<limit velocity>", 0.0)
            if jtype in ("revolute", "prismatic"):
                j.lower = rd.float(le.get("lower"), where, "<limit lower>", 0.0)
                j.upper = rd.float(le.get("upper"), where, "<limit upper>", 0.0)
                if j.lower > j.upper:
                    rd.fail(where, "<limit lower='%s' upper='%s'>: lower is above upper"
                            % (le.get("lower"), le.get("upper")))
        elif jtype in ("revolute", "prismatic"):
            rd.fail(where, "a %s joint needs <limit lower upper effort velocity> (as urdfdom requires)"
                    % jtype)
        de = je.find("dynamics")
        if de is not None:
            j.damping = rd.float(de.get("damping"), where, "<dynamics damping>", 0.0)
            j.friction = rd.float(de.get("friction"), where, "<dynamics friction>", 0.0)
            if j.damping < 0 or j.friction < 0:
                rd.fail(where, "<dynamics damping friction> must not be negative")
        me = je.find("mimic")
        if me is not None:
            if not me.get("joint"):
                rd.fail(where, "<mimic> needs joint=...")
            j.mimic = (me.get("joint"), rd.float(me.get("multiplier"), where, "<mimic multiplier>", 1.0),
                       rd.float(me.get("offset"), where, "<mimic offset>", 0.0))
        desc.joints[jname] = j

    for j in desc.joints.values():
        if j.mimic is not None:
            m = desc.joints.get(j.mimic[0])
            if m is None:
                rd.fail("joint '%s'" % j.name, "<mimic joint='%s'> does not exist" % j.mimic[0])
            if m.mimic is not None or m is j:
                rd.fail("joint '%s'" % j.name, "mimics '%s', which is itself a mimic joint" % m.name)
            if m.type not in ("revolute", "continuous", "prismatic") or \
                    j.type not in ("revolute", "continuous", "prismatic"):
                rd.fail("joint '%s'" % j.name, "mimic is supported between revolute, continuous "
                        "and prismatic joints")

    # the tree: one root, no cycles
    roots = [ln for ln in desc.links if ln not in parents and ln != "world"]
    world_joints = [j for j in desc.joints.values() if j.parent == "world"]
    if world_joints:
        desc.root = "world"
        if roots:
            rd.fail("tree", "link '%s' has no parent joint, but the model is attached to 'world' by "
                    "joint '%s': connect it" % (roots[0], world_joints[0].name))
    else:
        if len(roots) != 1:
            rd.fail("tree", "expected exactly one root link, found %d (%s)"
                    % (len(roots), ", ".join(roots) or "a cycle"))
        desc.root = roots[0]
    seen = set()
    stack = [desc.root]
    children = {}
    for j in desc.joints.values():
        children.setdefault(j.parent, []).append(j.child)
    while stack:
        ln = stack.pop()
        if ln in seen:
            rd.fail("tree", "the joints form a cycle at link '%s'" % ln)
        seen.add(ln)
        stack.extend(children.get(ln, ()))
    unreached = [ln for ln in desc.links if ln not in seen and ln != "world"]
    if unreached:
        rd.fail("tree", "links not connected to the root '%s': %s" % (desc.root, ", ".join(unreached)))

    _read_gazebo(rd, root, desc, name, warn)
    return limits.validate_model(desc)


def _value_attributes_as_text(ge, name, warn):
    """Gazebo's URDF conversion reads a key as ``<mu1 value="1"/>`` as well as ``<mu1>1</mu1>``
    (the attribute wins): turn the attribute form into the element form, so that every reader of
    these elements (contacts, joints, plugins' own look-ups) sees one form. Plugins and sensors
    inside the block are left as they are (Gazebo copies them verbatim)."""
    for c in ge:
        if local(c.tag) in ("plugin", "sensor") or c.get("value") is None:
            continue
        warn("urdf-value-attribute:%s:%s" % (name, local(c.tag)),
             "model '%s': <gazebo><%s value=\"%s\"/> read as <%s>%s</%s>, as Gazebo's URDF conversion "
             "does" % (name, local(c.tag), c.get("value"), local(c.tag), c.get("value"), local(c.tag)))
        c.text = c.get("value")


def _read_gazebo(rd, root, desc, name, warn):
    for ge in root.findall("gazebo"):
        ref = ge.get("reference")
        _value_attributes_as_text(ge, name, warn)
        if ref is None:
            for c in ge:
                tag = local(c.tag)
                if tag == "plugin":
                    desc.plugins.append(_plugin(rd, c, None, None))
                elif tag == "static":
                    desc.static = rd.bool(c.text, "<gazebo><static>", "static")
                elif tag in ("self_collide", "selfCollide"):
                    desc.self_collide = rd.bool(c.text, "<gazebo><self_collide>", "self_collide")
                elif tag == "gripper":
                    desc.grippers.append(read_gripper(rd, c, "<gazebo>", local))
                else:
                    warn("urdf-model-tag:" + tag, "model '%s': <gazebo><%s> is not supported here; "
                         "ignored" % (name, tag))
            continue
        if ref in desc.links:
            _gazebo_link(rd, ge, desc.links[ref], desc, name, warn)
        elif ref in desc.joints:
            j = desc.joints[ref]
            for c in ge:
                tag = local(c.tag)
                if tag == "sensor":
                    # a joint's sensor (force_torque): its plugins see the joint's child link,
                    # whose parent joint this is
                    for pe in c.findall("plugin"):
                        desc.plugins.append(_plugin(rd, pe, j.child, c))
                if tag in JOINT_ACCEPTED:
                    j.extra[tag] = c
                else:
                    warn("urdf-joint-tag:" + tag, "model '%s' joint '%s': <gazebo><%s> is not "
                         "supported; ignored" % (name, ref, tag))
        else:
            # Gazebo's URDF conversion drops a block whose reference names nothing (UR's ee_link)
            warn("urdf-dangling-reference:%s:%s" % (name, ref),
                 "model '%s': <gazebo reference='%s'> names no link or joint of the model; the block "
                 "is ignored, as Gazebo ignores it (links: %s)" % (name, ref, ", ".join(desc.links)))


def _gazebo_link(rd, ge, link, desc, name, warn):
    where = "<gazebo reference='%s'>" % link.name
    # a <collision> block goes into each of the link's collisions, as sdformat converts it for
    # Gazebo: its <max_contacts>, and its <surface> in place of what they had; then the block's own
    # tags (<mu1> ...) on top
    for c in ge:
        if local(c.tag) == "collision":
            link.surface = collision_surface(rd, c, where + "<collision>", base=link.surface)
    s = link.surface
    for c in ge:
        tag = local(c.tag)
        text = (c.text or "").strip()
        if tag == "mu1":
            s.mu1 = rd.float(text, where, "<mu1>")
        elif tag == "mu2":
            s.mu2 = rd.float(text, where, "<mu2>")
        elif tag == "kp":
            s.kp = rd.float(text, where, "<kp>")
        elif tag == "kd":
            s.kd = rd.float(text, where, "<kd>")
        elif tag == "maxVel":
            s.max_vel = rd.float(text, where, "<maxVel>")
        elif tag == "minDepth":
            s.min_depth = rd.float(text, where, "<minDepth>")
        elif tag == "fdir1":
            s.fdir1 = rd.floats(text, 3, where, "<fdir1>")
        elif tag == "maxContacts":
            s.max_contacts = rd.int(text, where, "<maxContacts>")
        elif tag == "material":
            link.material = text
        elif tag == "selfCollide":
            link.self_collide = rd.bool(text, where, "<selfCollide>")
        elif tag == "gravity":
            link.gravity = rd.bool(text, where, "<gravity>")
        elif tag == "turnGravityOff":
            link.gravity = not rd.bool(text, where, "<turnGravityOff>")
        elif tag == "sensor":
            link.sensors.append(c)
            for pe in c.findall("plugin"):
                desc.plugins.append(_plugin(rd, pe, link.name, c))
        elif tag == "plugin":
            desc.plugins.append(_plugin(rd, c, link.name, None))
        elif tag in LINK_ACCEPTED:
            link.extra[tag] = c
        else:
            warn("urdf-link-tag:" + tag, "model '%s' link '%s': <gazebo><%s> is not supported; "
                 "ignored" % (name, link.name, tag))
    for v, what in ((s.mu1, "mu1"), (s.mu2, "mu2"), (s.max_vel, "maxVel"), (s.min_depth or 0.0, "minDepth"),
                    (s.max_contacts, "maxContacts")):
        if v < 0:
            rd.fail(where, "<%s> must not be negative" % what)
    if s.kp <= 0 or s.kd < 0:
        rd.fail(where, "<kp> must be positive and <kd> not negative")


def _plugin(rd, elem, link, sensor):
    ns_elem = elem.find("robotNamespace")
    ns = ns_elem.text.strip() if ns_elem is not None and ns_elem.text else None
    return PluginSpec(elem.get("name", ""), elem.get("filename", ""), elem, ns, link, sensor)
