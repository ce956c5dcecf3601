"""The Polaris on the workspace's physics core without ROS: the same URDF, the same
gazebo_ros_control hardware (RobotHWSim with the table-2 pid_gains), stepped in-process.

For tier-1 tests and the figure scripts: deterministic, faster than the /gazebo node, and the
commands go through exactly the code the simulator's ros_control plugin runs (position and
velocity controllers only write the joint command; the hardware's PIDs do the rest).
"""
import math
import os
import subprocess

import yaml

from modrob_sim.physics import World
from modrob_sim.ros_control.hardware import RobotHWSim
from modrob_sim.ros_control.params import Params
from modrob_sim.ros_control.transmissions import parse_transmissions

from polaris_description import geometry as G
from polaris_description.errors import ConfigError
from polaris_description.transforms import quat_from_yaw, rotate, rotate_inverse, yaw_pitch_roll

PKG_DIR = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
URDF_XACRO = os.path.join(PKG_DIR, "urdf", "polaris.urdf.xacro")
PARKING_LOT = os.path.join(PKG_DIR, "worlds", "parking_lot.world")
PID_CONFIGS = (1, 2, 3, 4, 5, 6)
SPAWN_Z = 0.33
INF = float("inf")
FLAT_GROUND = ("<sdf version='1.6'><world name='flat'><include><uri>model://ground_plane</uri></include>"
               "</world></sdf>")


def pid_config_path(n):
    return os.path.join(PKG_DIR, "config", "pid_gains", "config_%s.yaml" % n)


def load_pid_gains(n):
    """The ``gazebo_ros_control/pid_gains`` dictionary of table 2's configuration ``n``."""
    path = pid_config_path(n)
    if not os.path.isfile(path):
        raise ConfigError("PID configuration %r does not exist (table 2 has %s): %s"
                          % (n, ", ".join(map(str, PID_CONFIGS)), path))
    with open(path) as f:
        data = yaml.safe_load(f)
    gains = (data or {}).get("gazebo_ros_control/pid_gains")
    if not isinstance(gains, dict):
        raise ConfigError("%s has no gazebo_ros_control/pid_gains dictionary" % path)
    return gains


def urdf_text(**args):
    """The URDF from the xacro, with xacro arguments such as four_wd=True, velodyne=False."""
    cmd = ["xacro", URDF_XACRO] + ["%s:=%s" % (k, str(v).lower() if isinstance(v, bool) else v)
                                   for k, v in sorted(args.items())]
    try:
        return subprocess.check_output(cmd, universal_newlines=True)
    except (OSError, subprocess.CalledProcessError) as e:
        raise ConfigError("xacro failed for %s (source scripts/env.sh first): %s" % (URDF_XACRO, e))


class VehicleSim(object):
    """One Polaris in a world. ``command(**joint_commands)`` sets commands (keys of
    geometry.JOINTS: steer_left, steer_right, rear_left, rear_right, front_left, front_right);
    ``run(seconds, controller=None, every=0.01)`` steps and returns samples (dicts).
    ``world_file`` None: a flat ground plane only (the seed's experiment)."""

    def __init__(self, world_file=PARKING_LOT, pid_config=5, four_wd=False, pose=(0.0, 0.0, 0.0),
                 time_step=0.001, seed=0, urdf=None):
        self.world = World(time_step=time_step, seed=seed)
        if world_file:
            with open(world_file) as f:
                self.world.add_sdf(f.read())
        else:
            self.world.add_sdf(FLAT_GROUND)
        if urdf is None:
            urdf = urdf_text(velodyne=False, four_wd=four_wd)
        x, y, yaw = pose
        self.model = self.world.add_urdf("polaris", urdf, pose=((x, y, SPAWN_Z), quat_from_yaw(yaw)))
        gains = load_pid_gains(pid_config)
        self.hw = RobotHWSim(self.model.joints, parse_transmissions(urdf),
                             Params(gains, "/gazebo_ros_control/pid_gains"), world=self.world)
        self.four_wd = four_wd
        self._commanded = True
        self.world.add_step_hook(before=self._before, before_due=self._before_due)

    def command(self, **cmds):
        for key, value in cmds.items():
            if key not in G.JOINTS:
                raise ConfigError("unknown wheel/steering key %r (known: %s)" % (key, ", ".join(G.JOINTS)))
            res = self.hw.joints.get(G.JOINTS[key])
            if res is not None:
                res.command = float(value)
                self._commanded = True

    def _before_due(self):
        # as gazebo_ros_control's loop between controller updates: the hardware writes when a
        # command came or its write still has work (a steering target rate-limited towards);
        # otherwise the World's actuators hold the last write and the steps run natively
        return None if self._commanded or self.hw.needs_every_update else INF

    def _before(self, t, dt):
        self._commanded = False
        self.hw.read()
        self.hw.write(dt)

    @property
    def time(self):
        return self.world.time

    def state(self):
        """Pose and speeds of base_link_polaris (the model's root link), plus joint values."""
        (x, y, z), q = self.model.pose
        (vx, vy, vz), (wx, wy, wz) = self.model.twist
        yaw, pitch, roll = yaw_pitch_roll(q)
        fwd = rotate_inverse(q, (vx, vy, vz))
        j = {k: (self.model.joints[n].position, self.model.joints[n].velocity) for k, n in G.JOINTS.items()}
        return {"t": self.world.time, "x": x, "y": y, "z": z, "yaw": yaw, "pitch": pitch, "roll": roll,
                "speed": math.hypot(vx, vy), "v_forward": fwd[0], "yaw_rate": wz, "joints": j}

    def run(self, seconds, controller=None, every=0.01):
        """Step ``seconds``; ``controller(state)`` (optional) is called every ``every`` s and may
        call ``command``. Returns the list of states sampled every ``every`` s."""
        n_total = int(round(seconds / self.world.time_step))
        n_every = max(1, int(round(every / self.world.time_step)))
        out = []
        done = 0
        while done < n_total:
            s = self.state()
            out.append(s)
            if controller is not None and controller(s) is False:
                break
            k = min(n_every, n_total - done)
            self.world.step(k)
            done += k
        return out

    def wheel_slip(self, key):
        """Longitudinal slip of a wheel in m/s: rim speed (joint rate x radius) minus the ground
        speed of its contact point along its rolling direction (see contact_ground_speed)."""
        return self.model.joints[G.JOINTS[key]].velocity * G.WHEEL_RADIUS - self.contact_ground_speed(key)

    def commanded_slip(self, key):
        """The slip the wheel's COMMAND asks for: commanded rate x radius minus the contact's ground
        speed. The velocity loops (P only: no i_clamp) yield instead of slipping, so in a turn with
        one rate on both rear wheels this shows up as a rate error and two wheels fighting."""
        return self.hw.joints[G.JOINTS[key]].command * G.WHEEL_RADIUS - self.contact_ground_speed(key)

    def wheel_effort(self, key):
        return float(self.model.joints[G.JOINTS[key]].effort)   # the actuator's, of the last step

    def contact_ground_speed(self, key):
        """Ground speed, along the wheel's rolling direction, of the point where it touches the
        ground (the lowest point of the tread's rim, moving with the chassis). The joint axis is
        the wheel's local +z (left wheels) or -z (right wheels); rolling forward is axis x up."""
        link = self.model.links["polaris_ranger_ev__%s_wheel" % key]
        c, q = link.pose
        sign = 1.0 if key.endswith("left") else -1.0
        ax = rotate(q, (0.0, 0.0, sign))
        down = (-ax[2] * ax[0], -ax[2] * ax[1], -1.0 + ax[2] * ax[2])     # -z without its axis part
        n = math.sqrt(sum(v * v for v in down))
        down = tuple(v / n for v in down)
        edges = [tuple(c[i] + G.WHEEL_RADIUS * down[i] + e * G.WHEEL_WIDTH / 2.0 * ax[i] for i in range(3))
                 for e in (1.0, -1.0)]
        p = min(edges, key=lambda e: e[2])
        (bp, _), (bv, bw) = self.model.pose, self.model.twist
        r = tuple(p[i] - bp[i] for i in range(3))
        wr = _cross(bw, r)
        vp = tuple(bv[i] + wr[i] for i in range(3))
        f = (ax[1], -ax[0], 0.0)            # ax x (0, 0, 1)
        nf = math.hypot(f[0], f[1]) or 1.0
        return (vp[0] * f[0] + vp[1] * f[1]) / nf


def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
