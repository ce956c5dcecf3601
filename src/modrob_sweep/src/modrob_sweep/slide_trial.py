"""The slide trial: a small, real scenario for sweeps and their tests (a few seconds per trial).

A puck is pushed along the floor of a paused /gazebo world with speed v0 (times 1 + jitter x a
seeded standard normal draw) and slides until friction (its mu) stops it. The trial steps the
simulation itself through /gazebo/step, so its result depends only on its parameters and seed,
never on the machine's speed. Success: the puck comes to rest before the stop line.
Writes the result file (YAML): success, distance, predicted (v0^2 / (2 mu g)), rest_time, v0,
sim_time, steps.

``fault`` makes a trial misbehave on purpose, for the tests of the runner: ``crash`` kills the
node with SIGKILL once the simulator is up (roslaunch then ends: no result file), ``hang`` never
finishes.
"""
import math
import os
import signal
import threading

import numpy as np
import yaml

G = 9.81
SETTLE_STEPS = 100
CHUNK_STEPS = 100
REST_SPEED = 1e-3


def predicted_distance(v0, mu):
    return v0 * v0 / (2.0 * mu * G) if mu > 0 else math.inf


def initial_speed(v0, jitter, seed):
    """v0 x (1 + jitter x N(0, 1)) from the trial's own generator."""
    return float(v0 * (1.0 + jitter * np.random.default_rng(seed).standard_normal()))


class SlideTrial(object):
    """The ROS side: the /gazebo services of a paused world."""

    def __init__(self, floor_xml, puck_xml, timeout=30.0):
        import rospy
        from gazebo_msgs.srv import GetModelState, SetModelState, SpawnModel
        from modrob_msgs.srv import StepSimulation
        names = ("/gazebo/spawn_urdf_model", "/gazebo/set_model_state", "/gazebo/get_model_state",
                 "/gazebo/step")
        for n in names:
            rospy.wait_for_service(n, timeout=timeout)
        self.spawn = rospy.ServiceProxy(names[0], SpawnModel)
        self.set_state = rospy.ServiceProxy(names[1], SetModelState)
        self.get_state = rospy.ServiceProxy(names[2], GetModelState)
        self.step_srv = rospy.ServiceProxy(names[3], StepSimulation)
        self.floor_xml, self.puck_xml = floor_xml, puck_xml
        self.sim_time, self.steps = 0.0, 0

    def step(self, n):
        resp = self.step_srv(n)
        if not resp.success:
            raise RuntimeError("/gazebo/step %d refused: %s (is the world paused?)" % (n,
                                                                                       resp.status_message))
        self.sim_time, self.steps = resp.sim_time, resp.iterations

    def state(self):
        resp = self.get_state("puck", "world")
        if not resp.success:
            raise RuntimeError("get_model_state puck: %s" % resp.status_message)
        return resp

    def run(self, v0, max_time):
        from geometry_msgs.msg import Pose
        from gazebo_msgs.msg import ModelState
        for name, xml, z in (("floor", self.floor_xml, 0.0), ("puck", self.puck_xml, 0.025)):
            pose = Pose()
            pose.position.z = z
            pose.orientation.w = 1.0
            resp = self.spawn(name, xml, "", pose, "world")
            if not resp.success:
                raise RuntimeError("spawn %s: %s" % (name, resp.status_message))
        self.step(SETTLE_STEPS)
        start = self.state()
        ms = ModelState(model_name="puck", pose=start.pose, reference_frame="world")
        ms.twist.linear.x = v0
        resp = self.set_state(ms)
        if not resp.success:
            raise RuntimeError("set_model_state puck: %s" % resp.status_message)
        t_push = self.sim_time
        rest_time = math.nan
        while self.sim_time - t_push < max_time:
            self.step(CHUNK_STEPS)
            s = self.state()
            v = s.twist.linear
            if math.sqrt(v.x * v.x + v.y * v.y + v.z * v.z) < REST_SPEED:
                rest_time = self.sim_time - t_push
                break
        end = self.state().pose.position
        return end.x - start.pose.position.x, rest_time


def main(argv=None):
    import rospy
    rospy.init_node("slide_trial")
    mu = float(rospy.get_param("~mu"))
    v0 = float(rospy.get_param("~v0", 1.0))
    jitter = float(rospy.get_param("~jitter", 0.0))
    seed = int(rospy.get_param("~seed", 0))
    stop_line = float(rospy.get_param("~stop_line", 0.5))
    max_time = float(rospy.get_param("~max_time", 5.0))
    fault = str(rospy.get_param("~fault", "none"))
    result_file = rospy.get_param("~result_file")
    trial = SlideTrial(rospy.get_param("~floor_description"), rospy.get_param("~puck_description"))
    if fault == "crash":
        rospy.logwarn("slide_trial: fault=crash: killing myself")
        os.kill(os.getpid(), signal.SIGKILL)
    if fault == "hang":
        rospy.logwarn("slide_trial: fault=hang: never finishing")
        threading.Event().wait()
    speed = initial_speed(v0, jitter, seed)
    distance, rest_time = trial.run(speed, max_time)
    result = {"success": bool(rest_time == rest_time and distance < stop_line), "distance": float(distance),
              "predicted": float(predicted_distance(speed, mu)), "rest_time": float(rest_time), "v0": speed,
              "mu": mu, "seed": seed, "sim_time": float(trial.sim_time), "steps": int(trial.steps)}
    d = os.path.dirname(os.path.abspath(result_file))
    os.makedirs(d, exist_ok=True)
    with open(result_file, "w") as fh:
        yaml.safe_dump(result, fh, sort_keys=True)
    print("RESULT slide_trial: %s, distance %.4f m (predicted %.4f m), at rest after %.2f s"
          % ("SUCCESS" if result["success"] else "FAILURE", distance, result["predicted"], rest_time),
          flush=True)
    return 0
