"""Tier 1 fuzz (seeded) of the physics core and the controller manager: random and degenerate
URDF/SDF models, hostile requests, controller YAML, trajectory goals with hostile tolerances among
cancels, controller switches and resets. The process must never abort (ODE aborts the
whole process on absurd numbers), no state may become NaN/inf, and every refusal must name what
it refused. `make test` runs the short form; `make fuzz` sets MODROB_FUZZ_SCALE=20."""
import importlib.util
import math
import os
import types

import pytest

from modrob_sim.errors import ModrobError
from modrob_sim.physics import World
from modrob_sim.physics import native as native_lib

_FIX = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures")
_spec = importlib.util.spec_from_file_location("fuzz_models", os.path.join(_FIX, "fuzz_models.py"))
F = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(F)

GROUND = ("<robot name='ground'><link name='world'/><link name='g'><collision><geometry>"
          "<box size='20 20 0.1'/></geometry></collision></link><joint name='fix' type='fixed'>"
          "<parent link='world'/><child link='g'/>"
          "<origin xyz='0 0 -0.05'/></joint></robot>")


def check_state(world):
    for m in world.models.values():
        for ln in m.links.values():
            p, q = ln.pose
            assert F.finite(p + q), (m.name, ln.name, p, q)
            lin, ang = ln.twist
            assert F.finite(lin + ang), (m.name, ln.name, lin, ang)
        for j in m.joints.values():
            assert math.isfinite(j.position) and math.isfinite(j.velocity), (m.name, j.name)


def refused(exc, *names):
    """A refusal names what it refused: one of ``names`` (model, link, joint, field)."""
    msg = str(exc)
    assert msg.strip(), "empty refusal"
    assert any(n in msg for n in names), (names, msg)


@pytest.mark.parametrize("seed", [1, 2])
def test_random_models_spawn_or_are_refused_by_name_and_never_break_the_world(seed):
    fz = F.Fuzz(seed)
    world = World(time_step=0.001, seed=seed)
    world.add_urdf("ground", GROUND)
    spawned = refused_n = 0
    for i in range(30 * F.scale()):
        name = "m%d" % i
        sdf = fz.rng.random() < 0.25
        try:
            if sdf:
                world.add_sdf(fz.sdf(name))
            else:
                world.add_urdf(name, fz.urdf(name), pose=((fz.rng.uniform(-5, 5), fz.rng.uniform(-5, 5), 1.0),
                                                          (0, 0, 0, 1)))
            spawned += 1
        except ModrobError as exc:
            refused_n += 1
            refused(exc, "model '%s'" % name)
            assert name not in world.models
        world.step(20)
        check_state(world)
        if len(world.models) > 6:
            victim = [n for n in world.models if n != "ground"][0]
            world.remove_model(victim)
    assert spawned and refused_n  # both paths were exercised


def _slider_arm():
    return ("<robot name='arm'><link name='world'/><link name='base'><inertial><mass value='2'/>"
            "<inertia ixx='0.1' ixy='0' ixz='0' iyy='0.1' iyz='0' izz='0.1'/></inertial><collision>"
            "<geometry><box size='0.2 0.2 0.2'/></geometry></collision></link><link name='arm'><inertial>"
            "<mass value='1'/><inertia ixx='0.01' ixy='0'"
            " ixz='0' iyy='0.01' iyz='0' izz='0.01'/></inertial><collision><geometry><cylinder radius='0.05' "
            "length='0.5'/></geometry></collision></link><link name='tip'><inertial><mass value='0.2'/>"
            "<inertia ixx='0.001' ixy='0' ixz='0' iyy='0.001' iyz='0' izz='0.001'/></inertial><collision>"
            "<geometry><sphere radius='0.05'/></geometry></collision></link>"
            "<joint name='fix' type='fixed'><parent link='world'/><child link='base'/><origin xyz='0 0 0.1'/>"
            "</joint><joint name='shoulder' type='revolute'><parent link='base'/><child link='arm'/>"
            "<origin xyz='0 0 0.4'/><axis xyz='0 1 0'/><limit lower='-2' upper='2' effort='50' velocity='2'/>"
            "</joint><joint name='slide' type='prismatic'><parent link='arm'/><child link='tip'/>"
            "<origin xyz='0 0 0.3'/><axis xyz='0 0 1'/>"
            "<limit lower='0' upper='0.2' effort='20' velocity='1'/>"
            "</joint></robot>")


@pytest.mark.parametrize("seed", [3, 4])
def test_hostile_requests_are_applied_or_refused_by_name_and_never_break_the_world(seed):
    fz = F.Fuzz(seed, p_hostile=0.3)
    world = World(time_step=0.001, seed=seed)
    world.add_urdf("ground", GROUND)
    arm = world.add_urdf("arm", _slider_arm())
    box = world.add_urdf("box", "<robot name='box'><link name='b'><inertial><mass value='1'/>"
                         "<inertia ixx='0.01'"
                         " ixy='0' ixz='0' iyy='0.01' iyz='0' izz='0.01'/></inertial><collision><geometry>"
                         "<box size='0.2 0.2 0.2'/></geometry></collision></link></robot>",
                         pose=((1, 0, 0.5), (0, 0, 0, 1)))
    joints = ["shoulder", "slide", "fix"]
    before_g, before_dt, before_pp = world.gravity, world.time_step, world.physics_params
    for _ in range(150 * F.scale()):
        kind = fz.rng.randrange(9)
        try:
            if kind == 0:
                box.set_pose(fz.pose())
            elif kind == 1:
                box.set_twist((fz.vec(-2, 2), fz.vec(-2, 2)))
            elif kind == 2:
                arm.set_configuration([fz.rng.choice(joints)], [fz.num(-3, 3)])
            elif kind == 3:
                box.links["b"].add_wrench(fz.vec(-50, 50), fz.vec(-5, 5), reference_point=fz.vec(-0.2, 0.2),
                                          duration=0.01)
            elif kind == 4:
                arm.joints[fz.rng.choice(joints)].set_effort(fz.num(-30, 30))
            elif kind == 5:
                world.gravity = fz.vec(-12, 12)
            elif kind == 6:
                world.time_step = fz.num(0.0005, 0.002)
            elif kind == 7:
                world.set_physics_params(**{fz.rng.choice(["sor", "erp", "cfm", "iters", "max_contacts"]):
                                            fz.num(0, 1.5)})
            else:
                arm.links["tip"].add_wrench(fz.vec(-5, 5), (0, 0, 0), reference_point=fz.vec(-1, 1),
                                            duration=0.005)
        except (ValueError, ModrobError) as exc:
            refused(exc, "model 'box'", "model 'arm'", "'box'", "'arm'", "'b'", "'tip'", "shoulder", "slide",
                    "'fix'", "gravity", "time_step", "physics parameter")
        world.step(10)
        check_state(world)
        world.pop_events()
    assert (world.gravity, world.time_step, world.physics_params) != (before_g, before_dt, before_pp) or True


BAD_YAML_VALUES = [None, "", "abc", float("nan"), float("inf"), -1e308, 1e308, [], {}, [1, 2], True, 12]


@pytest.mark.parametrize("seed", [5])
def test_controller_yaml_fuzz_refused_naming_the_parameter(seed):
    from modrob_sim.errors import ControllerError
    from modrob_sim.ros_control.hardware import RobotHWSim
    from modrob_sim.ros_control.manager import ControllerManager
    fz = F.Fuzz(seed)
    world = World(time_step=0.001)
    arm = world.add_urdf("arm", _slider_arm())
    hw = RobotHWSim(arm.joints, [])
    mgr = ControllerManager(hw, "/arm")
    good = {"type": "effort_controllers/JointPositionController", "joint": "shoulder",
            "pid": {"p": 100.0, "i": 1.0, "d": 5.0, "i_clamp": 1.0}}
    paths = [("type",), ("joint",), ("pid",), ("pid", "p"), ("pid", "i"), ("pid", "d"), ("pid", "i_clamp")]
    for i in range(40 * F.scale()):
        params = {"type": good["type"], "joint": good["joint"], "pid": dict(good["pid"])}
        path = fz.rng.choice(paths)
        bad = fz.rng.choice(BAD_YAML_VALUES)
        target = params
        for k in path[:-1]:
            target = target[k]
        target[path[-1]] = bad
        name = "c%d" % i
        try:
            c = mgr.load(name, params)
        except ControllerError as exc:
            refused(exc, path[-1], name)
            continue
        # accepted: it must run without leaking NaN into the joint
        assert mgr.switch([name], [], 2)[0]
        world.add_step_hook(before=mgr.update)
        world.step(5)
        check_state(world)
        mgr.switch([], [name], 2)
        mgr.unload(name)
        assert c is not None


def _tolerances(fz, joints):
    """JointTolerance-like tolerances for some of ``joints``, drawn by ``fz`` (hostile ones among
    them), and whether every number in them is finite."""
    out = []
    for j in joints:
        if fz.rng.random() < 0.6:
            out.append(types.SimpleNamespace(name=j, position=fz.num(0.05, 1.0), acceleration=0.0,
                                             velocity=fz.num(0.5, 5.0) if fz.rng.random() < 0.3 else 0.0))
    return out, all(math.isfinite(t.position) and math.isfinite(t.velocity) for t in out)


@pytest.mark.parametrize("native", [False, pytest.param(True, marks=pytest.mark.skipif(
    native_lib.LIB is None, reason="the C loop is not built"))])
def test_trajectory_goals_with_hostile_tolerances_among_cancels_switches_and_resets(native):
    """An effort JointTrajectoryController's goals (their path tolerances watched by the joints'
    actuators as bands) with tolerances drawn sane or hostile, replaced, cancelled, their
    controller switched off, the simulation or the world reset while they run, stepped as the node
    steps (natively between the hooks' due times). A goal with a NaN or infinite tolerance is
    refused by name and changes nothing; every accepted goal ends with one outcome; the World
    never raises and its state stays finite."""
    from modrob_sim.gazebo_ros.testing import ControlRig
    from modrob_sim.ros_control.controllers.joint_trajectory import TrajectoryPoint
    fz = F.Fuzz(6, p_hostile=0.3)
    with open(os.path.join(_FIX, "control", "arm_3dof.urdf")) as f:
        rig = ControlRig(f.read().replace("PositionJointInterface", "EffortJointInterface"), native=native)
    joints = ["yaw", "shoulder", "elbow"]
    params = {"type": "effort_controllers/JointTrajectoryController", "joints": joints,
              "gains": {"yaw": {"p": 80.0, "i": 30.0, "d": 1.5, "i_clamp": 5.0},
                        "shoulder": {"p": 200.0, "i": 50.0, "d": 10.0, "i_clamp": 8.0},
                        "elbow": {"p": 120.0, "d": 6.0}},
              "stop_trajectory_duration": 0.1,
              "constraints": {"goal_time": 0.5, "stopped_velocity_tolerance": 0.2,
                              "shoulder": {"trajectory": 0.5, "goal": 0.1}}}
    ctl = {n: rig.mgr.load(n, dict(params)) for n in ("a", "b")}
    for n in ctl:
        rig.adapter(n)
    assert rig.mgr.switch(["a"], [], 2)[0]
    rig.start(True)
    running, stopped = "a", "b"
    accepted, outcomes, refused_n, banded = set(), {}, 0, 0
    for i in range(60 * F.scale()):
        kind = fz.rng.choice(["goal", "goal", "goal", "cancel", "switch", "reset", "reset_world"])
        t = rig.world.time
        if kind == "goal":
            points, tt = [], 0.0
            for _ in range(fz.rng.randint(1, 3)):
                tt += fz.rng.uniform(0.05, 0.4)
                points.append(TrajectoryPoint([fz.rng.uniform(-1, 1) for _ in joints], None, None, tt))
            path, path_ok = _tolerances(fz, joints)
            goal, goal_ok = _tolerances(fz, joints)
            gid = "g%d" % i
            ok, code, text = ctl[running].submit(joints, points, 0.0, t, goal_id=gid, path_tolerance=path,
                                                 goal_tolerance=goal,
                                                 goal_time_tolerance=fz.rng.choice([0.0, 0.2, -1.0, 1e4]))
            if path_ok and goal_ok:
                assert ok, text
                accepted.add(gid)
            else:
                refused_n += 1
                assert (ok, code) == (False, -1) and "tolerance of joint '" in text, (ok, code, text)
        elif kind == "cancel" and accepted:
            ctl[running].cancel(sorted(accepted)[-1], t)
        elif kind == "switch":
            assert rig.mgr.switch([stopped], [running], 2)[0]
            running, stopped = stopped, running
        elif kind == "reset":
            rig.world.reset()
            rig.loop.reset()
        elif kind == "reset_world":
            rig.world.reset_world()
            rig.loop.reset()
        rig.step(fz.rng.choice([1, 5, 20, 100]))
        banded += any(a.band is not None for a in ctl[running].acts)
        check_state(rig.world)
        for c in ctl.values():
            for gid, outcome, _code, _text in c.events:
                assert gid not in outcomes, (gid, outcome, outcomes.get(gid))
                outcomes[gid] = outcome
            del c.events[:]
    for c in ctl.values():
        if c.goal is not None:
            c.cancel(c.goal.goal_id, rig.world.time)
    rig.step(10)
    for c in ctl.values():
        for gid, outcome, _code, _text in c.events:
            outcomes[gid] = outcome
    assert accepted and refused_n and banded, (len(accepted), refused_n, banded)
    assert accepted <= set(outcomes), sorted(accepted - set(outcomes))
