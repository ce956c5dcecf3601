"""apply_body_wrench, apply_joint_effort, clear_body_wrenches, clear_joint_forces (the timing of
the jobs is force_jobs.ForceJobs')."""
import math

import rospy
from gazebo_msgs import srv as gzs

from modrob_sim.errors import RequestError
from modrob_sim.gazebo_ros import transforms as tf
from modrob_sim.gazebo_ros.conversions import vector_from_msg
from modrob_sim.gazebo_ros.services.base import ServiceGroup, Status
from modrob_sim.physics.limits import LENGTH_LIMIT
from modrob_sim.physics.model import FORCE_CAP


def _bounded(field, v, limit, unit):
    if max(abs(x) for x in v) > limit:
        raise RequestError("%s %r is beyond +-%g %s (limits: docs/simulator.md); nothing applied"
                           % (field, tuple(v), limit, unit))


class ForceServices(ServiceGroup):
    def advertise(self):
        S = rospy.Service
        return [
            S("~apply_body_wrench", gzs.ApplyBodyWrench, self.apply_body_wrench),
            S("~apply_joint_effort", gzs.ApplyJointEffort, self.apply_joint_effort),
            S("~clear_body_wrenches", gzs.BodyRequest, self.clear_body_wrenches),
            S("~clear_joint_forces", gzs.JointRequest, self.clear_joint_forces),
        ]

    def apply_body_wrench(self, req):
        forces = self.sim.forces

        def do():
            link = self.lookup.link(req.body_name, "body_name [%s] does not exist; use the scoped name "
                                                   "model::link")
            f = vector_from_msg(req.wrench.force)
            tq = vector_from_msg(req.wrench.torque)
            p = vector_from_msg(req.reference_point)
            if not tf.is_finite(f, tq, p):
                raise RequestError("wrench or reference_point has a NaN or infinite value")
            _bounded("wrench.force", f, FORCE_CAP, "N")
            _bounded("wrench.torque", tq, FORCE_CAP, "N m")
            _bounded("reference_point", p, LENGTH_LIMIT, "m")
            if req.duration.to_sec() == 0.0:
                return "duration is 0: nothing applied"
            frame = self.lookup.frame(req.reference_frame)
            link_pose = link.pose
            if frame is not None:     # wrench and point given in that frame: rotate / move to world
                q = frame[0][1]
                f, tq = tf.quat_rotate(q, f), tf.quat_rotate(q, tq)
                p_world = tf.add(frame[0][0], tf.quat_rotate(q, p))
            else:                     # world axes, point relative to the body's origin
                p_world = tf.add(link_pose[0], p)
            # the core takes the point in the link frame (where the force acts on the link)
            p = tf.quat_rotate(tf.quat_conj(link_pose[1]), tf.sub(p_world, link_pose[0]))
            _bounded("reference_point (from the link origin, after reference_frame)", p, LENGTH_LIMIT, "m")
            start, duration = forces.start_and_duration(req.start_time.to_sec(), req.duration.to_sec())
            forces.add_wrench(link, f, tq, p, start, duration)
            return "wrench applied to [%s] from t=%.3f s %s" % (
                req.body_name, start, "until cleared" if duration is None else "for %.3f s" % duration)
        return self.run(do, gzs.ApplyBodyWrenchResponse(), "ApplyBodyWrench")

    def apply_joint_effort(self, req):
        forces = self.sim.forces

        def do():
            joint = self.lookup.joint(req.joint_name)
            if not math.isfinite(req.effort):
                raise RequestError("effort is NaN or infinite")
            if joint.type in ("fixed", "floating", "planar") or joint.ode_joint is None:
                raise RequestError("joint [%s] is %s: it takes no effort (nothing applied)"
                                   % (req.joint_name, joint.type))
            if abs(req.effort) > FORCE_CAP:
                raise RequestError("effort %g is beyond +-%g (limits: docs/simulator.md); nothing applied"
                                   % (req.effort, FORCE_CAP))
            if req.duration.to_sec() == 0.0:
                return "duration is 0: nothing applied"
            start, duration = forces.start_and_duration(req.start_time.to_sec(), req.duration.to_sec())
            end = None if duration is None else start + duration
            forces.add_effort(joint, float(req.effort), start, end)
            return "effort %g on [%s] from t=%.3f s %s" % (
                req.effort, req.joint_name, start,
                "until cleared" if end is None else "for %.3f s" % duration)
        return self.run(do, gzs.ApplyJointEffortResponse(), "ApplyJointEffort")

    def clear_body_wrenches(self, req):
        def do():
            link = self.lookup.link(req.body_name, "body_name [%s] does not exist")
            self.sim.forces.clear_link(link)
        self.run(do, Status(), "ClearBodyWrenches")
        return gzs.BodyRequestResponse()

    def clear_joint_forces(self, req):
        def do():
            self.sim.forces.clear_joint(self.lookup.joint(req.joint_name))
        self.run(do, Status(), "ClearJointForces")
        return gzs.JointRequestResponse()
