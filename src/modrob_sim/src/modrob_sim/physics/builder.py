"""ModelDesc -> ODE bodies, geoms and joints (a Model).

Fixed joints are LUMPED: the links they weld form one group = one ODE body with the combined
mass and inertia, the body at the group's centre of mass, oriented like the group's root link;
every link keeps its own frame (Link._T) so its pose stays exact. Groups welded to the 'world'
link, or holding a static link (every group of a static model; a static nested model's), have
no body: their geoms are static.

Everything that can fail on bad input (meshes, numbers, names) is checked before the first ODE
object is created, and a failure while creating destroys what was made: the world is unchanged.
"""
import logging
import math
from collections import deque

import numpy as np
import ode

from ..errors import ModelError
from . import limits, odelib
from .description import PluginSpec
from .gripper import Gripper
from .model import Group, Joint, Link, Model
from .transforms import (IDENTITY_POSE, pose_inv, pose_mul, quat_rotate,
                         quat_to_matrix, to_ode_quat)

LOG = logging.getLogger("modrob_sim.physics")

#: a group with no mass gets this (kg) and a warning; ODE cannot integrate a massless body.
MASS_FLOOR = 1e-3
#: principal moments are raised to at least INERTIA_REL_FLOOR * the largest and INERTIA_ABS_FLOOR
INERTIA_REL_FLOOR = 1e-3
INERTIA_ABS_FLOOR = 1e-9


def _inertia_matrix(i6):
    ixx, ixy, ixz, iyy, iyz, izz = i6
    return np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]], dtype=float)


def _rot(q):
    return np.array(quat_to_matrix(q), dtype=float)


def joint_order(desc):
    """Joints sorted parents-first (breadth first from the root)."""
    by_parent = {}
    for j in desc.joints.values():
        by_parent.setdefault(j.parent, []).append(j)
    out = []
    queue = deque([desc.root])
    while queue:
        ln = queue.popleft()
        for j in by_parent.get(ln, ()):
            out.append(j)
            queue.append(j.child)
    return out


def zero_configuration_poses(desc, order, pose):
    """World poses of every link (and 'world') with all joints at zero."""
    root_offset = getattr(desc, "root_offset", IDENTITY_POSE)
    poses = {desc.root: pose_mul(pose, root_offset)}
    if desc.root != "world":
        poses["world"] = pose
    for j in order:
        poses[j.child] = pose_mul(pose_mul(poses[j.parent], j.origin), j.child_offset)
    return poses


def _group_mass(links, poses, body_quat):
    """Total mass, world COM and inertia (about the COM, in the body frame of orientation
    body_quat) of a list of LinkDesc."""
    total = 0.0
    com = np.zeros(3)
    parts = []
    for ld in links:
        if ld.mass <= 0.0:
            continue
        frame = pose_mul(poses[ld.name], ld.inertial_origin)
        c = np.array(frame[0])
        r = _rot(frame[1])
        parts.append((ld.mass, c, r.dot(_inertia_matrix(ld.inertia)).dot(r.T)))
        total += ld.mass
        com += ld.mass * c
    if total <= 0.0:
        return 0.0, None, None
    com /= total
    inertia = np.zeros((3, 3))
    for m, c, i_world in parts:
        d = c - com
        inertia += i_world + m * (d.dot(d) * np.eye(3) - np.outer(d, d))
    rb = _rot(body_quat)
    return total, com, rb.T.dot(inertia).dot(rb)


def _floor_inertia(inertia, what):
    inertia = 0.5 * (inertia + inertia.T)
    w, v = np.linalg.eigh(inertia)
    top = max(float(w.max()), 0.0)
    floor = max(INERTIA_ABS_FLOOR, INERTIA_REL_FLOOR * top)
    if float(w.min()) < floor:
        if float(w.min()) < 0.0:
            LOG.warning("%s: inertia is not positive definite (principal moments %s): raised to %.3g",
                        what, ", ".join("%.3g" % x for x in w), floor)
        w = np.maximum(w, floor)
        inertia = v.dot(np.diag(w)).dot(v.T)
    return inertia


def _make_geom(g, space, kind_size, what):
    kind = g.kind
    if kind == "box":
        return ode.GeomBox(space, lengths=tuple(kind_size))
    if kind == "sphere":
        return ode.GeomSphere(space, kind_size[0])
    if kind == "cylinder":
        return ode.GeomCylinder(space, kind_size[0], kind_size[1])
    if kind == "capsule":
        return ode.GeomCapsule(space, kind_size[0], kind_size[1])
    raise ModelError("%s: %s collisions are not supported" % (what, kind))


def build_model(world, desc, pose, robot_namespace, prepared_meshes):
    """Create the ODE objects of ``desc`` in ``world`` placed at ``pose``. Returns the Model (not
    yet registered in the world). ``prepared_meshes`` maps id(GeometryDesc) -> mesh handle from
    World's _prepare_meshes (already loaded, so nothing here fails on files)."""
    model = Model(world, desc, robot_namespace)
    try:
        _build(world, model, desc, pose, robot_namespace, prepared_meshes)
    except Exception:
        world.destroy_model_objects(model)
        raise
    return model


def _build(world, model, desc, pose, robot_namespace, prepared_meshes):
    for jd in desc.joints.values():
        if jd.type == "planar":
            # as Gazebo's URDF -> SDF conversion: no joint is made, the child link moves freely
            world.warn_once("planar:%s:%s" % (model.name, jd.name),
                            "model '%s' joint '%s' is planar: as in Gazebo, which converts no joint for "
                            "it, link '%s' is a free body (nothing keeps it in the plane)"
                            % (model.name, jd.name, jd.child))
    for gd in desc.grippers:
        for ln in gd.gripper_links + (gd.palm_link,):
            if ln not in desc.links or ln == "world":
                raise ModelError("model '%s' <gripper name='%s'>: no link named '%s' (links: %s)"
                                 % (model.name, gd.name, ln, ", ".join(desc.links)))
    order = joint_order(desc)
    model._root_name = desc.root
    model._world_pose = pose if desc.root == "world" else IDENTITY_POSE
    for ld in desc.links.values():
        if ld.name == "world":
            continue
        model.links[ld.name] = Link(model, ld)
    for jd in order:
        j = Joint(model, jd)
        model.joints[jd.name] = j
        model._joint_order.append(j)
        if jd.child in model.links:
            model.links[jd.child].parent_joint = j
    for p in desc.plugins:
        ns = p.robot_namespace if p.robot_namespace is not None else robot_namespace
        model.plugins.append(PluginSpec(p.name, p.filename, p.element, ns, p.link, p.sensor))

    poses = zero_configuration_poses(desc, order, pose)
    for ln, p in poses.items():
        limits.check_link_extent(model.name, ln, p[0])

    # ---- groups: union over fixed joints ----------------------------------------------------
    group_of = {}
    groups = []
    static_root = desc.root == "world"
    first = desc.root
    if first != "world":
        g = Group(0, model, model.links[first])
        groups.append(g)
        group_of[first] = g
    else:
        g = Group(0, model, None)  # the world group
        groups.append(g)
        group_of["world"] = g
    for jd in order:
        if jd.type == "fixed":
            group_of[jd.child] = group_of[jd.parent]
        else:
            g = Group(len(groups), model, model.links[jd.child])
            groups.append(g)
            group_of[jd.child] = g
    for ln, link in model.links.items():
        g = group_of[ln]
        g.links.append(link)
        link._group = g
    if static_root:
        w = groups[0]
        if w.links:
            w.root = w.links[0]
        else:
            groups.pop(0)
            for i, g in enumerate(groups):
                g.index = i
    model._groups = groups
    # canonical link: the root link, or the first link attached to 'world'
    if desc.root != "world":
        model.canonical_link = model.links[desc.root]
    else:
        model.canonical_link = model.links[order[0].child]

    # ---- bodies -----------------------------------------------------------------------------
    for g in groups:
        # static: welded to the world, or holding a static link (a static model's, or of a static
        # nested model: a link welded to it cannot move either)
        is_static = (static_root and group_of.get("world") is g) or any(
            desc.link_static(desc.links[link.name]) for link in g.links)
        if is_static:
            for link in g.links:
                link._static_pose = poses[link.name]
            continue
        root_pose = poses[g.root.name]
        lds = [desc.links[link.name] for link in g.links]
        mass, com, inertia = _group_mass(lds, poses, root_pose[1])
        what = "model '%s' link '%s'" % (model.name, g.root.name)
        if mass <= 0.0:
            LOG.warning("%s (with %d welded links) has no mass: given %.3g kg so that ODE can "
                        "move it; add an <inertial>", what, len(g.links), MASS_FLOOR * 10)
            mass = MASS_FLOOR * 10
            com = np.array(pose_mul(root_pose, IDENTITY_POSE)[0])
            inertia = np.eye(3) * 1e-5
        inertia = _floor_inertia(inertia, what)
        body = ode.Body(world.ode_world)
        m = ode.Mass()
        m.setParameters(mass, 0.0, 0.0, 0.0, inertia[0, 0], inertia[1, 1], inertia[2, 2],
                        inertia[0, 1], inertia[0, 2], inertia[1, 2])
        body.setMass(m)
        body_pose = ((float(com[0]), float(com[1]), float(com[2])), root_pose[1])
        body.setPosition(body_pose[0])
        body.setQuaternion(to_ode_quat(body_pose[1]))
        g.body = body
        g.mass = mass
        g._inertia = inertia
        inv = pose_inv(body_pose)
        for link in g.links:
            link._body = body
            link._T = pose_mul(inv, poses[link.name])
        model._bodies.append(body)
        model._dyn_groups.append(g)
        world.group_gravity_changed(g)
    model.is_static = not model._bodies

    # ---- geoms ------------------------------------------------------------------------------
    for link in model.links.values():
        ld = desc.links[link.name]
        names = link.collision_names
        for ci, gd in enumerate(ld.collisions):
            what = "model '%s' link '%s'" % (model.name, link.name)
            surface = gd.surface or ld.surface
            body = link._body
            if gd.kind == "plane":
                if body is not None:
                    raise ModelError("%s: a <plane> collision must be static (in a static model)" % what)
                world_pose = pose_mul(link._static_pose, gd.origin)
                geom = world.make_plane(gd.size, world_pose)
                world.register_geom(geom, model, link, names[ci], surface, None)
                link._geoms.append((geom, gd.origin))
                continue
            space = world.space(dynamic=body is not None)
            origin = gd.origin
            if gd.kind == "mesh":
                geom, local = world.make_mesh_geom(prepared_meshes[id(gd)], body is not None, what)
                if local is not IDENTITY_POSE:
                    origin = pose_mul(gd.origin, local)
            else:
                geom = _make_geom(gd, space, gd.size, what)
            if body is not None:
                rel = pose_mul(link._T, origin)
                geom.setBody(body)
                geom.setOffsetPosition(rel[0])
                geom.setOffsetQuaternion(to_ode_quat(rel[1]))
            else:
                world.place_static_geom(geom, pose_mul(link._static_pose, origin))
            world.register_geom(geom, model, link, names[ci], surface, body)
            link._geoms.append((geom, origin))

    # ---- joints -----------------------------------------------------------------------------
    for j in model._joint_order:
        jd = desc.joints[j.name]
        if j.type in ("fixed", "floating", "planar"):
            continue
        child = model.links[j.child]
        if child._body is None:
            continue  # a static model: its joints are frozen
        parent_body = None if j.parent == "world" else model.links[j.parent]._body
        if parent_body is None:
            model._world_attached = True
        frame = pose_mul(poses[j.parent], jd.origin)
        axis = quat_rotate(frame[1], jd.axis)
        if j._angular:
            oj = ode.HingeJoint(world.ode_world)
            oj.attach(child._body, parent_body)
            oj.setAnchor(frame[0])
            oj.setAxis(axis)
            lo, hi = j.lower, j.upper
            if j.type == "revolute" and lo is not None:
                if lo >= -math.pi and hi <= math.pi:
                    oj.setParam(odelib.PARAM_LO_STOP, lo)
                    oj.setParam(odelib.PARAM_HI_STOP, hi)
                else:
                    j._soft_limits = True
            j._unwrap = not (j.type == "revolute" and lo is not None and lo > -3.0 and hi < 3.0)
        else:
            oj = ode.SliderJoint(world.ode_world)
            oj.attach(child._body, parent_body)
            oj.setAxis(axis)
            if j.lower is not None:
                oj.setParam(odelib.PARAM_LO_STOP, j.lower)
                oj.setParam(odelib.PARAM_HI_STOP, j.upper)
        for tag, param in (("stopErp", odelib.PARAM_STOP_ERP), ("stopCfm", odelib.PARAM_STOP_CFM)):
            el = jd.extra.get(tag)
            if el is not None:
                try:
                    v = float((el.text or "").strip())
                except ValueError:
                    v = float("nan")
                if not (math.isfinite(v) and v >= 0):
                    raise ModelError("model '%s' joint '%s': <gazebo><%s> must be a number >= 0, got %r"
                                     % (model.name, j.name, tag, el.text))
                oj.setParam(param, v)
        j._ode = oj
        model._ode_joints.append(oj)
        # inertia the joint moves directly (lower bound of the subtree's): for stable damping
        g = child._group
        if j._angular:
            r = np.array(g.body.getPosition()) - np.array(frame[0])
            a = np.array(axis)
            rperp = r - a * r.dot(a)
            rb = _rot(g.body.getQuaternion()[1:] + (g.body.getQuaternion()[0],))
            a_body = rb.T.dot(a)
            j._child_inertia = float(a_body.dot(g._inertia).dot(a_body) + g.mass * rperp.dot(rperp))
        else:
            j._child_inertia = g.mass
        j._apply_motor()
    # mimic joints start where their coupling puts them (multiplier * master + offset): from 0
    # with an offset, the coupling asked for offset / dt in the first step (0.1 m: 50 m/s, the
    # guard's limit, and the model was restored for ever)
    masters = {j.mimic[0]: 0.0 for j in model._joint_order
               if j.mimic is not None and j._ode is not None and j.mimic[2] != 0.0}
    if masters:
        model._apply_configuration(masters, rigid_velocity=False)
    model._grippers = [Gripper(world, model, gd) for gd in desc.grippers]
    return model
