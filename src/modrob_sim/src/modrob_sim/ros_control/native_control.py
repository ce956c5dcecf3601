"""One gazebo_ros_control plugin's update (read -> controllers -> write) in the C loop's batches
(modrob_sim.physics.native_batch), for the steps at which nothing of it needs Python.

Natively updated: effort joints driven by effort_controllers/JointPositionController (the PID of
pid.py, the error of JointResource.position_error), by effort_controllers/JointEffortController
or by effort_controllers/JointTrajectoryController (the desired state from the piece of its
trajectory that holds for the batch's steps, trajectory.Piece, evaluated in C as
trajectory.Segment samples it; its PIDs with the velocity error and velocity_ff), and effort
joints without a running controller (their last command). A JointPositionController needs a
Python update only when its ``state`` message is due and subscribed; a trajectory controller
when a goal or command waits in its adapter, while its goal has path tolerances and from its
trajectory's end until the goal's outcome. The joint_state_controller's update at its publish
times, and a trajectory controller's state sample and action feedback, need only what that
step read: the C loop makes the step and ends the batch there, and :meth:`NativeControl.finish`
takes the samples and publishes them from the step's read, as the Python update would have.
Anything else (position or velocity joints, other controller types, a ``controlPeriod``) keeps
every step in Python.

Python stays the reference: before a batch the controllers' state (PID gains and errors, commands,
the applied efforts) goes into the batch's joints; after it, what the updates did comes back
(controller update counts, PID state, joint commands, the hardware's last read), so the next
Python update carries on exactly. Commands arriving from ROS during a batch reach the C loop at
once: the controllers' command buffers write through to the batch joint.
"""
import math

from modrob_sim.physics import native_batch
from modrob_sim.ros_control.controllers.effort_joint_position import EffortJointPositionController
from modrob_sim.ros_control.controllers.effort_joint_position import STATE_DECIMATION
from modrob_sim.ros_control.controllers.forward_command import EffortJointEffortController
from modrob_sim.ros_control.controllers.joint_state import JointStateController
from modrob_sim.ros_control.controllers.joint_trajectory import EffortJointTrajectoryController
from modrob_sim.ros_control.trajectory import HOLD
from modrob_sim.ros_control.transmissions import EFFORT

INF = float("inf")


def _load_pid(e, pid):
    """A PID's gains and state into its C entry ``e`` before a batch."""
    g = pid.gains
    e.p, e.i, e.d, e.i_max, e.i_min = g.p, g.i, g.d, g.i_max, g.i_min
    e.antiwindup = int(g.antiwindup)
    e.p_error_last, e.p_error, e.i_error = pid.p_error_last, pid.p_error, pid.i_error
    e.d_error, e.cmd = pid.d_error, pid.cmd
    e.p_term, e.i_term, e.d_term = pid.terms


def _store_pid(pid, e):
    """The PID's state back from its C entry ``e`` after a batch."""
    pid.p_error_last, pid.p_error, pid.i_error, pid.d_error, pid.cmd = (e.p_error_last, e.p_error,
                                                                        e.i_error, e.d_error, e.cmd)
    pid.terms = (e.p_term, e.i_term, e.d_term)


class NativeControl(object):
    def __init__(self, plugin):
        self.plugin = plugin
        self.count = 0
        self.sim_joints = []
        self._arr = None
        self._off = 0
        self._pid = []          # (index, controller, state adapter or None)
        self._forward = []      # (index, controller)
        self._idle = []         # (index, JointResource): no running controller
        self._traj = []         # (controller, adapter, [indices]): effort trajectory controllers
        self._pieces = {}       # controller name -> (trajectory, Piece, time) last put into the batch
        self._res = []          # (index, JointResource), every joint
        self._jsc = []
        self._sampled = []
        self._mirrored = []

    def key(self):
        """What the batch layout depends on; None when this plugin needs Python at every step."""
        p = self.plugin
        if p.config.control_period is not None:
            return None
        mgr = p.manager
        return (id(self), mgr.generation, len(p.adapters))

    def layout(self):
        """(number of joints, physics Joints) for the batch, or None when not possible."""
        p = self.plugin
        hw, mgr = p.hw, p.manager
        for res in hw.joints.values():
            if res.method != EFFORT:
                return None
        for a in p.adapters.values():
            if not getattr(a, "NATIVE", False):
                return None
        for c in mgr.controllers.values():
            if c.state == "running" and type(c) not in (JointStateController, EffortJointPositionController,
                                                        EffortJointEffortController,
                                                        EffortJointTrajectoryController):
                return None
        return len(hw.order), [hw.joints[n].sim for n in hw.order]

    def attach(self, arr, offset):
        """Fill entries offset.. of the batch joint array ``arr`` (after layout())."""
        self.detach()
        p = self.plugin
        hw, mgr = p.hw, p.manager
        owner = {}
        jsc = []
        traj = {}
        for c in mgr.controllers.values():
            if c.state != "running":
                continue
            if isinstance(c, JointStateController):
                jsc.append(c)
            elif isinstance(c, EffortJointTrajectoryController):
                traj[c.name] = (c, p.adapters.get(c.name), [])
                for k, j in enumerate(c.joints):
                    owner[j.name] = (c, k)
            else:
                owner[c.joint.name] = c
        self._arr, self._off = arr, offset
        # the controllers whose samples finish() hands to their adapters, in the adapters' order
        order = {name: k for k, name in enumerate(p.adapters)}
        self._sampled = sorted([(c, p.adapters.get(c.name)) for c in jsc] +
                               [(c, a) for c, a, _j in traj.values()],
                               key=lambda ca: order.get(ca[0].name, len(order)))
        self._jsc = [ca for ca in self._sampled if isinstance(ca[0], JointStateController)]
        self._pid, self._forward, self._idle, self._res = [], [], [], []
        self._pieces = {}
        for k, name in enumerate(hw.order):
            idx = offset + k
            res = hw.joints[name]
            e = arr[idx]
            e.joint, e.slider, e.joint_limit = native_batch.joint_fields(res.sim)
            e.has_hw_limit = 0 if res.effort_limit is None else 1
            e.hw_limit = res.effort_limit if res.effort_limit is not None else 0.0
            if res.type == "continuous":
                e.err_kind = 2
            elif res.type == "revolute" and res.has_position_limits:
                e.err_kind, e.lower, e.upper = 1, res.lower, res.upper
            else:
                e.err_kind = 0
            self._res.append((idx, res))
            c = owner.get(name)
            if isinstance(c, tuple):            # a trajectory controller's joint
                c, k = c
                e.mode = 2
                e.err_kind = 2 if res.type == "continuous" else 0
                e.ff = c.velocity_ff[k]
                traj[c.name][2].append((idx, k))
                continue
            if isinstance(c, EffortJointPositionController):
                e.mode = 1
                adapter = p.adapters.get(c.name)
                self._pid.append((idx, c, getattr(adapter, "state_pub", None)))
            else:
                e.mode = 0
                if c is None:
                    self._idle.append((idx, res))
                else:
                    self._forward.append((idx, c))
            if c is not None:
                c.command.mirror(e)
                self._mirrored.append(c)
        self._traj = list(traj.values())
        self.count = len(hw.order)

    def detach(self):
        for c in self._mirrored:
            c.command.mirror(None)
        self._mirrored = []

    def plan(self, t, dt):
        """Before a batch whose first step starts at ``t`` (steps of ``dt``): the controllers' state
        into the batch joints. Returns (time before which the batch must stop, most steps, time
        from which a step ends the batch once made), or None when the next update needs Python."""
        arr = self._arr
        steps = 1 << 30
        due = INF
        stop = INF
        for c, adapter, joints in self._traj:
            d = self._plan_trajectory(c, adapter, joints, t)
            if d is None:
                return None
            due, stop = min(due, d[0]), min(stop, d[1])
        jsc_due = []
        for c, adapter in self._jsc:
            due_at = c.next_due()
            if due_at is None:
                return None
            if t >= due_at:
                jsc_due.append((c, adapter))
            else:
                stop = min(stop, due_at)
        for idx, c, pub in self._pid:
            if pub is not None and pub.get_num_connections() > 0:
                k = (STATE_DECIMATION - c._count % STATE_DECIMATION) % STATE_DECIMATION
                if k == 0:
                    return None
                steps = min(steps, k)
            _load_pid(arr[idx], c.pid)
        # a trajectory controller's sample due at the first step as well (stop <= t): that step
        # ends the batch and finish() hands every sample over in the adapters' order
        if jsc_due and stop > t:
            # due at the batch's first step only: that step's read is the joints' state now, so
            # the sample is taken and published here, as the Python step would do it before that
            # step's physics (not a batch of that one step, the sample, then the rest)
            self.plugin.hw.read()
            for c, adapter in jsc_due:
                c.update(t, dt)
                if adapter is not None:
                    adapter.after_update(t)
                stop = min(stop, c.next_due())
        for idx, res in self._idle:
            cmd = res.command
            arr[idx].command = cmd if math.isfinite(cmd) else 0.0
        for idx, res in self._res:
            arr[idx].applied = res.sim.effort
        return due, steps, stop

    def finish(self, steps, t_last, dt):
        """After a batch of ``steps`` steps of ``dt`` whose last started at ``t_last``."""
        arr = self._arr
        p = self.plugin
        p.manager.time = t_last
        p._last_update = t_last
        for idx, c, _pub in self._pid:
            e = arr[idx]
            _store_pid(c.pid, e)
            c._count += steps
            c.last_effort = c.joint.command = e.out
        for idx, c in self._forward:
            c.joint.command = arr[idx].out
        for c, _adapter, joints in self._traj:
            for idx, k in joints:
                e = arr[idx]
                _store_pid(c.pids[k], e)
                c.joints[k].command = e.out
        for idx, res in self._res:
            e = arr[idx]
            res.position, res.velocity, res.effort = e.position, e.velocity, e.effort
        # what was due at the last step's start, from that step's read (res above), then the
        # adapters publish, in their order, as in GazeboRosControlPlugin.before_step: a
        # joint_state_controller's update, the trajectory controllers' state samples and feedback
        for c, adapter in self._sampled:
            if isinstance(c, JointStateController):
                if t_last < c.next_due():
                    continue
                c.update(t_last, dt)
            else:
                due = c.samples_due(t_last)
                c.native_update_done(t_last)
                if not due:
                    continue
            if adapter is not None:
                adapter.after_update(t_last)

    def _plan_trajectory(self, c, adapter, joints, t):
        """An effort JointTrajectoryController's state into its batch joints for steps from ``t``
        on; returns (the time before which the batch must stop: its goal's check at the
        trajectory's end, the time from which a step ends the batch once made: its state sample
        or action feedback is due, as JointTrajectoryControllerBase.update decides it), or None
        when the update at ``t`` needs Python: a goal or command waiting in the adapter, a goal
        with path tolerances (checked at every update) or past its trajectory's end."""
        traj, goal = c.trajectory, c.goal
        if traj is None or c._next_state is None or (adapter is not None and adapter.inbox):
            return None
        due = INF
        stop = c._next_state - 1e-9
        if goal is not None:
            if c._next_feedback is None or t >= goal.end_time:
                return None
            for tol in goal.path:
                if tol.position > 0.0 or tol.velocity > 0.0:
                    return None
            due = goal.end_time
            if not c._feedback_with_state:     # else the feedback comes with a state sample
                stop = min(stop, c._next_feedback - 1e-9)
        arr = self._arr
        last = self._pieces.get(c.name)
        if (last is None or last[0] is not traj or t < last[2]
                or not (t < last[1].abs_until and t - last[1].base < last[1].rel_until)):
            piece = traj.piece(t)
            self._pieces[c.name] = (traj, piece, t)
            seg, off = piece.segment, piece.offsets
            for idx, k in joints:
                e = arr[idx]
                e.traj_kind = piece.kind
                if piece.kind == HOLD:
                    e.ncoef = 1
                    e.coef[0] = piece.positions[k]
                else:
                    coeffs = seg.coeffs[k]
                    e.ncoef = len(coeffs)
                    for m, v in enumerate(coeffs):
                        e.coef[m] = v
                    e.seg_t0, e.seg_t1 = seg.t0, seg.t1
                e.rel_base = piece.base
                e.has_offset = 0 if off is None else 1
                e.offset = 0.0 if off is None else off[k]
                e.abs_until, e.rel_until = piece.abs_until, piece.rel_until
        for idx, k in joints:
            _load_pid(arr[idx], c.pids[k])
        return due, stop
