"""The World's actuators (physics.actuators, docs/design/sim_core_api.md "Actuators"): one interface
over the two backends. The pure-Python backend (actuators.step_python, the Pid class) and the
native one (mr_apply_actuators in C) give the same steps bit for bit for every kind (held effort,
PID to a position with each error rule, PID to a velocity, PID along absolute, relative and held
trajectory segments with feed-forward, a wheel motor with an acceleration ramp), with gains and
set-points changed mid-run, efforts given with set_effort added before the joint's clamp, and a
continuous joint counting turns; the same for an output that drives the joint's ODE motor's velocity
(OUT_VELOCITY: gazebo_ros_control's velocity joint) instead of its effort; a FOLLOW_PID's target
velocity, bias and set-point relative to its own joint; actuators that follow each other step alike
in either order; a SEGMENT_PID actuator's tracking error is what its step computes, alike on both
backends, and a band on it ends a native stretch exactly at the step whose start leaves it; pieces
queued behind a SEGMENT_PID actuator's own take over as an owner placing them one at a time would
place them, and a stretch ends only where the last ends; bad requests are refused with messages
that say what to do."""
import math
import os

import pytest

from modrob_sim.errors import InputError
from modrob_sim.physics import World, actuators as A
from modrob_sim.physics import native as native_mod

FIX = os.path.join(os.path.dirname(__file__), "..", "fixtures", "control")
needs_c = pytest.mark.skipif(native_mod.LIB is None, reason="the C loop is not built")


def arm(native):
    with open(os.path.join(FIX, "arm_3dof.urdf")) as f:
        xml = f.read().replace('name="yaw" type="revolute"', 'name="yaw" type="continuous"')
    w = World(time_step=0.001, seed=3, native=native)
    m = w.add_urdf("arm", xml)
    return w, m


def sample(k, w, joints, links=()):
    """What a scenario compares between the backends after step ``k``: the joints' state, every
    actuator's PID state and last step, the first joint's turn count (and the links' poses)."""
    out = (k, [(j.position, j.velocity, j.effort) for j in joints],
           [(a.pid_state(), a.last) for a in w.actuators], joints[0].turn_state)
    links = [(ln.pose, ln.twist) for ln in links]
    return out + (links,) if links else out


def scenario(native):
    """Every kind on the three joints in turn; returns what was seen at every 25th step."""
    w, m = arm(native)
    yaw, shoulder, elbow = (m.joints[n] for n in ("yaw", "shoulder", "elbow"))
    g = A.PidGains(60.0, 20.0, 3.0, 4.0, -4.0, True)
    a_yaw = w.add_actuator(yaw, A.POSITION_PID, gains=g, effort_limit=30.0, error=A.SHORTEST)
    a_sh = w.add_actuator(shoulder, A.SEGMENT_PID, gains=A.PidGains(150.0, 10.0, 8.0, 2.0, -2.0))
    a_el = w.add_actuator(elbow, A.EFFORT, effort_limit=3.0)
    a_yaw.command = 7.0                             # continuous: the short way, across +-pi
    a_sh.set_segment([0.0, 0.4, 0.0, -0.05], 0.0, 2.0, until=0.6)
    a_sh.feedforward = 0.3
    a_el.command = 8.0                              # beyond the hardware clamp
    seen = []
    for k in range(1600):
        t = w.time
        if k == 300:
            a_yaw.gains = A.PidGains(80.0, 0.0, 4.0)
            a_el.kind = A.VELOCITY_PID
            a_el.gains = A.PidGains(2.0, 1.0, 0.0, 1.0, -1.0)
            a_el.command = -1.5
        if k == 600:
            a_sh.set_segment([0.1, -0.3, 0.2], 0.0, 0.5, base=t, offset=0.25, rel_until=0.4)
            a_yaw.kind = A.POSITION_PID
            a_yaw.error = A.PLAIN
            a_yaw.command = 2.0
        if k == 900:
            a_sh.hold(-0.4)
            a_el.kind = A.MOTOR
            a_el.max_force = 4.0
            a_el.acceleration = 3.0
            a_el.command = 2.0
        if 1000 <= k < 1010:
            yaw.set_effort(5.0)                     # added to the actuator's, then the joint's clamp
        if k == 1200:
            w.remove_actuator(a_el)
        w.step(1)
        if k % 25 == 0 or 1000 <= k < 1012:
            seen.append(sample(k, w, (yaw, shoulder, elbow)))
    return w, seen


def assert_backends_alike(scenario, samples):
    """``scenario(native)`` -> (world, samples seen): both backends see the same samples, more than
    ``samples`` of them, and end in the same state, bit for bit."""
    wp, pure = scenario(False)
    wn, nat = scenario(True)
    assert not wp.native and wn.native
    assert len(pure) == len(nat) > samples
    for a, b in zip(pure, nat):
        assert a == b, "step %d differs" % a[0]
    assert wp.state_digest() == wn.state_digest()


@needs_c
def test_the_two_backends_step_every_kind_alike_bit_for_bit():
    assert_backends_alike(scenario, 60)


def velocity_scenario(native):
    """PIDs and a trajectory segment whose outputs are the joints' motor velocities, switched to
    effort and back, limits and gains changed mid-run; what was seen at every 20th step."""
    w, m = arm(native)
    yaw, shoulder, elbow = (m.joints[n] for n in ("yaw", "shoulder", "elbow"))
    a_yaw = w.add_actuator(yaw, A.POSITION_PID, gains=A.PidGains(5.0, 1.0, 0.05, 0.5, -0.5), error=A.SHORTEST,
                           output=A.OUT_VELOCITY)
    a_yaw.velocity_limit = 1.5
    a_yaw.max_force = 40.0
    a_yaw.command = 7.0
    a_sh = w.add_actuator(shoulder, A.SEGMENT_PID, gains=A.PidGains(8.0, 0.0, 0.1), output=A.OUT_VELOCITY)
    a_sh.max_force = 50.0
    a_sh.set_segment([0.0, 0.4, 0.0, -0.05], 0.0, 2.0, until=0.6)
    a_sh.feedforward = 1.0
    a_el = w.add_actuator(elbow, A.VELOCITY_PID, gains=A.PidGains(3.0), output=A.OUT_VELOCITY)
    a_el.max_force = 20.0
    a_el.command = 0.8                              # the PID's output is the motor's velocity
    seen = []
    for k in range(1200):
        t = w.time
        if k == 300:
            a_yaw.velocity_limit = None
            a_yaw.gains = A.PidGains(4.0, 0.0, 0.0)
            a_el.output = A.OUT_EFFORT              # now an effort PID on the velocity error
            a_el.effort_limit = 5.0
        if k == 600:
            a_sh.set_segment([0.1, -0.3, 0.2], 0.0, 0.5, base=t, offset=0.25, rel_until=0.4)
            a_el.output = A.OUT_VELOCITY
        if 700 <= k < 705:
            shoulder.set_effort(4.0)                # an effort beside the motor
        if k == 900:
            w.remove_actuator(a_el)
        w.step(1)
        if k % 20 == 0 or 700 <= k < 706:
            seen.append(sample(k, w, (yaw, shoulder, elbow)))
    return w, seen


@needs_c
def test_velocity_outputs_step_alike_on_both_backends_bit_for_bit():
    assert_backends_alike(velocity_scenario, 60)


@pytest.mark.parametrize("native", [False, pytest.param(True, marks=needs_c)])
def test_a_velocity_output_drives_the_motor(native):
    w, m = arm(native)
    yaw = m.joints["yaw"]
    a = w.add_actuator(yaw, A.POSITION_PID, gains=A.PidGains(10.0), output=A.OUT_VELOCITY)
    a.velocity_limit = 0.5
    a.max_force = 50.0
    a.command = 1.0
    w.step(200)
    # far from the target the PID asks 10 rad/s; the motor runs at the clamp
    assert yaw.velocity == pytest.approx(0.5, abs=1e-3)
    assert a.last.output == pytest.approx(10.0 * (1.0 - a.last.position))
    assert a.last.applied == 0.0 == yaw.effort       # no effort: the motor moves the joint
    w.step(3000)
    assert yaw.position == pytest.approx(1.0, abs=1e-3) and abs(yaw.velocity) < 1e-2
    # while it runs, the motor holds its velocity against an effort (max_force 50 N m) ...
    a.command = -2.0
    w.step(300)
    assert yaw.velocity == pytest.approx(-0.5, abs=1e-3)
    for _ in range(100):
        yaw.set_effort(5.0)
        w.step(1)
    assert yaw.velocity == pytest.approx(-0.5, abs=0.02)
    # ... and removed, it gives the joint its own (frictionless) motor back: the effort turns it
    w.remove_actuator(a)
    for _ in range(100):
        yaw.set_effort(5.0)
        w.step(1)
    assert yaw.velocity > 0.0


def position_scenario(native):
    """Kinematic set-points: a held command on the continuous yaw (rate-limited, the short way
    across +-pi), a trajectory segment on the shoulder, a command beyond the elbow's limit, then
    the elbow back to an effort PID and removed; what was seen at every 20th step."""
    w, m = arm(native)
    yaw, shoulder, elbow = (m.joints[n] for n in ("yaw", "shoulder", "elbow"))
    a_yaw = w.add_actuator(yaw, A.EFFORT, error=A.SHORTEST, output=A.OUT_POSITION)
    a_yaw.velocity_limit = 2.0
    a_yaw.command = 3.0
    a_sh = w.add_actuator(shoulder, A.SEGMENT_PID, output=A.OUT_POSITION)
    a_sh.set_segment([0.0, 0.8, 0.0, -0.2], 0.0, 1.0, until=0.5)
    a_el = w.add_actuator(elbow, A.POSITION_PID, gains=A.PidGains(50.0, 0.0, 2.0), error=A.CLAMPED,
                          output=A.OUT_POSITION)
    a_el.command = 4.0                              # beyond the upper limit 2.5: clamped
    seen = []
    for k in range(1000):
        t = w.time
        if k == 300:
            a_yaw.command = -2.5                    # the short way: on through +pi
        if k == 500:
            a_sh.set_segment([0.1, -0.3, 0.2], 0.0, 0.5, base=t, offset=0.25, rel_until=0.4)
        if 550 <= k < 555:
            shoulder.set_effort(4.0)
        if k == 600:
            a_el.output = A.OUT_EFFORT              # the PID drives the elbow's effort from here
            a_el.command = 1.0
        if k == 800:
            w.remove_actuator(a_yaw)
        w.step(1)
        if k % 20 == 0 or 550 <= k < 556:
            seen.append(sample(k, w, (yaw, shoulder, elbow), m.links.values()))
    return w, seen


@needs_c
def test_position_outputs_step_alike_on_both_backends_bit_for_bit():
    assert_backends_alike(position_scenario, 50)


@pytest.mark.parametrize("native", [False, pytest.param(True, marks=needs_c)])
def test_a_position_output_sets_the_joint(native):
    w, m = arm(native)
    yaw, shoulder, elbow = (m.joints[n] for n in ("yaw", "shoulder", "elbow"))
    tip = m.links["l3"]
    a = w.add_actuator(shoulder, A.EFFORT, output=A.OUT_POSITION)
    a.velocity_limit = 1.0
    a.command = 0.6
    w.step(100)
    # 1 rad/s: 0.1 rad after 100 steps, the joint at rest relative to its parent after each set;
    # gravity moves it within the step that follows (about 33 rad/s^2 for 1 ms here)
    assert shoulder.position == pytest.approx(0.1, abs=1e-4) and abs(shoulder.velocity) < 0.05
    assert a.last.output == pytest.approx(0.1, abs=1e-9) and a.last.set_point == 0.6
    w.step(600)
    assert shoulder.position == pytest.approx(0.6, abs=1e-4)
    # the links below turned with it: the elbow (free, under gravity) hangs from where it was carried
    q_el = elbow.position
    pose_before = tip.pose
    b = w.add_actuator(elbow, A.EFFORT, output=A.OUT_POSITION)
    b.command = q_el
    w.step(50)
    assert elbow.position == pytest.approx(q_el, abs=1e-4)
    assert tip.pose[0] == pytest.approx(pose_before[0], abs=1e-3)
    # yaw turns the whole arm about the vertical
    c = w.add_actuator(yaw, A.EFFORT, output=A.OUT_POSITION)
    c.command = math.pi / 2
    w.step(1)
    x, y, _ = tip.pose[0]
    assert yaw.position == pytest.approx(math.pi / 2, abs=1e-4)
    assert abs(x) < 1e-3 and y == pytest.approx(math.hypot(*pose_before[0][:2]), abs=1e-3)
    # a non-finite command holds the last set-point
    c.command = float("nan")
    w.step(5)
    assert yaw.position == pytest.approx(math.pi / 2, abs=1e-4)


@pytest.mark.parametrize("native", [False, pytest.param(True, marks=needs_c)])
def test_what_the_actuators_do(native):
    w, m = arm(native)
    yaw, shoulder, elbow = (m.joints[n] for n in ("yaw", "shoulder", "elbow"))
    a = w.add_actuator(yaw, A.POSITION_PID, gains=A.PidGains(60.0, 0.0, 3.0), error=A.SHORTEST)
    a.command = 7.0
    e = w.add_actuator(elbow, A.EFFORT, effort_limit=3.0)
    e.command = 8.0
    w.step(2000)
    # the short way to 7 rad is 7 - 2 pi = 0.717 rad, not a turn and more
    assert abs(yaw.position - (7.0 - 2 * math.pi)) < 0.02
    assert e.last.output == 8.0 and e.applied == 3.0 == elbow.effort
    s = a.last
    assert s.set_point == 7.0 and abs(s.error) < 0.02 and s.t == pytest.approx(w.time - 0.001)
    yaw.set_effort(10.0)            # for one step, on top of the actuator's effort
    w.step(1)
    assert yaw.effort == pytest.approx(a.last.output + 10.0)
    w.step(1)
    assert yaw.effort == a.last.output
    w.remove_actuator(e)
    w.step(1)
    assert elbow.effort == 0.0 and elbow.actuator is None


def test_bad_requests_say_what_to_do():
    w, m = arm(False)
    a = w.add_actuator(m.joints["yaw"], A.EFFORT)
    with pytest.raises(InputError, match="already has an actuator.*remove it first"):
        w.add_actuator(m.joints["yaw"], A.POSITION_PID)
    with pytest.raises(InputError, match="a fixed joint cannot be driven"):
        w.add_actuator(m.joints["base_fixed"], A.EFFORT)
    with pytest.raises(InputError, match="unknown kind 99"):
        w.add_actuator(m.joints["elbow"], 99)
    with pytest.raises(InputError, match="unknown output 7.*OUT_VELOCITY"):
        w.add_actuator(m.joints["elbow"], A.EFFORT, output=7)
    with pytest.raises(ValueError, match="OUT_EFFORT, OUT_VELOCITY or OUT_POSITION"):
        a.output = 3
    with pytest.raises(ValueError, match="set-point from an EFFORT, POSITION_PID or SEGMENT_PID kind, "
                                         "not MOTOR"):
        w.add_actuator(m.joints["elbow"], A.MOTOR).output = A.OUT_POSITION
    with pytest.raises(ValueError, match="1 to 6 coefficients"):
        a.set_segment([0.0] * 7, 0.0, 1.0)
    other, om = arm(False)
    with pytest.raises(InputError, match="not in this World"):
        other.add_actuator(m.joints["elbow"], A.EFFORT)
    w.remove_model("arm")
    assert w.actuators == () and om.joints["yaw"].actuator is None


@pytest.mark.parametrize("native", [False, pytest.param(True, marks=needs_c)])
def test_a_dropped_world_with_actuators_frees_its_backend_without_the_cycle_collector(native):
    """An actuator holds its backend weakly: the backend's tables lead to the models and back to
    the joint the actuator drives, so a strong reference left the backend in a reference cycle
    that only the cycle collector freed. With the collector off, dropping the World frees it; an
    actuator kept past its World says so."""
    import gc
    import weakref
    from modrob_sim.errors import SimulationError
    gc.collect()
    gc.disable()
    try:
        w, m = arm(native)
        kept = w.add_actuator(m.joints["yaw"], A.POSITION_PID, gains=A.PidGains(60.0, 1.0, 3.0))
        w.add_actuator(m.joints["elbow"], A.SEGMENT_PID).set_segment([0.0, 0.4], 0.0, 1.0)
        kept.command = 0.5
        w.step(200)
        world, backend = weakref.ref(w), weakref.ref(w._backend)
        del w, m
        assert world() is None and backend() is None
        with pytest.raises(SimulationError, match="its World is gone.*world.add_actuator"):
            kept.gains = A.PidGains(1.0, 0.0, 0.0)
    finally:
        gc.enable()


PLANAR_BOT = """<robot name="base">
  <link name="base"><inertial><origin xyz="0.05 -0.02 0.1"/><mass value="8"/>
    <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.15" iyz="0" izz="0.2"/></inertial></link>
  <link name="flap"><inertial><origin xyz="0 0 0.1"/><mass value="1"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <joint name="hinge" type="revolute"><parent link="base"/><child link="flap"/><origin xyz="0.3 0 0.2"/>
    <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="10" velocity="2"/></joint>
</robot>"""


def planar_run(native):
    """A two-body base driven by a PLANAR_VELOCITY actuator, its command changed twice; the
    links' poses and twists every 50 steps."""
    w = World(gravity=(0.0, 0.0, 0.0), native=native)
    m = w.add_urdf("base", PLANAR_BOT, pose=((0.0, 0.0, 0.5), (0.0, 0.0, 0.38941834, 0.92106099)))
    a = w.add_model_actuator(m, A.PLANAR_VELOCITY)
    seen = []
    for k in range(900):
        if k == 0:
            a.command = (0.3, -0.1, 0.5)
        if k == 500:
            a.command = (0.0, 0.2, -1.0)
        w.step(1)
        if k % 50 == 49:
            seen.append([(ln.pose, ln.twist) for ln in m.links.values()])
    return w, m, a, seen


@needs_c
def test_the_planar_velocity_actuator_is_the_same_on_both_backends_bit_for_bit():
    assert planar_run(None)[3] == planar_run(False)[3]


@pytest.mark.parametrize("native", [None, False])
def test_the_planar_velocity_actuator_moves_the_model_in_its_heading(native):
    """Each step starts with the rigid twist of the base moving at (vx, vy) in its heading and
    turning at wz (Model.set_twist's), vertical 0: 0.5 s at (0.3, -0.1, 0.5) from a heading of
    0.8 rad goes along the arc of that twist; the flap on its hinge turns with the base."""
    w, m, a, _seen = planar_run(native)
    assert w.model_actuators == (a,)
    w2 = World(gravity=(0.0, 0.0, 0.0), native=native)
    m2 = w2.add_urdf("base", PLANAR_BOT, pose=((0.0, 0.0, 0.5), (0.0, 0.0, 0.38941834, 0.92106099)))
    a2 = w2.add_model_actuator(m2, A.PLANAR_VELOCITY)
    a2.command = (0.3, -0.1, 0.5)
    w2.step(500)
    (p, q) = m2.pose
    yaw0, yaw1 = 0.8, 0.8 + 0.5 * 0.5
    # the arc of a body-frame velocity (vx, vy) turning at wz, from yaw0 to yaw1
    x = (0.3 * (math.sin(yaw1) - math.sin(yaw0)) + (-0.1) * (math.cos(yaw1) - math.cos(yaw0))) / 0.5
    y = (-0.3 * (math.cos(yaw1) - math.cos(yaw0)) + (-0.1) * (math.sin(yaw1) - math.sin(yaw0))) / 0.5
    assert p[0] == pytest.approx(x, abs=1e-3) and p[1] == pytest.approx(y, abs=1e-3)
    assert p[2] == pytest.approx(0.5, abs=1e-6)     # the hinge's constraint drifts it by ~2e-7
    assert 2.0 * math.atan2(q[2], q[3]) == pytest.approx(yaw1, abs=1e-3)
    assert abs(m2.joints["hinge"].position) < 1e-3     # carried along (7e-5 rad of constraint drift)
    (v, wv) = m2.links["flap"].twist
    assert wv == pytest.approx((0.0, 0.0, 0.5), abs=1e-3)    # after the step: what the solver left
    a.command = (0.0, 0.0, 0.0)      # would stop it at the next step; removed, it coasts on
    w.remove_model_actuator(a)
    w.step(100)
    assert math.hypot(*m.twist[0][:2]) > 0.1 and abs(m.twist[1][2]) > 0.5


def test_model_actuator_requests_say_what_to_do():
    w, m = arm(False)
    with pytest.raises(InputError, match="canonical link 'world' is static|canonical link '.*' is static"):
        w.add_model_actuator(m, A.PLANAR_VELOCITY)
    free = w.add_urdf("base", PLANAR_BOT, pose=((2.0, 0.0, 0.5), (0.0, 0.0, 0.0, 1.0)))
    with pytest.raises(InputError, match="unknown kind 7"):
        w.add_model_actuator(free, 7)
    a = w.add_model_actuator(free, A.PLANAR_VELOCITY)
    with pytest.raises(InputError, match="already has a model actuator: remove it first"):
        w.add_model_actuator(free, A.PLANAR_VELOCITY)
    with pytest.raises(InputError, match="non-finite"):
        a.command = (float("nan"), 0.0, 0.0)
    with pytest.raises(InputError, match="beyond"):
        a.command = (0.0, 0.0, 1e7)
    other, _om = arm(False)
    with pytest.raises(InputError, match="not in this World"):
        other.add_model_actuator(free, A.PLANAR_VELOCITY)
    w.remove_model("base")
    assert w.model_actuators == ()


def follow_scenario(native):
    """A FOLLOW_PID actuator on the elbow following the yaw (a continuous joint spun through
    several turns: its turn count is in the master's position), then the shoulder; gains, the
    deadband and the master changed mid-run, an effort given with set_effort, a step without a
    master, the derivative against a target velocity with a bias effort, the elbow following
    itself (a set-point a step ahead of where it is); what was seen at every 20th step."""
    w, m = arm(native)
    yaw, shoulder, elbow = (m.joints[n] for n in ("yaw", "shoulder", "elbow"))
    a_yaw = w.add_actuator(yaw, A.VELOCITY_PID, gains=A.PidGains(20.0))
    a_yaw.command = 9.0
    a_sh = w.add_actuator(shoulder, A.POSITION_PID, gains=A.PidGains(150.0, 0.0, 8.0))
    a_sh.command = 0.3
    a_el = w.add_actuator(elbow, A.FOLLOW_PID, gains=A.PidGains(40.0, 10.0, 2.0, 2.0, -2.0), effort_limit=6.0)
    a_el.follow(yaw, 0.05, -0.2)
    seen = []
    turns = 0
    for k in range(1500):
        if k == 300:
            a_el.gains = A.PidGains(60.0, 0.0, 3.0)
            a_el.follow(yaw, 0.05, -0.2, deadband=0.02)   # inside it: no effort, the PID kept
            a_sh.command = -0.4
        if k == 600:
            a_el.follow(shoulder, -1.5, 0.1)
            a_yaw.command = -4.0
        if 700 <= k < 705:
            elbow.set_effort(2.0)                         # added before the joint's clamp
        if k == 900:
            a_el.follow(None)
        if k == 950:
            a_el.follow(shoulder, 1.0, 0.0, deadband=0.001)
        if k == 1000:
            a_el.follow(shoulder, 1.0, 0.0, velocity=0.0, bias=0.8)
        if 1050 <= k < 1100:
            a_el.follow(elbow, 1.0, 0.0004, velocity=0.4, bias=-0.2)
        if k == 1100:
            a_el.follow(shoulder, -1.0, 0.2, deadband=0.3, velocity=0.1, bias=0.3)
        if k == 1150:
            a_el.follow(shoulder, -1.0, 0.2, velocity=0.1, bias=0.3)
        if k == 1200:
            a_el.kind = A.POSITION_PID
            a_el.command = 0.5
        w.step(1)
        turns = max(turns, abs(yaw.turn_state[0]))
        if k % 20 == 0 or 700 <= k < 706 or 298 <= k < 330 or 998 <= k < 1010 or 1048 <= k < 1060:
            seen.append(sample(k, w, (yaw, shoulder, elbow)))
    assert turns >= 1, "the master should have turned"
    return w, seen


@needs_c
def test_follow_pid_steps_alike_on_both_backends_bit_for_bit():
    assert_backends_alike(follow_scenario, 100)


@pytest.mark.parametrize("native", [False, pytest.param(True, marks=needs_c)])
def test_a_follow_pid_holds_its_joint_on_the_master(native):
    w, m = arm(native)
    yaw, shoulder, elbow = (m.joints[n] for n in ("yaw", "shoulder", "elbow"))
    w.add_actuator(yaw, A.VELOCITY_PID, gains=A.PidGains(20.0)).command = 12.0
    a = w.add_actuator(elbow, A.FOLLOW_PID, gains=A.PidGains(400.0, 0.0, 10.0), effort_limit=40.0)
    a.follow(yaw, 0.02, 0.1)
    assert a.master is yaw
    w.step(3000)
    # the yaw turned several times: its position (with the turns) is what the elbow follows
    assert yaw.position > 4 * math.pi
    s = a.last
    assert s.set_point == pytest.approx(0.02 * yaw.position + 0.1, abs=1e-3)
    assert abs(elbow.position - s.set_point) < 0.01
    assert abs(elbow.effort) <= 40.0
    # inside the deadband: no effort and the PID's state as it was
    a.follow(yaw, 0.0, elbow.position, deadband=0.5)
    state = a.pid_state()
    w.step(5)
    assert a.pid_state() == state and a.last.output == 0.0 and elbow.effort == 0.0
    a.follow(None)
    w.step(1)
    assert a.last.output == 0.0 and a.last.set_point == a.last.position


@pytest.mark.parametrize("native", [False, pytest.param(True, marks=needs_c)])
def test_a_follow_pid_with_a_target_velocity_and_a_bias(native):
    """The derivative is velocity - dq (the PID's p_error_last untouched), the bias is added to
    the output; following itself, the set-point is the offset away from where the joint is."""
    w, m = arm(native)
    shoulder, elbow = m.joints["shoulder"], m.joints["elbow"]
    w.add_actuator(shoulder, A.POSITION_PID, gains=A.PidGains(150.0, 0.0, 8.0)).command = 0.4
    a = w.add_actuator(elbow, A.FOLLOW_PID, gains=A.PidGains(30.0, 0.0, 2.0))
    a.follow(shoulder, 1.0, 0.0, velocity=0.25, bias=1.5)
    w.step(200)
    before = (elbow.position, elbow.velocity, shoulder.position)
    w.step(1)
    s = a.last
    assert (s.position, s.velocity) == before[:2] and s.set_point == 1.0 * before[2] + 0.0
    assert s.desired_velocity == 0.25 and s.error_dot == 0.25 - before[1]
    assert s.output == 30.0 * (before[2] - before[0]) + 2.0 * (0.25 - before[1]) + 1.5
    assert a.pid_state()[0] == 0.0                  # no error difference taken
    a.follow(elbow, 1.0, 0.01, velocity=-0.5)
    q = elbow.position
    w.step(1)
    assert a.last.set_point == q + 0.01 and a.last.error == (q + 0.01) - q
    a.follow(shoulder, 1.0, 0.0, deadband=10.0, bias=-2.0)      # inside the deadband: the bias only
    w.step(1)
    assert a.last.output == -2.0


@pytest.mark.parametrize("native", [False, pytest.param(True, marks=needs_c)])
def test_two_follow_pids_that_follow_each_other_step_alike_in_either_order(native):
    """Every actuator reads the step's start state before any acts: the shoulder and the elbow
    following each other (as franka_gazebo's fingers do) give the same steps whichever is first."""
    def run(order):
        w, m = arm(native)
        joints = {n: m.joints[n] for n in ("shoulder", "elbow")}
        acts = {}
        for n in order:
            acts[n] = w.add_actuator(joints[n], A.FOLLOW_PID, gains=A.PidGains(40.0, 5.0, 1.0, 1.0, -1.0))
        acts["shoulder"].follow(joints["elbow"], 1.0, 0.3, velocity=0.0, bias=0.5)
        acts["elbow"].follow(joints["shoulder"], 1.0, -0.3, velocity=0.0, bias=-0.5)
        seen = []
        for k in range(400):
            w.step(1)
            seen.append([(acts[n].last, acts[n].pid_state()) for n in ("shoulder", "elbow")])
        return w.state_digest(), seen
    a, b = run(("shoulder", "elbow")), run(("elbow", "shoulder"))
    assert a == b
    assert a[1][-1][0][0].output != a[1][0][0][0].output, "nothing moved"


def test_bad_follow_requests_say_what_to_do():
    w, m = arm(False)
    a = w.add_actuator(m.joints["elbow"], A.FOLLOW_PID, gains=A.PidGains(1.0))
    with pytest.raises(InputError, match="velocity nan and bias 0.0 must be finite"):
        a.follow(m.joints["elbow"], velocity=float("nan"))
    with pytest.raises(InputError, match="bias inf must be finite"):
        a.follow(m.joints["yaw"], bias=float("inf"))
    with pytest.raises(InputError, match="must be numbers"):
        a.follow(m.joints["yaw"], velocity="fast")
    with pytest.raises(InputError, match="joint 'base_fixed' is fixed; only a revolute"):
        a.follow(m.joints["base_fixed"])
    other, om = arm(False)
    with pytest.raises(InputError, match="the master must be a joint of model 'arm'"):
        a.follow(om.joints["yaw"])
    with pytest.raises(InputError, match="deadband -1 >= 0"):
        a.follow(m.joints["yaw"], deadband=-1)
    with pytest.raises(ValueError, match="set-point from an EFFORT, POSITION_PID or SEGMENT_PID kind, "
                                         "not FOLLOW_PID"):
        a.output = A.OUT_POSITION


def tracking_scenario(native):
    """SEGMENT_PID actuators (the continuous yaw across +-pi by the short way, the shoulder on an
    absolute, a relative segment with an offset and a hold, the elbow driving its motor's velocity):
    before every step the tracking error each reports for that step's start, and after the step
    what the step computed (its PID's error and error_dot)."""
    w, m = arm(native)
    yaw, shoulder, elbow = (m.joints[n] for n in ("yaw", "shoulder", "elbow"))
    a_yaw = w.add_actuator(yaw, A.SEGMENT_PID, gains=A.PidGains(40.0, 0.0, 2.0), error=A.SHORTEST)
    a_yaw.set_segment([2.5, 1.5], 0.0, 1.0)           # 2.5 -> 4.0 rad: through +pi
    a_sh = w.add_actuator(shoulder, A.SEGMENT_PID, gains=A.PidGains(150.0, 10.0, 8.0, 2.0, -2.0))
    a_sh.set_segment([0.0, 0.4, 0.0, -0.05], 0.0, 2.0, until=0.6)
    a_el = w.add_actuator(elbow, A.SEGMENT_PID, gains=A.PidGains(8.0, 0.0, 0.1), output=A.OUT_VELOCITY)
    a_el.max_force = 50.0
    a_el.set_segment([0.2, -0.5], 0.0, 0.8)
    acts = (a_yaw, a_sh, a_el)
    seen = []
    for k in range(1200):
        t = w.time
        if k == 600:
            a_sh.set_segment([0.1, -0.3, 0.2], 0.0, 0.5, base=t, offset=0.25, rel_until=0.4)
        if k == 1000:
            a_sh.hold(-0.4)
        before = [a.tracking_error(t) for a in acts]
        w.step(1)
        after = [(a.last.error, a.last.error_dot) for a in acts]
        assert before == after, "step %d: the tracking errors differ from what the step computed" % k
        seen.append((k, before))
    return w, seen


@needs_c
def test_the_tracking_error_is_what_the_step_computes_alike_on_both_backends_bit_for_bit():
    assert_backends_alike(tracking_scenario, 1000)


SHOULDER_PIECES = [A.segment_piece([0.0, 0.4, 0.0, -0.05], 0.0, 2.0, until=0.3),
                   A.segment_piece([0.1, -0.3, 0.2], 0.0, 0.5, base=0.3, offset=0.25, until=0.9,
                                   rel_until=0.4),
                   A.segment_piece([0.0, 0.5], 0.7, 0.75, until=0.7),     # never holds: passed over
                   A.segment_piece([0.35, -0.4, 0.3], 0.7, 1.0, until=1.0),
                   A.hold_piece(-0.4)]
YAW_PIECES = [A.segment_piece([2.5 + 0.3 * k, 1.5], 0.2 * k, 0.2 * (k + 1), until=0.2 * (k + 1))
              for k in range(6)] + [A.hold_piece(4.3)]


def _holds(p, t):
    return t < p[7] and t - p[5] < p[8]


def queued_scenario(native, queued=True):
    """The shoulder and the continuous yaw (across +-pi) on pieces that follow each other (absolute,
    relative with an offset, one that never holds, a hold): queued at once (set_pieces) or, as an
    owner placed them before there was a queue, one at a time by a before-hook due at each one's
    end. What was seen every 10 steps: the joints, the PIDs and their last steps, the tracking
    errors for the next step."""
    w, m = arm(native)
    yaw, shoulder = m.joints["yaw"], m.joints["shoulder"]
    a_sh = w.add_actuator(shoulder, A.SEGMENT_PID, gains=A.PidGains(150.0, 10.0, 8.0, 2.0, -2.0))
    a_yaw = w.add_actuator(yaw, A.SEGMENT_PID, gains=A.PidGains(40.0, 0.0, 2.0), error=A.SHORTEST)
    a_sh.feedforward = 0.3
    plan = [(a_sh, SHOULDER_PIECES), (a_yaw, YAW_PIECES)]
    if queued:
        for a, pieces in plan:
            a.set_pieces(pieces)
    else:
        placed = {}

        def place(t, dt):
            for a, pieces in plan:
                k = next(i for i, p in enumerate(pieces) if _holds(p, t))
                if placed.get(a) != k:
                    a.set_pieces([pieces[k]])
                    placed[a] = k

        def due():
            return min(a.segment_ends() for a, _ in plan) - 0.0005
        place(w.time, w.time_step)
        w.add_step_hook(before=place, before_due=due)
    seen = []
    for k in range(130):
        w.step(10)
        seen.append((k, [(j.position, j.velocity) for j in (yaw, shoulder)],
                     [(a.pid_state(), a.last) for a in (a_sh, a_yaw)],
                     # what the next step will compute (an owner placing pieces has not yet)
                     [a.tracking_error(w.time) for a in (a_sh, a_yaw)] if queued else None))
    return w, seen


@needs_c
def test_queued_pieces_follow_each_other_as_placed_one_at_a_time_on_both_backends_bit_for_bit():
    assert_backends_alike(queued_scenario, 100)
    queued, by_hook = queued_scenario(True), queued_scenario(True, queued=False)
    assert [x[:3] for x in queued[1]] == [x[:3] for x in by_hook[1]]
    assert queued[0].state_digest() == by_hook[0].state_digest()
    # without an owner, in one native stretch to the end: the last piece is a hold
    # (the hook's owner stops at each of the 9 ends, and where segment_ends' rounded relative end
    # comes a step before the piece's own test ends it, at that step too)
    assert queued[0].native_steps == 1300 and by_hook[0].native_steps <= 1300 - 9


@pytest.mark.parametrize("native", [False, pytest.param(True, marks=needs_c)])
def test_a_stretch_ends_where_the_last_queued_piece_does(native):
    """Pieces ending at 0.25 s: the World stops for Python there (its before-hook runs at the
    first step the pieces do not hold for); a new kind or set_segment leaves nothing queued."""
    w, m = arm(native)
    a = w.add_actuator(m.joints["yaw"], A.SEGMENT_PID, gains=A.PidGains(40.0, 0.0, 2.0))
    a.set_pieces(YAW_PIECES[:1] + [A.segment_piece([2.8, 1.5], 0.2, 0.25, until=0.25)])
    assert a.segment_ends() == 0.25
    ran = []
    w.add_step_hook(before=lambda t, dt: ran.append(t), before_due=lambda: math.inf)
    w.step(400)
    if native:
        assert ran and abs(ran[0] - 0.25) < 1e-9 and w.native_steps >= 250, (ran[:2], w.native_steps)
    a.set_pieces(YAW_PIECES)
    a.set_segment([1.0], 0.0, 1.0)             # nothing queued now: the yaw holds 1.0 past 1.2 s
    w.step(1200)
    assert abs(a.last.set_point - 1.0) < 1e-12
    a.set_pieces(YAW_PIECES)
    a.kind = A.POSITION_PID
    a.kind = A.SEGMENT_PID
    assert a.segment_ends() == math.inf
    with pytest.raises(ValueError, match="at least one piece"):
        a.set_pieces([])
    with pytest.raises(ValueError, match="at most 33 pieces at once"):
        a.set_pieces([A.hold_piece(0.0)] * 34)
    with pytest.raises(ValueError, match="1 to 6 coefficients"):
        A.segment_piece([0.0] * 7, 0.0, 1.0)


def banded(native, band):
    """The shoulder on a SEGMENT_PID too soft for its segment (its error grows to 0.32 rad, its
    velocity error to 1.3 rad/s) with ``band`` (position, velocity) watched from the start; a
    before-hook that is never due records the times at which it runs."""
    w, m = arm(native)
    a = w.add_actuator(m.joints["shoulder"], A.SEGMENT_PID, gains=A.PidGains(20.0, 0.0, 1.0))
    a.set_segment([0.0, 0.0, 3.6, -2.4], 0.0, 1.0)     # from rest to 1.2 rad in 1 s
    ran = []
    w.add_step_hook(before=lambda t, dt: ran.append(t), before_due=lambda: math.inf)
    a.watch_band(*band)
    return w, a, ran


@needs_c
@pytest.mark.parametrize("band", [(0.05, 0.0), (0.0, 1.2), (0.25, 1.4)])
def test_a_band_ends_the_native_stretch_at_the_step_whose_start_leaves_it(band):
    """Stepped one step at a time, the first step whose start state has a tracking error beyond
    the band; stepped in native stretches, the World stops for its hooks exactly there, and once
    the band is gone it steps on natively."""
    ref, a_ref, _ = banded(True, band)
    first = None
    for _ in range(1000):
        e, edot = a_ref.tracking_error(ref.time)
        if (band[0] > 0.0 and abs(e) > band[0]) or (band[1] > 0.0 and abs(edot) > band[1]):
            first = ref.time
            break
        ref.step(1)
    assert first is not None and first > 0.02, "the band was never (or at once) left"
    w, a, ran = banded(True, band)
    w.step(1000)
    assert ran and ran[0] == first, (ran[:3], first)
    assert w.native_steps >= round(first / 0.001), "the steps before it were not native"
    # the hook would stop it at every step while the error stays out of the band: an owner whose
    # update runs there takes the band away (or aborts), and the stretches go on
    w2, a2, ran2 = banded(True, band)

    def owner(t, dt):
        if a2.band is not None and t >= first:
            a2.unwatch_band()
    w2.add_step_hook(before=owner, before_due=lambda: math.inf)
    w2.step(1000)
    assert ran2 == [first] and a2.band is None
    assert w2.native_steps == 999 and w2.state_digest() == w.state_digest()


@pytest.mark.parametrize("native", [False, pytest.param(True, marks=needs_c)])
def test_band_requests_say_what_to_do(native):
    w, m = arm(native)
    a = w.add_actuator(m.joints["shoulder"], A.SEGMENT_PID, gains=A.PidGains(20.0))
    assert a.band is None
    a.watch_band(0.1, 0.5)
    assert a.band == (0.1, 0.5)
    a.watch_band(0.0, 0.0)                          # nothing to check: no band
    assert a.band is None
    for bad in ((-0.1, 0.0), (0.1, float("nan")), (float("inf"), 0.0)):
        with pytest.raises(InputError, match="finite and >= 0"):
            a.watch_band(*bad)
    with pytest.raises(InputError, match="must be numbers"):
        a.watch_band("wide", 0.0)
    a.watch_band(0.1)
    a.kind = A.POSITION_PID                         # another owner's kind: the band ends
    assert a.band is None
    with pytest.raises(ValueError, match="a band watches a SEGMENT_PID actuator's tracking error; "
                                         "this one is POSITION_PID"):
        a.watch_band(0.1)
    with pytest.raises(ValueError, match="only a SEGMENT_PID actuator has a tracking error"):
        a.tracking_error(w.time)
