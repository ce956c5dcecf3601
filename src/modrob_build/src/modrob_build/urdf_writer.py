"""RobotModel -> Gazebo-ready URDF text (deterministic: the same input gives the same bytes).

What goes in, per the seed (section IV-B, fig. 6):
* links with <inertial>, <visual> (RViz colour from the database) and <collision>;
* the base fixed to the "world" link at the base pose;
* actuated joints with <limit> and <dynamics damping friction> from the database;
* <gazebo reference=link>: material (Gazebo/DarkGrey links, Gazebo/Blue joint modules), mu1, mu2;
* <gazebo reference=joint>: implicitSpringDamper, provideFeedback;
* one <transmission> per actuated joint (SimpleTransmission, EffortJointInterface, reduction);
* the gazebo_ros_control plugin with robotNamespace /modrob<N>.
"""
import math
import xml.etree.ElementTree as ET

from modrob_build.module_database import AXES

CONTROL_PLUGIN = "libgazebo_ros_control.so"
ROBOT_SIM_TYPE = "gazebo_ros_control/DefaultRobotHWSim"
HW_INTERFACE = "hardware_interface/EffortJointInterface"


def fmt(x):
    """Compact, stable number formatting (no '-0')."""
    x = float(x)
    if abs(x) < 1e-12:
        x = 0.0
    text = "%.9g" % x
    return text


def vec(values):
    return " ".join(fmt(v) for v in values)


def _sub(parent, tag, **attrs):
    return ET.SubElement(parent, tag, {k: v for k, v in attrs.items()})


def _text(parent, tag, text):
    el = ET.SubElement(parent, tag)
    el.text = text
    return el


def material_names(robot):
    """{(gazebo material, rgba): URDF material name}, in first-use order."""
    names = {}
    for link in robot.links:
        if link.material and link.material not in names:
            base = link.material[0].split("/")[-1].lower() or "material"
            name = "modrob_" + base
            while name in names.values():
                name += "_"
            names[link.material] = name
    return names


def _shape_rpy(axis):
    return {"x": (0.0, math.pi / 2, 0.0), "y": (math.pi / 2, 0.0, 0.0), "z": (0.0, 0.0, 0.0)}[axis]


def _geometry(parent, shape):
    geo = _sub(parent, "geometry")
    _sub(geo, "cylinder", radius=fmt(shape.radius), length=fmt(shape.length))


def add_link(root, link, materials):
    el = _sub(root, "link", name=link.name)
    if link.body is None:
        return el
    inertial = _sub(el, "inertial")
    _sub(inertial, "origin", xyz=vec(link.com), rpy="0 0 0")
    _sub(inertial, "mass", value=fmt(link.mass))
    ixx, iyy, izz = link.inertia
    _sub(inertial, "inertia", ixx=fmt(ixx), ixy="0", ixz="0", iyy=fmt(iyy), iyz="0", izz=fmt(izz))
    for shape in link.body.shapes:
        for tag in ("visual", "collision"):
            part = _sub(el, tag)
            _sub(part, "origin", xyz=vec(shape.center), rpy=vec(_shape_rpy(shape.axis)))
            _geometry(part, shape)
            if tag == "visual":
                _sub(part, "material", name=materials[link.material])
    return el


def add_joint(root, joint):
    el = _sub(root, "joint", name=joint.name, type=joint.type)
    _sub(el, "parent", link=joint.parent)
    _sub(el, "child", link=joint.child)
    _sub(el, "origin", xyz=vec(joint.xyz), rpy=vec(joint.rpy))
    m = joint.module
    if joint.actuated and m is not None:
        _sub(el, "axis", xyz=vec(AXES[m.axis]))
        _sub(el, "limit", lower=fmt(m.lower), upper=fmt(m.upper), effort=fmt(m.effort),
             velocity=fmt(m.velocity))
        _sub(el, "dynamics", damping=fmt(m.damping), friction=fmt(m.friction))
    return el


def add_link_gazebo(root, link):
    if link.body is None:
        return
    module = link.module
    gz = _sub(root, "gazebo", reference=link.name)
    _text(gz, "material", module.gazebo_material)
    _text(gz, "mu1", fmt(module.mu1))
    _text(gz, "mu2", fmt(module.mu2))
    _text(gz, "selfCollide", "false")


def add_joint_gazebo(root, joint):
    gz = _sub(root, "gazebo", reference=joint.name)
    _text(gz, "implicitSpringDamper", "true")
    _text(gz, "provideFeedback", "true")


def add_transmission(root, joint, number, reduction):
    tr = _sub(root, "transmission", name="trans%d" % number)
    _text(tr, "type", "transmission_interface/SimpleTransmission")
    j = _sub(tr, "joint", name=joint.name)
    _text(j, "hardwareInterface", HW_INTERFACE)
    act = _sub(tr, "actuator", name="motor%d" % number)
    _text(act, "hardwareInterface", HW_INTERFACE)
    _text(act, "mechanicalReduction", "%f" % reduction)


def add_control_plugin(root, namespace):
    gz = _sub(root, "gazebo")
    plugin = _sub(gz, "plugin", name="gazebo_ros_control", filename=CONTROL_PLUGIN)
    _text(plugin, "robotNamespace", namespace)
    _text(plugin, "robotSimType", ROBOT_SIM_TYPE)


def robot_element(robot, comment=None):
    """The <robot> element (arm only; the gripper is added by gripper.py through xacro)."""
    root = ET.Element("robot", name=robot.name)
    if comment:
        root.append(ET.Comment(comment))
    materials = material_names(robot)
    for (gz_name, rgba), name in materials.items():
        mat = _sub(root, "material", name=name)
        _sub(mat, "color", rgba=vec(rgba))
    for link in robot.links:
        add_link(root, link, materials)
    for joint in robot.joints:
        add_joint(root, joint)
    for link in robot.links:
        add_link_gazebo(root, link)
    for number, joint in enumerate(robot.actuated_joints, start=1):
        add_joint_gazebo(root, joint)
        add_transmission(root, joint, number, joint.module.reduction)
    add_control_plugin(root, robot.namespace)
    return root


def default_comment(robot):
    return (" %s: generated by modrob_build (create_urdf_and_gazebo) from the module order [%s], "
            "base at x=%s y=%s z=%s yaw=%s. Do not edit: regenerate. "
            % (robot.name, ", ".join(str(i) for i in robot.order), *[fmt(v) for v in robot.base_pose]))


def to_text(root):
    ET.indent(root, space="  ")
    return '<?xml version="1.0"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def robot_urdf(robot, comment=None):
    """URDF text of the arm."""
    return to_text(robot_element(robot, comment if comment is not None else default_comment(robot)))
