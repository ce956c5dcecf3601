"""Tier 1: Gazebo's <gripper> grasp check welds a held object to the palm and lets it go once the
contact is gone (physics/gripper.py), counting as Gazebo 11 does: one contact per pair of
collisions per step, one gripper link is enough, one stillness ring for all candidates."""
import importlib.util
import os

import pytest

from modrob_sim.errors import ModelError
from modrob_sim.physics import SeenContact, World
from modrob_sim.physics import builder
from modrob_sim.physics import native as native_mod
from modrob_sim.physics.gripper import UPDATE_PERIOD, Gripper

_FIX = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures", "physics")
_spec = importlib.util.spec_from_file_location("physics_helpers", os.path.join(_FIX, "physics_helpers.py"))
H = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(H)


needs_c = pytest.mark.skipif(native_mod.LIB is None, reason="the C loop is not built")


def hand_and_box():
    world = World(time_step=0.001)
    hand = world.add_urdf("hand", H.fixture("gripper_hand.urdf"))
    box = world.add_urdf("box", H.robot("box", H.box_link("box", 0.1, (0.1, 0.1, 0.1))),
                         pose=((0, 0, 0.9), (0, 0, 0, 1)))
    squeeze = {"f": 20.0}

    def drive(t, dt):
        if "hand" not in world.models:
            return
        hand.joints["left"].set_effort(-squeeze["f"])
        hand.joints["right"].set_effort(squeeze["f"])
    world.add_step_hook(before=drive)
    return world, hand, box, squeeze


def seconds(world, s):
    world.step(int(round(s / world.time_step)))


def test_an_object_held_from_two_sides_is_attached_then_released_after_the_contact_goes():
    world, hand, box, squeeze = hand_and_box()
    g = hand._grippers[0]
    seconds(world, 2 * UPDATE_PERIOD)
    assert g.attached is None  # not before attach_steps updates and a still pose
    seconds(world, 14 * UPDATE_PERIOD)
    assert g.attached is not None and g.attached[0] is box and g.attached[1] == "box"
    z_held = box.pose[0][2]
    squeeze["f"] = -20.0  # open: the fingers leave, the weld holds the box
    seconds(world, 1.0)
    assert hand.joints["left"].position > 0.0 > hand.joints["right"].position  # fingers wide open
    assert abs(box.pose[0][2] - z_held) < 0.002
    seconds(world, 4 * UPDATE_PERIOD)  # more than detach_steps updates without contact
    assert g.attached is None
    seconds(world, 0.5)
    assert box.pose[0][2] < z_held - 0.5  # falls


def test_deleting_the_held_object_or_the_hand_lets_go_cleanly():
    world, hand, box, squeeze = hand_and_box()
    seconds(world, 16 * UPDATE_PERIOD)
    g = hand._grippers[0]
    assert g.attached is not None
    world.remove_model("box")
    world.step(5)
    assert g.attached is None
    world.remove_model("hand")
    world.step(5)
    assert g._hook is None


def test_a_gripper_naming_an_unknown_link_is_refused():
    xml = H.fixture("gripper_hand.urdf").replace("<palm_link>palm</palm_link>", "<palm_link>paw</palm_link>")
    world = World()
    with pytest.raises(ModelError, match="<gripper name='grasp'>: no link named 'paw'"):
        world.add_urdf("hand", xml)
    assert not world.models


def test_sdf_gripper_element_is_read():
    sdf = ("<sdf version='1.6'><model name='m'><link name='palm'/><link name='f'/>"
           "<gripper name='g'><grasp_check><attach_steps>3</attach_steps></grasp_check>"
           "<gripper_link>f</gripper_link><palm_link>palm</palm_link></gripper></model></sdf>")
    m = World().add_sdf(sdf)[0]
    d = m._grippers[0].desc
    assert (d.attach_steps, d.detach_steps, d.min_contact_count, d.gripper_links) == (3, 40, 2, ("f",))


def test_dropping_the_world_while_an_object_is_held_exits_cleanly():
    """The weld joint must go before the ODE world (it segfaulted when freed after it)."""
    import subprocess
    import sys
    code = ("import importlib.util, gc\n"
            "spec = importlib.util.spec_from_file_location('t', %r)\n"
            "t = importlib.util.module_from_spec(spec); spec.loader.exec_module(t)\n"
            "world, hand, box, sq = t.hand_and_box()\n"
            "t.seconds(world, 16 * t.UPDATE_PERIOD)\n"
            "g = hand._grippers[0]\n"
            "assert g.attached is not None\n"
            "del world, sq; gc.collect()\n"
            "del hand, box, g; gc.collect()\n"
            "print('clean')\n" % os.path.abspath(__file__))
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr[-2000:]
    assert r.stdout.strip() == "clean"
    assert "Exception ignored" not in r.stderr


# ---- due times: the check runs at its updates only, on the contacts of every step between ----------

def lifting_hand_and_box(native):
    """The fixture's hand on a vertical slider (a POSITION_PID actuator holds it, then lifts), its
    fingers squeezed by EFFORT actuators, the box between them: nothing of it needs Python between
    the gripper's updates."""
    from modrob_sim.physics import actuators as A
    xml = H.fixture("gripper_hand.urdf").replace(
        '<joint name="mount" type="fixed"><parent link="world"/><child link="palm"/><origin xyz="0 0 1"/>',
        '<joint name="mount" type="prismatic"><parent link="world"/><child link="palm"/><origin xyz="0 0 1"/>'
        '<axis xyz="0 0 1"/><limit lower="-0.2" upper="0.5" effort="500" velocity="1"/>')
    assert 'type="prismatic"><parent link="world"/>' in xml
    world = World(time_step=0.001, native=native)
    hand = world.add_urdf("hand", xml)
    box = world.add_urdf("box", H.robot("box", H.box_link("box", 0.1, (0.1, 0.1, 0.1))),
                         pose=((0, 0, 0.9), (0, 0, 0, 1)))
    lift = world.add_actuator(hand.joints["mount"], A.POSITION_PID, gains=A.PidGains(3000.0, 0.0, 200.0))
    fingers = [world.add_actuator(hand.joints[j], A.EFFORT) for j in ("left", "right")]
    return world, hand, box, lift, fingers


def record_updates(gripper):
    """[(t, contacts counted, held)] at each of ``gripper``'s updates (nothing here may hold the
    World: the gripper is reachable from it, and the World must stay collectable)."""
    log = []
    update = gripper._update

    def recorded(seen):
        update(seen)
        log.append((round(gripper.world.time, 6), tuple(sorted(seen)), gripper.attached is not None))
    gripper._update = recorded
    return log


def close_hold_lift_open(world, box, lift, fingers):
    """Close on the box (it is welded after 13 updates), lift it 0.3 m, open: the weld holds it
    until the contact has been gone for more than detach_steps updates, then it falls."""
    left, right = fingers
    left.command, right.command = -20.0, 20.0
    seconds(world, 12.0)
    lift.command = 0.3
    seconds(world, 2.0)
    held = box.pose[0][2]
    left.command, right.command = 20.0, -20.0
    seconds(world, 4.0)
    return held


class EveryStepGripper(Gripper):
    """The grasp check as it was before due times: its hook is due at EVERY step and gathers the
    contacts of world.contacts() (the last step's), one per pair of collisions per step (the
    links here have one collision each); its updates count those. It also drains its contact
    watch at each update and keeps both, so that a test can compare them update by update."""

    def __init__(self, world, model, desc):
        self.per_step, self.compared = {}, []
        super(EveryStepGripper, self).__init__(world, model, desc)

    def after_due(self):
        return None

    def after_step(self, t, dt):
        name = self.model.name
        step = set()
        for c in self.world.contacts():
            for me, ml, om, ol in ((c.model1, c.link1, c.model2, c.link2),
                                   (c.model2, c.link2, c.model1, c.link1)):
                if me != name or ml not in self.links:
                    continue
                m = self.world.models.get(om)
                if m is not None and m.links[ol].body is not None:
                    (mc,), (oc,) = self.model.links[ml].collision_names, m.links[ol].collision_names
                    step.add((ml, mc, om, ol, oc))
        for key in step:
            self.per_step[key] = self.per_step.get(key, 0) + 1
        super(EveryStepGripper, self).after_step(t, dt)

    def _contacts(self):
        watched = super(EveryStepGripper, self)._contacts()
        per_step, self.per_step = self.per_step, {}
        per_step = sorted(SeenContact(*(key + (n,))) for key, n in per_step.items())
        self.compared.append((watched, per_step))
        return per_step


def run_lift(native, every_step, monkeypatch):
    with monkeypatch.context() as mp:
        if every_step:
            mp.setattr(builder, "Gripper", EveryStepGripper)
        world, hand, box, lift, fingers = lifting_hand_and_box(native)
    g = hand._grippers[0]
    assert isinstance(g, EveryStepGripper) == every_step
    log = record_updates(g)
    held = close_hold_lift_open(world, box, lift, fingers)
    return world, g, log, held, box


@needs_c
def test_the_check_on_due_times_decides_as_at_every_step_and_stops_the_world_only_at_its_updates(monkeypatch):
    """The same scene natively (between the updates in C), on the pure-Python backend and with the
    every-step rule: the same contacts counted at the same updates, the same attach and detach;
    natively the World stops for Python once per update (0.75 s), not at every step."""
    native = run_lift(True, False, monkeypatch)
    pure = run_lift(False, False, monkeypatch)
    every = run_lift(True, True, monkeypatch)
    world, log = native[0], native[2]
    held = [u for u in log if u[2]]
    assert len(log) == 24 and log[0][0] == UPDATE_PERIOD and log[-1][0] == 18.0
    assert held[0][0] == 9.75 and held[-1][0] == 15.75      # welded at the 13th update, let go at the 22nd
    assert len(log[0][1]) == 2 and log[-1][1] == ()
    assert native[3] > 1.15 and native[4].pose[0][2] < 0.0  # lifted with the hand, dropped when let go
    assert pure[2] == log
    assert every[2] == log
    # update by update the watch saw exactly what every step's contacts added up to
    assert len(every[1].compared) == 24
    assert all(watched == per_step for watched, per_step in every[1].compared)
    assert every[0].state_digest() == world.state_digest()
    # 1.33 stops per simulated second, every step made in C; at every step with the old rule
    assert world.stops == len(log) and world.native_steps == world.iterations == 18000
    assert every[0].stops == 18000


@pytest.mark.parametrize("native", [pytest.param(False, id="pure"),
                                    pytest.param(True, id="native", marks=needs_c)])
def test_reset_world_and_reset_let_go_and_count_again(native):
    """After a reset the gripper lets go at the next step and its updates start 0.75 s later: the
    object is welded again only after as many updates as the first time."""
    world, hand, box, lift, fingers = lifting_hand_and_box(native)
    g = hand._grippers[0]
    log = record_updates(g)
    fingers[0].command, fingers[1].command = -20.0, 20.0
    seconds(world, 10.0)
    assert g.attached is not None
    for reset in ("reset_world", "reset"):
        t0 = world.time if reset == "reset_world" else 0.0
        getattr(world, reset)()
        del log[:]
        world.step(1)
        assert g.attached is None, reset
        seconds(world, 10.0 if reset == "reset_world" else 1.6)
        assert [u[0] for u in log[:2]] == [round(t0 + 0.001 + UPDATE_PERIOD, 6),
                                           round(t0 + 0.001 + 2 * UPDATE_PERIOD, 6)], reset
        held = [u[2] for u in log]
        assert held.index(True) == 12 if reset == "reset_world" else not any(held)   # the 13th, as at first


# ---- Gazebo 11's counting: contacts per pair of collisions and step; one ring for all candidates ----

def pressed_against_posts(native, sides):
    """The fixture's hand with its fingers opening outwards, each pressing a box (0.06 m) against a
    static post beside it (``sides``: "l", "r" or both): each box touches ONE gripper link."""
    world = World(time_step=0.001, native=native)
    hand = world.add_urdf("hand", H.fixture("gripper_hand.urdf"))
    posts = '<link name="world"/>'
    for side, sign in (("l", 1), ("r", -1)):
        posts += (H.box_link("post_" + side, 1.0, (0.1, 0.05, 0.3)) +
                  H.joint("at_" + side, "fixed", "world", "post_" + side, xyz="0 %r 0.9" % (sign * 0.2)))
        if side in sides:
            world.add_urdf("box_" + side, H.robot("box", H.box_link("box", 0.1, (0.06, 0.06, 0.06))),
                           pose=((0, sign * 0.145, 0.9), (0, 0, 0, 1)))
    world.add_urdf("posts", H.robot("posts", posts))
    from modrob_sim.physics import actuators as A
    world.add_actuator(hand.joints["left"], A.EFFORT).command = 20.0     # opening: towards +y
    world.add_actuator(hand.joints["right"], A.EFFORT).command = -20.0
    return world, hand


@pytest.mark.parametrize("native", [pytest.param(False, id="pure"),
                                    pytest.param(True, id="native", marks=needs_c)])
def test_an_object_touched_by_one_gripper_link_is_welded(native):
    """Gazebo counts the contacts of every step, one per pair of collisions: one finger pressing a
    box makes 750 of them per update (>= min_contact_count 2), and the box, in at least 2 of them,
    is welded once still (the 13th update with the fixture's attach_steps 2: the 3rd update on
    fills the ring of 10). The rule before counted distinct pairs (1 < 2) and wanted two sides."""
    world, hand = pressed_against_posts(native, "l")
    g = hand._grippers[0]
    log = record_updates(g)
    seconds(world, 13 * UPDATE_PERIOD - 0.01)
    assert g.attached is None
    seconds(world, 0.02)
    assert g.attached is not None and g.attached[0].name == "box_l"
    assert [len(u[1]) for u in log] == [1] * 13              # finger_l and the box only
    assert all(u[1][0].link == "finger_l" and u[1][0].steps == 750 for u in log[1:])
    if native:
        assert world.stops == 13


@needs_c
def test_two_objects_touched_at_once_share_one_stillness_ring_and_neither_is_welded():
    """Each finger presses a box of its own: both are candidates at every update, in the order of
    their collisions' scoped names, and each one's position is compared with the other's (Gazebo's
    one ring and one previous pose): neither ever counts as still, although each alone is welded
    at the 13th update (above)."""
    world, hand = pressed_against_posts(True, "lr")
    g = hand._grippers[0]
    log = record_updates(g)
    seconds(world, 20 * UPDATE_PERIOD)
    assert g.attached is None
    assert all(sorted(s.other_model for s in u[1]) == ["box_l", "box_r"] for u in log[1:])
    assert g._pos == 20 and min(g._diffs) > 0.08          # |(0, 0.29, 0)|^2 between the boxes


def test_the_update_counts_contacts_per_step_and_pair_of_collisions():
    """One finger touching an object in 2 steps of an update period counts up (min_contact_count
    2); in 1 step it counts down; two fingers touching each other make one contact per step
    (the watch has their pair both ways round)."""
    world = World(time_step=0.001, native=False)
    hand = world.add_urdf("hand", H.fixture("gripper_hand.urdf"))
    g = hand._grippers[0]

    def box(steps):
        return SeenContact("finger_l", "finger_l_collision", "box", "box", "box_collision", steps)

    def fingers(steps):
        lc, rc = "finger_l_collision", "finger_r_collision"
        return [SeenContact("finger_l", lc, "hand", "finger_r", rc, steps),
                SeenContact("finger_r", rc, "hand", "finger_l", lc, steps)]
    for seen, counted, pos in (([box(2)], 2, 1), ([box(1)], 1, 0), ([box(5)], 5, 1), (fingers(1), 1, 0),
                               (fingers(2), 2, 1), (fingers(1) + [box(1)], 2, 2)):
        assert g.contact_count(seen) == counted
        g._update(seen)
        assert g._pos == pos, seen


@needs_c
def test_a_let_go_object_is_welded_again_at_once_where_it_was():
    """HandleDetach keeps the ring and the previous position (Gazebo resets neither): an object
    still where it was when welded is welded again at the next update that counts up."""
    world, hand = pressed_against_posts(True, "l")
    g = hand._grippers[0]
    log = record_updates(g)
    seconds(world, 13 * UPDATE_PERIOD + 0.01)
    assert g.attached is not None
    g._detach("a test let go")
    seconds(world, UPDATE_PERIOD)
    assert g.attached is not None and log[-1][2]


@pytest.mark.parametrize("native", [pytest.param(False, id="pure"),
                                    pytest.param(True, id="native", marks=needs_c)])
def test_a_static_gripper_link_counts_nothing(native):
    """Gazebo drops a contact with a static collision: a box resting (awake) on the fixture's palm,
    welded to the world and named a gripper link here, is never counted."""
    xml = H.fixture("gripper_hand.urdf")
    xml = xml.replace("<gripper_link>finger_l</gripper_link>", "<gripper_link>palm</gripper_link>")
    world = World(time_step=0.001, native=native)
    world.set_physics_params(auto_disable=False)
    hand = world.add_urdf("hand", xml)
    world.add_urdf("box", H.robot("box", H.box_link("box", 0.1, (0.1, 0.1, 0.1))),
                   pose=((0, 0, 1.08), (0, 0, 0, 1)))
    g = hand._grippers[0]
    assert hand.links["palm"].body is None
    seconds(world, 3 * UPDATE_PERIOD)
    assert world.models["box"].pose[0][2] == pytest.approx(1.075, abs=0.002)   # resting on the palm
    assert (g._pos, g._zero) == (0, 3)
