"""get_world/model/joint/link_properties, set_link_properties, and the Gazebo services this
simulator cannot honour (answered with success: false and the reason)."""
import rospy
from gazebo_msgs import srv as gzs

from modrob_sim.errors import RequestError
from modrob_sim.gazebo_ros import transforms as tf
from modrob_sim.gazebo_ros.conversions import pose_from_msg, pose_to_msg
from modrob_sim.gazebo_ros.services.base import ServiceGroup

JOINT_TYPE = {"revolute": gzs.GetJointPropertiesResponse.REVOLUTE,
              "continuous": gzs.GetJointPropertiesResponse.CONTINUOUS,
              "prismatic": gzs.GetJointPropertiesResponse.PRISMATIC,
              "fixed": gzs.GetJointPropertiesResponse.FIXED,
              "floating": gzs.GetJointPropertiesResponse.BALL,
              "planar": gzs.GetJointPropertiesResponse.UNIVERSAL}

NO_LIGHTS = "lights are not simulated (RViz lights the scene itself)"


class PropertyServices(ServiceGroup):
    def advertise(self):
        S = rospy.Service
        u = self.unsupported
        return [
            S("~get_world_properties", gzs.GetWorldProperties, self.get_world_properties),
            S("~get_model_properties", gzs.GetModelProperties, self.get_model_properties),
            S("~get_joint_properties", gzs.GetJointProperties, self.get_joint_properties),
            S("~get_link_properties", gzs.GetLinkProperties, self.get_link_properties),
            S("~set_link_properties", gzs.SetLinkProperties, self.set_link_properties),
            # Gazebo offers these too; this simulator models no lights and no ODE joint tuning:
            # they answer success: false with the reason instead of leaving callers waiting
            S("~delete_light", gzs.DeleteLight, lambda r: u(
                gzs.DeleteLightResponse(), "DeleteLight", "light [%s]" % r.light_name,
                "lights are not simulated")),
            S("~get_light_properties", gzs.GetLightProperties, lambda r: u(
                gzs.GetLightPropertiesResponse(), "GetLightProperties", "light [%s]" % r.light_name,
                NO_LIGHTS)),
            S("~set_light_properties", gzs.SetLightProperties, lambda r: u(
                gzs.SetLightPropertiesResponse(), "SetLightProperties", "light [%s]" % r.light_name,
                NO_LIGHTS)),
            S("~set_joint_properties", gzs.SetJointProperties, lambda r: u(
                gzs.SetJointPropertiesResponse(), "SetJointProperties", "joint [%s]" % r.joint_name,
                "ODE joint parameters cannot be changed at run time; set <dynamics> and <limit> in the "
                "URDF and spawn the model again")),
        ]

    def get_world_properties(self, req):
        resp = gzs.GetWorldPropertiesResponse()

        def do():
            resp.sim_time = self.world.time
            resp.model_names = list(self.world.models)
            resp.rendering_enabled = False
            return "GetWorldProperties: got properties"
        self.run(do, resp, "GetWorldProperties")
        resp.status_message = "GetWorldProperties: got properties" if resp.success else resp.status_message
        return resp

    def get_model_properties(self, req):
        resp = gzs.GetModelPropertiesResponse()

        def do():
            m = self.lookup.model(req.model_name)
            resp.parent_model_name = ""
            resp.canonical_body_name = m.canonical_link.name if m.canonical_link is not None else ""
            resp.body_names = list(m.links)
            resp.geom_names = [g for link in m.links.values() for g in link.collision_names]
            resp.joint_names = [n for n, j in m.joints.items() if j.type != "fixed"]
            resp.child_model_names = []
            resp.is_static = bool(m.is_static)
            return "got properties"
        return self.run(do, resp, "GetModelProperties")

    def get_joint_properties(self, req):
        resp = gzs.GetJointPropertiesResponse()

        def do():
            j = self.lookup.joint(req.joint_name)
            resp.type = JOINT_TYPE.get(j.type, gzs.GetJointPropertiesResponse.FIXED)
            if j.type == "fixed":
                resp.damping, resp.position, resp.rate = [], [], []
            else:
                resp.damping = [float(j.damping or 0.0)]
                resp.position = [float(j.position)]
                resp.rate = [float(j.velocity)]
            return "got properties"
        return self.run(do, resp, "GetJointProperties")

    def get_link_properties(self, req):
        resp = gzs.GetLinkPropertiesResponse()

        def do():
            link = self.lookup.link(req.link_name)
            pose_to_msg(link.inertial_origin, resp.com)
            resp.gravity_mode = bool(link.gravity_enabled)
            resp.mass = float(link.mass)
            (resp.ixx, resp.ixy, resp.ixz, resp.iyy, resp.iyz, resp.izz) = [float(v) for v in link.inertia]
            return "got properties"
        return self.run(do, resp, "GetLinkProperties")

    def set_link_properties(self, req):
        def do():
            link = self.lookup.link(req.link_name)
            inertia = (req.ixx, req.ixy, req.ixz, req.iyy, req.iyz, req.izz)
            pose_from_msg(req.com, "com")    # checked; the inertial frame cannot move
            if not tf.is_finite(inertia, req.mass):
                raise RequestError("mass or inertia has a NaN or infinite value")
            changed = abs(req.mass - link.mass) > 1e-12 or any(
                abs(a - b) > 1e-12 for a, b in zip(inertia, link.inertia))
            if changed:
                raise RequestError("changing mass/inertia of a link is not supported by this simulator; "
                                   "only gravity_mode can be set (send the current mass and inertia)")
            link.gravity_enabled = bool(req.gravity_mode)
            return "set link properties done"
        return self.run(do, gzs.SetLinkPropertiesResponse(), "SetLinkProperties")
