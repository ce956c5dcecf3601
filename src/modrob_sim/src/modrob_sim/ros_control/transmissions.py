"""URDF ``<transmission>`` parsing (transmission_interface's TransmissionParser rules) and
transmission_interface::SimpleTransmission.

How gazebo_ros_control uses them: DefaultRobotHWSim (gazebo_ros_control/src/
default_robot_hw_sim.cpp) takes from each transmission ONLY the joint name and its first
``<hardwareInterface>`` (falling back, with a deprecation warning, to the actuator's). It never
builds a transmission: ``mechanicalReduction`` is parsed but IGNORED, so controllers command the
joint directly (an effort of 5 N m is 5 N m at the joint, whatever the reduction). We do the same;
``SimpleTransmission`` below is the real transmission_interface mapping, kept for users of
actuator-space values and tested for its actuator->joint->actuator identity.
"""
import xml.etree.ElementTree as ET

from modrob_sim.errors import ModelError

EFFORT = "EffortJointInterface"
POSITION = "PositionJointInterface"
VELOCITY = "VelocityJointInterface"
INTERFACES = (EFFORT, POSITION, VELOCITY)
CPP_NAMES = {EFFORT: "hardware_interface::EffortJointInterface",
             POSITION: "hardware_interface::PositionJointInterface",
             VELOCITY: "hardware_interface::VelocityJointInterface"}


def canonical_interface(text):
    """'hardware_interface/EffortJointInterface', 'EffortJointInterface' or
    'hardware_interface::EffortJointInterface' -> 'EffortJointInterface'; None if unknown."""
    name = (text or "").strip()
    for prefix in ("hardware_interface/", "hardware_interface::"):
        if name.startswith(prefix):
            name = name[len(prefix):]
    return name if name in INTERFACES else None


class TransmissionJoint(object):
    def __init__(self, name, interfaces):
        self.name, self.interfaces = name, interfaces


class TransmissionActuator(object):
    def __init__(self, name, reduction, interfaces):
        self.name, self.reduction, self.interfaces = name, reduction, interfaces


class TransmissionInfo(object):
    def __init__(self, name, type_, joints, actuators):
        self.name, self.type, self.joints, self.actuators = name, type_, joints, actuators

    def __repr__(self):
        return "TransmissionInfo(%s, %s, joints=%s)" % (self.name, self.type, [j.name for j in self.joints])


def _text(el, tag):
    child = el.find(tag)
    return child.text.strip() if child is not None and child.text else None


def parse_transmissions(urdf_xml):
    """Every ``<transmission>`` of a URDF string, in document order. Raises ModelError for XML
    that does not parse or a transmission without a name/joint name."""
    try:
        root = ET.fromstring(urdf_xml)
    except ET.ParseError as exc:
        raise ModelError("robot description is not valid XML: %s" % exc)
    out = []
    for el in root.iter("transmission"):
        name = el.get("name")
        if not name:
            raise ModelError("a <transmission> without a name attribute; give each transmission a "
                             "unique name")
        type_ = _text(el, "type") or el.get("type") or ""
        joints = []
        for j in el.findall("joint"):
            if not j.get("name"):
                raise ModelError("transmission '%s': a <joint> without a name attribute" % name)
            ifaces = [h.text.strip() for h in j.findall("hardwareInterface") if h.text and h.text.strip()]
            joints.append(TransmissionJoint(j.get("name"), ifaces))
        actuators = []
        for a in el.findall("actuator"):
            red_text = _text(a, "mechanicalReduction")
            try:
                reduction = float(red_text) if red_text is not None else 1.0
            except ValueError:
                raise ModelError("transmission '%s', actuator '%s': mechanicalReduction %r is not a number"
                                 % (name, a.get("name"), red_text))
            actuators.append(TransmissionActuator(a.get("name") or "", reduction,
                                                  [h.text.strip() for h in a.findall("hardwareInterface")
                                                   if h.text and h.text.strip()]))
        out.append(TransmissionInfo(name, type_, joints, actuators))
    return out


class SimpleTransmission(object):
    """transmission_interface::SimpleTransmission: one actuator, one joint, reduction n, offset.
    joint effort = n * actuator effort; joint velocity = actuator velocity / n;
    joint position = actuator position / n + offset (and the inverse maps)."""

    def __init__(self, reduction, joint_offset=0.0):
        if reduction == 0.0:
            raise ModelError("SimpleTransmission: mechanicalReduction must not be zero")
        self.reduction, self.joint_offset = float(reduction), float(joint_offset)

    def actuator_to_joint_effort(self, e):
        return e * self.reduction

    def actuator_to_joint_velocity(self, v):
        return v / self.reduction

    def actuator_to_joint_position(self, p):
        return p / self.reduction + self.joint_offset

    def joint_to_actuator_effort(self, e):
        return e / self.reduction

    def joint_to_actuator_velocity(self, v):
        return v * self.reduction

    def joint_to_actuator_position(self, p):
        return (p - self.joint_offset) * self.reduction
