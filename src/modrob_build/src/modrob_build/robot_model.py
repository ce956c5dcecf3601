"""A robot's kinematic chain built from a validated module order (pure data, no XML).

Naming (prefix p, e.g. "modrob0_"; the prefix is "" for single named robots):
  p + "base_link"                 the base module, fixed to the "world" link at the base pose
  p + "tube<k>"                   the k-th link (tube) module, k = 1, 2, ...
  p + "joint<k>_housing"          the housing of the module that carries joint<k>
  p + "joint<k>_output"           its output side (the child of joint<k>)
  p + "ee_link"                   the end-effector frame at the distal face of the last module
Actuated joints are "joint1".."jointM" in chain order (as in the seed); fixed joints are named
after their child link without the prefix plus "_mount" ("tube1_mount"), "world_joint" and
"ee_joint".
"""
import math

from modrob_build.errors import LayoutError


class LinkSpec(object):
    def __init__(self, name, module, body, mass, com, inertia, material):
        self.name = name
        self.module = module      # Module, or None for frames without a body (world, ee_link)
        self.body = body          # module_database.Body or None
        self.mass = mass
        self.com = com            # (x, y, z) in the link frame
        self.inertia = inertia    # (ixx, iyy, izz) about the COM
        self.material = material  # (gazebo material, rgba) or None


class JointSpec(object):
    def __init__(self, name, jtype, parent, child, xyz, rpy=(0.0, 0.0, 0.0), module=None):
        self.name = name
        self.type = jtype
        self.parent = parent
        self.child = child
        self.xyz = tuple(float(v) for v in xyz)
        self.rpy = tuple(float(v) for v in rpy)
        self.module = module      # Module for actuated joints (axis, limits, dynamics ...)

    @property
    def actuated(self):
        return self.type in ("revolute", "continuous", "prismatic")


class RobotModel(object):
    """Links and joints in chain order, plus what the URDF writer and the gains need."""

    def __init__(self, name, index, order, modules, base_pose, prefix):
        self.name = name
        self.index = index
        self.namespace = "/modrob%d" % index
        self.order = list(order)
        self.modules = modules
        self.base_pose = base_pose    # (x, y, z, yaw)
        self.prefix = prefix
        self.links = []
        self.joints = []

    @property
    def actuated_joints(self):
        return [j for j in self.joints if j.actuated]

    @property
    def ee_link(self):
        return self.prefix + "ee_link"

    @property
    def base_link(self):
        return self.prefix + "base_link"


def base_pose_tuple(base):
    """(x, y, z, yaw) from a 3- or 4-sequence of finite numbers."""
    values = tuple(float(v) for v in base)
    if len(values) == 3:
        values += (0.0,)
    if len(values) != 4 or not all(math.isfinite(v) for v in values):
        raise LayoutError("a base pose is x,y,z or x,y,z,yaw of finite numbers, not %r" % (base,))
    return values


def armature_inertia(inertia, axis, armature):
    """Output-body inertia with the reflected rotor inertia of the drive (N^2 J_motor) added as a
    flywheel: +A about the joint axis and +A/2 about the two others (keeps it physical)."""
    k = "xyz".index(axis)
    return tuple(v + (armature if i == k else 0.5 * armature) for i, v in enumerate(inertia))


def build_robot_model(modules, order, index=0, base=(0.0, 0.0, 0.0), prefix=None, name=None):
    """RobotModel from validated modules (order.validate_order)."""
    prefix = "modrob%d_" % index if prefix is None else prefix
    robot = RobotModel(name or "modrob%d" % index, index, order, modules, base_pose_tuple(base),
                       prefix)
    robot.links.append(LinkSpec("world", None, None, 0.0, None, None, None))
    parent, parent_distal = "world", None
    tube_count = joint_count = 0
    for module in modules:
        mat = (module.gazebo_material, module.rgba)
        for body in module.bodies():
            inertia = body.inertia
            if module.kind == "base":
                lname = prefix + "base_link"
            elif module.kind == "link":
                tube_count += 1
                lname = prefix + "tube%d" % tube_count
            elif body.role == "housing":
                joint_count += 1
                lname = prefix + "joint%d_housing" % joint_count
            else:
                lname = prefix + "joint%d_output" % joint_count
                inertia = armature_inertia(inertia, module.axis, module.armature)
            robot.links.append(LinkSpec(lname, module, body, body.mass, (0.0, 0.0, body.com_z),
                                        inertia, mat))
            short = lname[len(prefix):]
            if parent == "world":
                x, y, z, yaw = robot.base_pose
                robot.joints.append(JointSpec("world_joint", "fixed", "world", lname, (x, y, z),
                                              (0.0, 0.0, yaw)))
            elif body.role == "output":
                robot.joints.append(JointSpec("joint%d" % joint_count, "revolute", parent, lname,
                                              (0.0, 0.0, parent_distal), module=module))
            else:
                robot.joints.append(JointSpec(short + "_mount", "fixed", parent, lname,
                                              (0.0, 0.0, parent_distal)))
            parent, parent_distal = lname, body.distal_z
    robot.links.append(LinkSpec(robot.ee_link, None, None, 0.0, None, None, None))
    robot.joints.append(JointSpec("ee_joint", "fixed", parent, robot.ee_link, (0.0, 0.0, parent_distal)))
    return robot
