"""Spawn, delete, get/set model and link states, set_model_configuration."""
import xml.etree.ElementTree as ET

import rospy
from gazebo_msgs import msg as gzm
from gazebo_msgs import srv as gzs

from modrob_sim.errors import ModrobError, RequestError
from modrob_sim.gazebo_ros import memory_debug
from modrob_sim.gazebo_ros import transforms as tf
from modrob_sim.gazebo_ros.conversions import (pose_from_msg, pose_to_msg, ros_time, twist_from_msg,
                                               twist_to_msg)
from modrob_sim.gazebo_ros.services.base import ServiceGroup


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


class ModelServices(ServiceGroup):
    def __init__(self, sim):
        super(ModelServices, self).__init__(sim)
        self._seq = 0

    def advertise(self):
        S = rospy.Service
        return [
            S("~spawn_urdf_model", gzs.SpawnModel, lambda r: self.spawn(r, "urdf")),
            S("~spawn_sdf_model", gzs.SpawnModel, lambda r: self.spawn(r, "sdf")),
            S("~delete_model", gzs.DeleteModel, self.delete_model),
            S("~get_model_state", gzs.GetModelState, self.get_model_state),
            S("~set_model_state", gzs.SetModelState, self.set_model_state_srv),
            S("~set_model_configuration", gzs.SetModelConfiguration, self.set_model_configuration),
            S("~get_link_state", gzs.GetLinkState, self.get_link_state),
            S("~set_link_state", gzs.SetLinkState, self.set_link_state_srv),
            rospy.Subscriber("~set_model_state", gzm.ModelState, self.set_model_state_topic, queue_size=50),
            rospy.Subscriber("~set_link_state", gzm.LinkState, self.set_link_state_topic, queue_size=50),
        ]

    # ---- spawn / delete -----------------------------------------------------------------------
    def spawn(self, req, service_kind):
        name = req.model_name.strip()
        xml = req.model_xml
        kind = xml_kind(xml)

        def do():
            if not name:
                raise RequestError("model_name is empty: give the model a name")
            if name in self.world.models:
                raise RequestError("model name [%s] already exists: delete it first (/gazebo/delete_model) "
                                   "or choose another name" % name)
            if not xml.strip():
                raise RequestError("model_xml of [%s] is empty (did the robot_description parameter "
                                   "load?)" % name)
            if kind is None:
                try:
                    ET.fromstring(xml)
                except ET.ParseError as exc:
                    raise RequestError("model_xml of [%s] is not valid XML: %s" % (name, exc))
                raise RequestError("model_xml of [%s] is neither URDF (<robot>) nor SDF (<sdf>, <model>)"
                                   % name)
            pose = pose_from_msg(req.initial_pose, "initial_pose")
            frame = self.lookup.frame(req.reference_frame)
            if frame is not None:
                pose = tf.compose(frame[0], pose)
            ns = req.robot_namespace
            try:
                if kind == "urdf":
                    models = [self.world.add_urdf(name, xml, pose=pose, robot_namespace=ns)]
                else:
                    models = self.world.add_sdf(xml, name=name, pose=pose)
            except ModrobError as exc:
                raise RequestError("could not spawn [%s]: %s" % (name, exc))
            for m in models:
                self.sim.plugins.load(m, ns)
            self.sim.outputs.publish_markers(force=True)
            return "Successfully spawned entity [%s]" % ", ".join(m.name for m in models)
        if kind is not None and service_kind != kind:
            rospy.loginfo("spawn_%s_model got %s text for [%s]: spawning it as %s" % (
                service_kind, kind.upper(), name, kind.upper()))
        return self.run(do, gzs.SpawnModelResponse(), "SpawnModel")

    def delete_model(self, req):
        def do():
            model = self.lookup.model(req.model_name)
            self.sim.plugins.unload(req.model_name)
            self.sim.forces.drop_model(model)
            self.world.remove_model(req.model_name)
            self.sim.outputs.forget_model(req.model_name)
            self.sim.outputs.publish_markers(force=True)
            return "successfully deleted model [%s]" % req.model_name
        resp = self.run(do, gzs.DeleteModelResponse(), "DeleteModel")
        memory_debug.trim_heap()   # in this service thread: the loop does not wait for it
        return resp

    # ---- states -------------------------------------------------------------------------------
    def _moved(self):
        """A model was moved by hand (in the loop). While the simulation runs, the next marker time
        draws it; while it is paused nothing would, so the latched ~world_markers are made now, for
        RViz and for whoever subscribes later, as after a spawn."""
        if self.loop.paused:
            self.sim.outputs.publish_markers(force=True)

    def get_model_state(self, req):
        resp = gzs.GetModelStateResponse()

        def do():
            m = self.lookup.model(req.model_name)
            pose, twist = m.pose, m.twist
            frame = self.lookup.frame(req.relative_entity_name, "relative_entity_name")
            if frame is not None:
                pose = tf.relative(frame[0], pose)
                twist = tf.twist_in_frame(frame[0], frame[1], twist)
            self._seq += 1
            resp.header.seq = self._seq
            resp.header.stamp = ros_time(self.world.time)
            resp.header.frame_id = req.relative_entity_name
            pose_to_msg(pose, resp.pose)
            twist_to_msg(twist, resp.twist)
            return "got properties"
        return self.run(do, resp, "GetModelState")

    def _apply_model_state(self, state):
        m = self.lookup.model(state.model_name)
        pose = pose_from_msg(state.pose, "model_state.pose")
        twist = twist_from_msg(state.twist, "model_state.twist")
        frame = self.lookup.frame(state.reference_frame)
        if frame is not None:
            pose = tf.compose(frame[0], pose)
            twist = tf.twist_to_world(frame[0], twist)
        m.set_pose(pose)
        m.set_twist(twist)
        self._moved()
        return "set model state done"

    def set_model_state_srv(self, req):
        return self.run(lambda: self._apply_model_state(req.model_state), gzs.SetModelStateResponse(),
                        "SetModelState")

    def set_model_state_topic(self, msg):
        self.post(lambda: self._apply_model_state(msg), "/gazebo/set_model_state")

    def _apply_link_state(self, state):
        link = self.lookup.link(state.link_name)
        pose = pose_from_msg(state.pose, "link_state.pose")
        twist = twist_from_msg(state.twist, "link_state.twist")
        frame = self.lookup.frame(state.reference_frame)
        if frame is not None:
            pose = tf.compose(frame[0], pose)
            twist = tf.twist_to_world(frame[0], twist)
        link.set_pose(pose)
        link.set_twist(twist)
        self._moved()
        return "set link state done"

    def set_link_state_srv(self, req):
        return self.run(lambda: self._apply_link_state(req.link_state), gzs.SetLinkStateResponse(),
                        "SetLinkState")

    def set_link_state_topic(self, msg):
        self.post(lambda: self._apply_link_state(msg), "/gazebo/set_link_state")

    def get_link_state(self, req):
        resp = gzs.GetLinkStateResponse()

        def do():
            link = self.lookup.link(req.link_name)
            pose, twist = link.pose, link.twist
            frame = self.lookup.frame(req.reference_frame)
            if frame is not None:
                pose = tf.relative(frame[0], pose)
                twist = tf.twist_in_frame(frame[0], frame[1], twist)
            resp.link_state.link_name = req.link_name
            pose_to_msg(pose, resp.link_state.pose)
            twist_to_msg(twist, resp.link_state.twist)
            resp.link_state.reference_frame = req.reference_frame
            return "got state"
        return self.run(do, resp, "GetLinkState")

    def set_model_configuration(self, req):
        def do():
            m = self.lookup.model(req.model_name)
            if len(req.joint_names) != len(req.joint_positions):
                raise RequestError("%d joint_names but %d joint_positions"
                                   % (len(req.joint_names), len(req.joint_positions)))
            unknown = [j for j in req.joint_names if j not in m.joints]
            if unknown:
                raise RequestError("model [%s] has no joint %s (joints: %s)" % (
                    req.model_name, ", ".join(unknown), ", ".join(m.joints)))
            if not tf.is_finite(tuple(req.joint_positions)):
                raise RequestError("joint_positions has a NaN or infinite value: %s" % (req.joint_positions,))
            m.set_configuration(list(req.joint_names), [float(v) for v in req.joint_positions])
            self._moved()
            return "set model configuration done"
        return self.run(do, gzs.SetModelConfigurationResponse(), "SetModelConfiguration")
