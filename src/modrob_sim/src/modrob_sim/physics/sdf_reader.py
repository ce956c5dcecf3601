"""A documented SDF subset -> ModelDesc list (see docs/physics.md, "SDF subset").

<sdf><world> with <include> of model://ground_plane and model://sun (built in; other model://
includes are read from <dir>/model.sdf found through the resolver or GAZEBO_MODEL_PATH), <gravity>
and <physics> (applied to the World by add_sdf), and <model>s; or one <model> alone.
<model>: <static>, <pose>, <self_collide>, <plugin>, <link> (<pose>, <inertial> with <mass>,
<pose>, <inertia>, <collision>/<visual> with <pose> and box, cylinder, sphere, plane, mesh
(<uri>, <scale>) geometry, <surface><friction><ode><mu><mu2>, <surface><contact><ode><kp><kd>
<max_vel><min_depth>, <gravity>, <self_collide>, <sensor>), <joint> revolute, continuous,
prismatic, fixed (<parent>, <child>, <pose> in the child frame, <axis><xyz> in the joint frame
or the model frame with <use_parent_model_frame>/expressed_in="__model__", <limit>, <dynamics>).
Links not connected by joints are free bodies. Poses are "x y z roll pitch yaw"; `relative_to`
other than the defaults is not supported and is refused.
"""
import os
import xml.etree.ElementTree as ET

from ..errors import ModelError
from . import limits
from .description import (GeometryDesc, JointDesc, LinkDesc, ModelDesc, PluginSpec, Surface)
from .meshes import default_resolver
from .sdf_versions import upgrade
from .gripper import read_gripper
from .transforms import IDENTITY_POSE, pose_inv, pose_mul, quat_from_rpy, quat_rotate, rpy_from_quat
from .xml_util import Reader, local, parse_xml

SDF_JOINT_TYPES = {"revolute": "revolute", "continuous": "continuous", "prismatic": "prismatic",
                   "fixed": "fixed"}
GROUND_PLANE = """<model name="ground_plane"><static>true</static><link name="link">
  <collision name="collision"><geometry><plane><normal>0 0 1</normal><size>100 100</size></plane>
  </geometry><surface><friction><ode><mu>100</mu><mu2>50</mu2></ode></friction></surface></collision>
  <visual name="visual"><geometry><plane><normal>0 0 1</normal><size>100 100</size></plane></geometry>
  <material><ambient>0.8 0.8 0.8 1</ambient><diffuse>0.8 0.8 0.8 1</diffuse></material></visual>
</link></model>"""


def _child(elem, tag):
    for c in elem:
        if local(c.tag) == tag:
            return c
    return None


def _children(elem, tag):
    return [c for c in elem if local(c.tag) == tag]


def _text(elem, tag, default=None):
    c = _child(elem, tag) if elem is not None else None
    if c is None or c.text is None:
        return default
    return c.text.strip()


def _pose(rd, elem, where):
    pe = _child(elem, "pose") if elem is not None else None
    if pe is None:
        return IDENTITY_POSE
    rel = pe.get("relative_to")
    if rel:
        rd.fail(where, "<pose relative_to='%s'> is not supported (poses are relative to the default "
                "frame)" % rel)
    v = rd.floats((pe.text or "0 0 0 0 0 0").strip(), 6, where, "<pose>")
    return (v[:3], quat_from_rpy(*v[3:]))


def _geometry(rd, elem, where):
    geo = _child(elem, "geometry")
    if geo is None or len(geo) == 0:
        rd.fail(where, "<%s> has no <geometry>" % local(elem.tag))
    g = geo[0]
    kind = local(g.tag)
    origin = _pose(rd, elem, where)
    name = elem.get("name")
    if kind == "box":
        size = rd.floats(_text(g, "size"), 3, where, "<box><size>")
        if min(size) <= 0:
            rd.fail(where, "<box><size> must be positive")
        return GeometryDesc("box", size, origin, name=name)
    if kind == "cylinder":
        r = rd.float(_text(g, "radius"), where, "<cylinder><radius>")
        length = rd.float(_text(g, "length"), where, "<cylinder><length>")
        if r <= 0 or length <= 0:
            rd.fail(where, "<cylinder> radius and length must be positive")
        return GeometryDesc("cylinder", (r, length), origin, name=name)
    if kind == "sphere":
        r = rd.float(_text(g, "radius"), where, "<sphere><radius>")
        if r <= 0:
            rd.fail(where, "<sphere><radius> must be positive")
        return GeometryDesc("sphere", (r,), origin, name=name)
    if kind == "plane":
        n = rd.floats(_text(g, "normal", "0 0 1"), 3, where, "<plane><normal>")
        if sum(x * x for x in n) < 1e-12:
            rd.fail(where, "<plane><normal> has zero length")
        gd = GeometryDesc("plane", n, origin, name=name)
        gd.extent = rd.floats(_text(g, "size", "100 100"), 2, where, "<plane><size>")
        return gd
    if kind == "mesh":
        uri = _text(g, "uri")
        if not uri:
            rd.fail(where, "<mesh> needs a <uri>")
        scale = rd.floats(_text(g, "scale", "1 1 1"), 3, where, "<mesh><scale>")
        return GeometryDesc("mesh", scale, origin, uri=uri, name=name)
    rd.fail(where, "unsupported geometry <%s> (box, cylinder, sphere, plane, mesh)" % kind)


def collision_surface(rd, ce, where, base=None):
    """The contact surface of an SDF ``<collision>`` element ``ce`` (its ``<max_contacts>`` and
    ``<surface>``): from SDF's defaults, or where ``ce`` has no ``<surface>`` from ``base`` (a URDF
    link's so far: a ``<gazebo reference><collision>`` block, urdf_reader)."""
    s = Surface() if base is None or _child(ce, "surface") is not None else base.copy()
    if _text(ce, "max_contacts") is not None:
        s.max_contacts = rd.int(_text(ce, "max_contacts"), where, "<max_contacts>")
        if s.max_contacts < 0:
            rd.fail(where, "<max_contacts> must not be negative")
    se = _child(ce, "surface")
    if se is None:
        return s
    fo = _child(_child(se, "friction") if _child(se, "friction") is not None else se, "ode")
    if fo is not None and _child(se, "friction") is not None:
        s.mu1 = rd.float(_text(fo, "mu"), where, "<mu>", s.mu1)
        s.mu2 = rd.float(_text(fo, "mu2"), where, "<mu2>", s.mu2)
        if _text(fo, "fdir1"):
            s.fdir1 = rd.floats(_text(fo, "fdir1"), 3, where, "<fdir1>")
    ce2 = _child(se, "contact")
    co = _child(ce2, "ode") if ce2 is not None else None
    if co is not None:
        s.kp = rd.float(_text(co, "kp"), where, "<kp>", s.kp)
        s.kd = rd.float(_text(co, "kd"), where, "<kd>", s.kd)
        s.max_vel = rd.float(_text(co, "max_vel"), where, "<max_vel>", s.max_vel)
        if _text(co, "min_depth") is not None:
            s.min_depth = rd.float(_text(co, "min_depth"), where, "<min_depth>")
    if min(s.mu1, s.mu2, s.kd, s.max_vel, s.min_depth or 0.0) < 0 or s.kp <= 0:
        rd.fail(where, "surface parameters must not be negative (kp positive)")
    return s


def _color(ve):
    m = _child(ve, "material")
    if m is None:
        return None, None
    script = _child(m, "script")
    name = _text(script, "name") if script is not None else None
    for tag in ("diffuse", "ambient"):
        t = _text(m, tag)
        if t:
            try:
                vals = tuple(float(x) for x in t.split())
                if len(vals) in (3, 4):
                    return name, vals + (1.0,) * (4 - len(vals))
            except ValueError:
                pass
    return name, None


def _plugin(pe, link=None, sensor=None):
    ns = _text(pe, "robotNamespace")
    return PluginSpec(pe.get("name", ""), pe.get("filename", ""), pe, ns, link, sensor)


def _pose_text(pose):
    (x, y, z), q = pose
    return "%r %r %r %r %r %r" % ((x, y, z) + tuple(rpy_from_quat(q)))


def _set_pose(elem, pose):
    pe = _child(elem, "pose")
    if pe is None:
        pe = ET.SubElement(elem, "pose")
    pe.attrib.pop("frame", None)
    pe.text = _pose_text(pose)


#: the private attribute by which a link of a nested model carries that model's <static>
NESTED_STATIC = "{urn:modrob-sim}static"


def _flatten_nested(rd, me, name, warn, resolver):
    """Nested models (SDF 1.5+: a ``<model>`` or ``<include>`` inside a ``<model>``, as in
    turtlebot3_house) become links and joints of the outer model, named ``nested::link`` as Gazebo
    scopes them, their poses composed with the nested model's pose. As in Gazebo, a nested model
    keeps its own ``<static>`` (not given: dynamic, also inside a static model; an ``<include>``'s
    ``<static>`` overrides the included file's): its links carry it (``NESTED_STATIC``)."""
    for index, c in enumerate(list(me)):
        tag = local(c.tag)
        if tag == "include":
            uri = _text(c, "uri", "")
            inner = _included_model(rd, uri, resolver, warn) if uri else None
            if inner is None:
                me.remove(c)
                continue
            if _text(c, "name"):
                inner.set("name", _text(c, "name"))
            if _child(c, "pose") is not None:
                _set_pose(inner, _pose(rd, c, "<include><pose>"))
            if _text(c, "static") is not None:
                st = _child(inner, "static")
                if st is None:
                    st = ET.SubElement(inner, "static")
                st.text = _text(c, "static")
            me.remove(c)
            me.insert(index, inner)
            c = inner
        elif tag != "model":
            continue
        nested = c.get("name") or "model_%d" % index
        _flatten_nested(rd, c, name + "::" + nested, warn, resolver)
        where = "nested model '%s'" % nested
        at = _pose(rd, c, where)
        static = "true" if rd.bool(_text(c, "static", "false"), where, "<static>") else "false"
        for e in list(c):
            t = local(e.tag)
            if t == "link":
                if e.get(NESTED_STATIC) is None:    # a link of a model nested deeper keeps its own
                    e.set(NESTED_STATIC, static)
                e.set("name", "%s::%s" % (nested, e.get("name", "")))
                _set_pose(e, pose_mul(at, _pose(rd, e, where + " link '%s'" % e.get("name"))))
            elif t == "joint":
                e.set("name", "%s::%s" % (nested, e.get("name", "")))
                for end in ("parent", "child"):
                    ee = _child(e, end)
                    if ee is not None and ee.text and ee.text.strip() != "world":
                        ee.text = "%s::%s" % (nested, ee.text.strip())
                axis = _child(e, "axis")
                xyz = _child(axis, "xyz") if axis is not None else None
                if xyz is not None and (xyz.get("expressed_in") == "__model__" or (
                        _text(axis, "use_parent_model_frame", "false").lower() in ("1", "true"))):
                    xyz.text = "%r %r %r" % quat_rotate(at[1], rd.floats(xyz.text, 3, where, "<axis><xyz>"))
            elif t != "plugin":
                continue
            c.remove(e)
            me.append(e)
        me.remove(c)


def _model(rd, me, name, warn, resolver=None):
    _flatten_nested(rd, me, name, warn, resolver)
    desc = ModelDesc(name, "sdf", None)
    desc.static = rd.bool(_text(me, "static", "false"), "<static>", "static")
    desc.self_collide = rd.bool(_text(me, "self_collide", "false"), "<self_collide>", "self_collide")
    desc.pose = _pose(rd, me, "model pose")
    for pe in _children(me, "plugin"):
        desc.plugins.append(_plugin(pe))
    for ge in _children(me, "gripper"):
        desc.grippers.append(read_gripper(rd, ge, "<model>", local))
    for le in _children(me, "link"):
        lname = le.get("name")
        if not lname:
            rd.fail("<link>", "a <link> has no name")
        if lname in desc.links:
            rd.fail("link '%s'" % lname, "two links are named '%s'" % lname)
        where = "link '%s'" % lname
        ld = LinkDesc(lname)
        if le.get(NESTED_STATIC) is not None:
            ld.static = le.get(NESTED_STATIC) == "true"
        ld.pose = _pose(rd, le, where)
        ie = _child(le, "inertial")
        if ie is not None:
            ld.has_inertial = True
            ld.mass = rd.float(_text(ie, "mass"), where, "<mass>", 1.0)
            if ld.mass < 0:
                rd.fail(where, "<mass> is negative")
            ld.inertial_origin = _pose(rd, ie, where)
            it = _child(ie, "inertia")
            if it is not None:
                ld.inertia = tuple(rd.float(_text(it, k), where, "<%s>" % k, 0.0)
                                   for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"))
            else:
                ld.inertia = (1.0, 0.0, 0.0, 1.0, 0.0, 1.0)
        elif not desc.link_static(ld):
            ld.mass = 1.0  # SDF's defaults: 1 kg, unit inertia
            ld.inertia = (1.0, 0.0, 0.0, 1.0, 0.0, 1.0)
        ld.gravity = rd.bool(_text(le, "gravity", "true"), where, "<gravity>")
        ld.self_collide = rd.bool(_text(le, "self_collide", "false"), where, "<self_collide>")
        for ce in _children(le, "collision"):
            cw = "%s collision '%s'" % (where, ce.get("name", ""))
            gd = _geometry(rd, ce, cw)
            gd.surface = collision_surface(rd, ce, cw)
            ld.collisions.append(gd)
        for ve in _children(le, "visual"):
            gd = _geometry(rd, ve, "%s visual '%s'" % (where, ve.get("name", "")))
            gd.material, gd.color = _color(ve)
            ld.visuals.append(gd)
        for se in _children(le, "sensor"):
            ld.sensors.append(se)
            for pe in _children(se, "plugin"):
                desc.plugins.append(_plugin(pe, lname, se))
        for c in le:
            t = local(c.tag)
            if t not in ("pose", "inertial", "collision", "visual", "sensor", "gravity",
                         "self_collide", "kinematic", "velocity_decay", "must_be_base_link",
                         "enable_wind"):
                warn("sdf-link-tag:" + t, "model '%s' link '%s': SDF <%s> is not supported; ignored"
                     % (name, lname, t))
        desc.links[lname] = ld
    if not desc.links:
        rd.fail("<model name='%s'>" % name, "the model has no <link>")

    parents = {}
    for je in _children(me, "joint"):
        jname = je.get("name")
        where = "joint '%s'" % jname
        if not jname:
            rd.fail("<joint>", "a <joint> has no name")
        if jname in desc.joints:
            rd.fail(where, "two joints are named '%s'" % jname)
        stype = je.get("type")
        if stype not in SDF_JOINT_TYPES:
            rd.fail(where, "type '%s' is not supported (revolute, continuous, prismatic, fixed)" % stype)
        parent, child = _text(je, "parent"), _text(je, "child")
        if parent not in desc.links and parent != "world":
            rd.fail(where, "parent link '%s' does not exist" % parent)
        if child not in desc.links:
            rd.fail(where, "child link '%s' does not exist" % child)
        if child in parents:
            rd.fail(where, "link '%s' is the child of two joints" % child)
        parents[child] = jname
        j = JointDesc(jname, SDF_JOINT_TYPES[stype], parent, child)
        jpose = _pose(rd, je, where)  # joint frame in the child link frame
        child_pose = desc.links[child].pose
        parent_pose = IDENTITY_POSE if parent == "world" else desc.links[parent].pose
        frame = pose_mul(child_pose, jpose)  # joint frame in the model frame
        j.origin = pose_mul(pose_inv(parent_pose), frame)
        j.child_offset = pose_inv(jpose)
        ae = _child(je, "axis")
        if ae is not None:
            xyz_e = _child(ae, "xyz")
            axis = rd.floats(_text(ae, "xyz", "0 0 1"), 3, where, "<axis><xyz>")
            limits.check_axis(name, where, "<axis><xyz>", axis)
            axis = limits.normalized_axis(axis)
            in_model = rd.bool(_text(ae, "use_parent_model_frame", "false"), where,
                               "<use_parent_model_frame>") or \
                (xyz_e is not None and xyz_e.get("expressed_in") == "__model__")
            if in_model:
                axis = quat_rotate((-frame[1][0], -frame[1][1], -frame[1][2], frame[1][3]), axis)
            j.axis = axis
            le = _child(ae, "limit")
            if le is not None:
                lo = rd.float(_text(le, "lower"), where, "<lower>", -1e16)
                hi = rd.float(_text(le, "upper"), where, "<upper>", 1e16)
                if j.type in ("revolute", "prismatic") and hi < 1e15 and lo > -1e15:
                    if lo > hi:
                        rd.fail(where, "<limit> lower %g is above upper %g" % (lo, hi))
                    j.lower, j.upper = lo, hi
                j.effort_limit = rd.float(_text(le, "effort"), where, "<effort>", -1.0)
                j.velocity_limit = rd.float(_text(le, "velocity"), where, "<velocity>", -1.0)
                if j.effort_limit < 0:
                    j.effort_limit = None
                if j.velocity_limit < 0:
                    j.velocity_limit = None
            de = _child(ae, "dynamics")
            if de is not None:
                j.damping = rd.float(_text(de, "damping"), where, "<damping>", 0.0)
                j.friction = rd.float(_text(de, "friction"), where, "<friction>", 0.0)
        for se in _children(je, "sensor"):
            # a joint's sensor (force_torque): its plugins see the joint's child link, whose
            # parent joint this is
            for pe in _children(se, "plugin"):
                desc.plugins.append(_plugin(pe, child, se))
        if j.type == "revolute" and j.lower is None:
            j.type = "continuous"  # SDF revolute without limits turns freely
        desc.joints[jname] = j

    # root, and free links as floating children of the root
    first = next(iter(desc.links))
    world_joints = [j for j in desc.joints.values() if j.parent == "world"]
    desc.root = "world" if world_joints else first
    children = {}
    for j in desc.joints.values():
        children.setdefault(j.parent, []).append(j.child)
    reached = set()
    stack = [desc.root]
    while stack:
        ln = stack.pop()
        if ln in reached:
            rd.fail("tree", "the joints form a cycle at link '%s'" % ln)
        reached.add(ln)
        stack.extend(children.get(ln, ()))
    for ln, ld in desc.links.items():
        if ln in reached:
            continue
        if ln in parents:
            rd.fail("tree", "link '%s' hangs in a joint cycle not connected to '%s'" % (ln, desc.root))
        j = JointDesc("%s__free" % ln, "floating", desc.root, ln)
        rp = IDENTITY_POSE if desc.root == "world" else desc.links[desc.root].pose
        j.origin = pose_mul(pose_inv(rp), ld.pose)
        desc.joints[j.name] = j
        stack = [ln]
        while stack:
            x = stack.pop()
            if x in reached:
                rd.fail("tree", "the joints form a cycle at link '%s'" % x)
            reached.add(x)
            stack.extend(children.get(x, ()))
    # the model frame is the spawn frame: the root link sits at its own pose in it
    if desc.root != "world":
        rp = desc.links[desc.root].pose
        desc.root_offset = rp
    else:
        desc.root_offset = IDENTITY_POSE
    return limits.validate_model(desc)


def read_sdf(xml_text, name, warn, resolver=None):
    """Parse SDF text; returns (list of ModelDesc, world settings dict or None)."""
    label = name or "sdf"
    rd = Reader(label, "SDF")
    root = upgrade(parse_xml(xml_text, label, "SDF"), label, warn)
    tag = local(root.tag)
    if tag == "sdf":
        worlds = _children(root, "world")
        models = _children(root, "model")
        if worlds:
            return _world(rd, worlds[0], warn, resolver, xml_text)
        if len(models) != 1:
            rd.fail("<sdf>", "expected one <world> or one <model>, found %d models" % len(models))
        me = models[0]
    elif tag == "model":
        me = root
    elif tag == "world":
        return _world(rd, root, warn, resolver, xml_text)
    else:
        rd.fail("root element", "expected <sdf>, <world> or <model>, found <%s>" % tag)
    mname = name or me.get("name")
    if not mname:
        rd.fail("<model>", "the model has no name and none was given")
    rd = Reader(mname, "SDF")
    d = _model(rd, me, mname, warn, resolver)
    d.source_xml = xml_text
    return [d], None


def _world_settings(rd, we):
    """The settings of a <world>, checked: ``time_step``, ``gravity`` (the world's, else its
    <physics>'s), ``params`` (ODE solver settings for World.set_physics_params),
    ``real_time_factor`` and ``real_time_update_rate`` (for the node's pacing). The one reader of
    a world's <physics> (world files and spawned worlds)."""
    settings = {}
    ph = _child(we, "physics")
    g = _text(we, "gravity") or (_text(ph, "gravity") if ph is not None else None)
    if g:
        settings["gravity"] = _checked(rd, limits.check_gravity, rd.floats(g, 3, "<world>", "<gravity>"),
                                       "<world><gravity>")
    if ph is not None:
        if _text(ph, "max_step_size"):
            settings["time_step"] = _checked(
                rd, limits.check_time_step,
                rd.float(_text(ph, "max_step_size"), "<physics>", "<max_step_size>"),
                "<physics><max_step_size>")
        for tag in ("real_time_factor", "real_time_update_rate"):
            if _text(ph, tag):
                settings[tag] = rd.float(_text(ph, tag), "<physics>", "<%s>" % tag)
        params = {}
        if _text(ph, "max_contacts") is not None:
            # Gazebo's per-pair cap (its default 20; ours 4 when the world does not say)
            params["max_contacts"] = rd.float(_text(ph, "max_contacts"), "<physics>", "<max_contacts>")
        ode_e = _child(ph, "ode")
        if ode_e is not None:
            solver = _child(ode_e, "solver")
            cons = _child(ode_e, "constraints")
            kind = _text(solver, "type") if solver is not None else None
            if kind is not None:
                if kind not in limits.SOLVER_TYPES:
                    rd.fail("<physics><ode><solver>", "<type> '%s' is not 'quick' or 'world'" % kind)
                params["solver_type"] = kind
            for parent, tag, key in ((solver, "iters", "iters"), (solver, "sor", "sor"),
                                     (cons, "cfm", "cfm"), (cons, "erp", "erp"),
                                     (cons, "contact_max_correcting_vel", "contact_max_correcting_vel"),
                                     (cons, "contact_surface_layer", "contact_surface_layer")):
                if parent is not None and _text(parent, tag) is not None:
                    params[key] = rd.float(_text(parent, tag), "<physics><ode>", "<%s>" % tag)
        if params:
            settings["params"] = params
    return settings


def read_world_settings(xml_text, label="world"):
    """The settings (see _world_settings) of the <world> of an SDF text (any SDF version); {}
    when it has no world. ModelError naming the element when a value is bad."""
    rd = Reader(label, "SDF")
    root = upgrade(parse_xml(xml_text, label, "SDF"), label, lambda key, message: None)  # read_sdf says it
    we = root if local(root.tag) == "world" else _child(root, "world")
    return _world_settings(rd, we) if we is not None else {}


def _world(rd, we, warn, resolver, xml_text):
    settings = _world_settings(rd, we)
    descs = []
    for c in we:
        t = local(c.tag)
        if t == "include":
            uri = _text(c, "uri", "")
            nm = _text(c, "name")
            if not uri:
                warn("sdf-include-no-uri:%s" % (c.get("filename") or nm), "SDF world <include> without <uri> "
                     "(%s) skipped: name the model as <uri>model://name</uri>"
                     % ("filename='%s', the form before SDF 1.0" % c.get("filename") if c.get("filename")
                        else "nothing to include"))
                continue
            if uri in ("model://sun",) or uri.endswith("/sun"):
                continue  # a light: nothing to simulate
            if uri == "model://ground_plane":
                me = parse_xml(GROUND_PLANE, "ground_plane", "SDF")
            else:
                me = _included_model(rd, uri, resolver, warn)
                if me is None:
                    continue
            mname = nm or me.get("name")
            mrd = Reader(mname, "SDF")
            d = _model(mrd, me, mname, warn, resolver)
            if _child(c, "pose") is not None:
                d.pose = _pose(mrd, c, "<include><pose>")
            if _text(c, "static") is not None:
                d.static = mrd.bool(_text(c, "static"), "<include><static>", "static")
            d.source_xml = xml_text
            descs.append(d)
        elif t == "model":
            mname = c.get("name")
            if not mname:
                rd.fail("<world>", "a <model> has no name")
            d = _model(Reader(mname, "SDF"), c, mname, warn, resolver)
            d.source_xml = xml_text
            descs.append(d)
        elif t == "plugin":
            # Gazebo's world plugins extend the server itself; the node provides gazebo_ros's API
            # on its own and loads model and sensor plugins only
            fname = c.get("filename", "")
            warn("sdf-world-plugin:" + fname,
                 "SDF world <plugin name='%s' filename='%s'>: world plugins are not loaded by this "
                 "simulator (model and sensor plugins are); ignored" % (c.get("name", ""), fname))
        elif t not in ("physics", "gravity", "light", "scene", "gui", "magnetic_field",
                       "atmosphere", "spherical_coordinates", "state", "wind"):
            warn("sdf-world-tag:" + t, "SDF world <%s> is not supported; ignored" % t)
    _saved_state(rd, we, descs)
    return descs, settings


def _saved_state(rd, we, descs):
    """A world saved by Gazebo carries a <state>: as Gazebo loads such a world, the models start
    at the poses of its first <state>, not at their own <pose> (husky_gazebo's playpen moved a
    barrier off the robot's spawn point that way). Only the models' poses are taken; the saved
    clock, link poses and velocities are not."""
    states = _children(we, "state")
    if not states:
        return
    by_name = dict((d.name, d) for d in descs)
    for me in _children(states[0], "model"):
        d = by_name.get(me.get("name"))
        if d is not None and _child(me, "pose") is not None:
            d.pose = _pose(rd, me, "<state><model name='%s'><pose>" % d.name)


def _checked(rd, check, value, what):
    try:
        return check(value, what)
    except ValueError as e:
        rd.fail("<world>", str(e))


#: the newest SDF version Gazebo 11 reads (a model.config may list newer files; they are skipped)
SDF_VERSION = (1, 7)


def _version(text):
    try:
        return tuple(int(x) for x in (text or "").strip().split("."))
    except ValueError:
        return None


def _model_file(folder):
    """The SDF file of a model folder, as Gazebo picks it: from model.config the ``<sdf>`` of the
    highest version it reads, else model.sdf."""
    config = os.path.join(folder, "model.config")
    best = None
    if os.path.isfile(config):
        try:
            root = parse_xml(open(config).read(), config, "model.config")
        except ModelError:
            root = None
        for e in (_children(root, "sdf") if root is not None else ()):
            v = _version(e.get("version"))
            readable = e.text and e.text.strip() and (v is None or v <= SDF_VERSION)
            if readable and (best is None or (v or ()) > best[0]):
                best = (v or (), e.text.strip())
    return os.path.join(folder, best[1] if best else "model.sdf")


def _included_model(rd, uri, resolver, warn):
    """The <model> Element an <include> names, or None when the URI is found nowhere on this
    machine (warned about once, naming the URI and where it looked: the rest of the world loads,
    as Gazebo goes on when it cannot download a model)."""
    try:
        path = (resolver or default_resolver)(uri)
    except ModelError as e:     # meshes.ResourceNotFound (a model:// found nowhere) and the like
        warn("sdf-include-missing:" + uri, "SDF <include><uri>%s</uri> skipped: %s" % (uri, e))
        return None
    except Exception as e:  # a user resolver may raise anything: report it
        raise ModelError("SDF <include><uri>%s</uri>: cannot resolve: %s: %s" % (uri, type(e).__name__, e))
    if not path:
        raise ModelError("SDF <include><uri>%s</uri>: the resource resolver returned nothing" % uri)
    f = _model_file(path) if os.path.isdir(path) else path
    try:
        with open(f) as fh:
            text = fh.read()
    except OSError as e:
        raise ModelError("SDF <include><uri>%s</uri>: cannot read '%s': %s" % (uri, f, e))
    root = upgrade(parse_xml(text, uri, "SDF"), uri, warn)
    if local(root.tag) == "sdf":
        ms = _children(root, "model")
        if not ms:
            raise ModelError("SDF <include><uri>%s</uri>: '%s' has no <model>" % (uri, f))
        return ms[0]
    return root
