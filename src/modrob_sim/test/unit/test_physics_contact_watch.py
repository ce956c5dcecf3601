"""Tier 1: the World's contact watches (World.watch_contacts, physics/contact_watch.py): the pairs of
collisions a few links touched at ANY step since the last drain and in how many steps, noted where
each backend makes its contacts (the C loop's near callback, the pure-Python path's), so that the
steps between two drains run natively. Both backends; what the watch reports equals a per-step
accumulation over world.contacts(); a link with two collisions makes two pairs; it survives spawns
(the C geom table rehashed), deletions, resets and a model frozen by the guard."""
import importlib.util
import os

import pytest

from modrob_sim.errors import InputError
from modrob_sim.physics import SeenContact, World
from modrob_sim.physics import native as native_mod

_FIX = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures", "physics")
_spec = importlib.util.spec_from_file_location("physics_helpers", os.path.join(_FIX, "physics_helpers.py"))
H = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(H)

BACKENDS = [pytest.param(False, id="pure"),
            pytest.param(True, id="native", marks=pytest.mark.skipif(native_mod.LIB is None,
                                                                     reason="the C loop is not built"))]


def ball_urdf(radius=0.05, mass=0.2):
    i = 0.4 * mass * radius * radius
    return H.robot("ball", '<link name="ball">%s<collision><geometry><sphere radius="%r"/></geometry>'
                           '</collision></link>' % (H.inertial(mass, i, i, i), radius))


def chute_world(native):
    """A static plate tilted by 0.6 rad 1 m up, a ball dropped on it: it lands, rolls off the plate's
    lower edge within a few tenths of a second and falls on (nothing below)."""
    world = World(time_step=0.001, native=native)
    plate = H.box_link("plate", 1.0, (0.4, 0.4, 0.02))
    fix = H.joint("fix", "fixed", "world", "plate", xyz="0 0 1", rpy="0.6 0 0")
    chute = world.add_urdf("chute", H.robot("chute", '<link name="world"/>' + plate + fix))
    ball = world.add_urdf("ball", ball_urdf(), pose=((0, 0, 1.15), (0, 0, 0, 1)))
    return world, chute, ball


def pairs(drained):
    """(watched link, other model, other link) of what a drain gave (the steps checked apart)."""
    assert all(s.steps > 0 for s in drained)
    return [(s.link, s.other_model, s.other_link) for s in drained]


PLATE_BALL = [("plate", "ball", "ball")]


@pytest.mark.parametrize("native", BACKENDS)
def test_a_contact_between_two_drains_is_reported_though_gone_at_the_drain(native):
    world, chute, ball = chute_world(native)
    watch = world.watch_contacts([chute.links["plate"]])
    world.step(1500)
    assert ball.pose[0][2] < 0.0                 # it rolled off and fell past the plate
    assert world.contacts() == []                # nothing touches anything now
    seen = watch.drain()                         # but the plate was touched in between:
    assert seen == [SeenContact("plate", "plate_collision", "ball", "ball", "ball_collision", seen[0].steps)]
    assert 50 < seen[0].steps < 1000             # in the steps it rolled over the plate
    assert watch.drain() == []                   # forgotten once handed out
    if native:
        assert world.native_steps == world.iterations == 1500   # every step made in C


def per_step_accumulation(world, model, links):
    """What the watch should report, from world.contacts() after every step (a Python hook): the
    steps in which each pair touched (the links here have one collision each)."""
    seen = {}

    def after(t, dt):
        step = set()
        for c in world.contacts():
            for me, ml, om, ol in ((c.model1, c.link1, c.model2, c.link2),
                                   (c.model2, c.link2, c.model1, c.link1)):
                if me == model and ml in links and world.models[om].links[ol].body is not None:
                    (name,) = world.models[me].links[ml].collision_names
                    (other,) = world.models[om].links[ol].collision_names
                    step.add((ml, name, om, ol, other))
        for key in step:
            seen[key] = seen.get(key, 0) + 1
    world.add_step_hook(after=after)
    return seen


@pytest.mark.parametrize("native", BACKENDS)
def test_the_watch_reports_what_every_steps_contacts_add_up_to(native):
    """Boxes rain on a hand (a static palm and two sliding fingers) and on a floor: the watch on the
    palm and one finger reports, at each drain, exactly the pairs of every step's contacts since
    the last one (static collisions, the floor's, and the other finger's not)."""
    world = World(time_step=0.001, native=native)
    world.add_sdf("<sdf version='1.6'><world name='w'><include><uri>model://ground_plane</uri></include>"
                  "</world></sdf>")
    hand = world.add_urdf("hand", H.fixture("gripper_hand.urdf"))
    # on the palm, on finger_l's outer edge, on finger_r's, on the floor, on the palm
    for k, (x, y, z) in enumerate([(0.0, 0.0, 1.3), (0.0, 0.135, 1.2), (0.0, -0.135, 1.4), (0.3, 0.0, 1.0),
                                   (-0.06, 0.05, 1.8)]):
        world.add_urdf("box%d" % k, H.robot("box", H.box_link("box", 0.1, (0.06, 0.06, 0.06))),
                       pose=((x, y, z), (0, 0, 0, 1)))
    watched = ("palm", "finger_l")
    watch = world.watch_contacts([hand.links[n] for n in watched])
    expected = per_step_accumulation(world, "hand", watched)
    on_floor = world.watch_contacts([world.models["box3"].links["box"]])  # touches the floor only
    drains = []
    for _ in range(12):
        world.step(100)
        got = watch.drain()
        assert got == sorted(SeenContact(*(key + (n,))) for key, n in expected.items()), "t=%.3f" % world.time
        drains.append(got)
        expected.clear()
        assert on_floor.drain() == []              # a static collision is no pair
    assert world.models["box3"].pose[0][2] == pytest.approx(0.03, abs=0.002)   # resting on the floor
    seen = set(s for d in drains for s in d)
    # both watched links were touched, and the boxes falling on the ground only are not there
    assert set(s.link for s in seen) == set(watched)
    assert all(s.other_model.startswith("box") for s in seen)
    assert ("box3" not in set(s.other_model for s in seen))


@pytest.mark.parametrize("native", BACKENDS)
def test_each_pair_of_collisions_counts_the_steps_it_touched_in(native):
    """A bar with a block at each end (two collisions of one link, one named, one not) is dropped
    tilted on a loose plate lying on the floor: one end lands first. The watch on the plate gives
    a pair per collision, each with the steps in which it touched; resting (awake: auto-disable
    off, a sleeping pair makes no contacts), both touch at every step. The floor (static) is no
    pair of the plate's."""
    world = World(time_step=0.001, native=native)
    world.set_physics_params(auto_disable=False)
    world.add_sdf("<sdf version='1.6'><world name='w'><include><uri>model://ground_plane</uri></include>"
                  "</world></sdf>")
    plate = world.add_urdf("plate", H.robot("plate", H.box_link("plate", 5.0, (0.6, 0.3, 0.02))),
                           pose=((0, 0, 0.01), (0, 0, 0, 1)))
    ball = '<collision%s><origin xyz="%r 0 0"/><geometry><box size="0.06 0.06 0.06"/></geometry></collision>'
    bar = ('<link name="bar">%s%s%s</link>'
           % (H.inertial(0.3, 1e-4, 4e-3, 4e-3), ball % (' name="end_a"', -0.2), ball % ("", 0.2)))
    # tilted about y by -0.3 rad: end_a (at -x) is the lower one
    world.add_urdf("bar", H.robot("bar", bar), pose=((0, 0, 0.2), (0, -0.14943813, 0, 0.98877108)))
    watch = world.watch_contacts([plate.links["plate"]])
    world.step(1500)
    landed = watch.drain()
    assert [(s.collision, s.other_model, s.other_link, s.other_collision) for s in landed] == [
        ("plate_collision", "bar", "bar", "bar_collision_1"), ("plate_collision", "bar", "bar", "end_a")]
    first, second = landed[1].steps, landed[0].steps
    assert 1500 > first > second > 1000           # end_a landed first, both rest now
    world.step(100)
    assert [(s.other_collision, s.steps) for s in watch.drain()] == [("bar_collision_1", 100), ("end_a", 100)]
    if native:
        assert world.native_steps == world.iterations == 1600


@pytest.mark.parametrize("native", BACKENDS)
def test_models_spawned_and_deleted_around_a_watch(native):
    world, chute, ball = chute_world(native)
    watch = world.watch_contacts([chute.links["plate"]])
    # 150 more geoms: the C loop's geom table grows (rehashed); the watch's entries go with it
    for k in range(150):
        world.add_urdf("crate%d" % k, H.robot("crate", H.box_link("crate", 0.1, (0.05, 0.05, 0.05))),
                       pose=((5.0 + 0.1 * (k % 10), 0.1 * (k // 10), 0.02), (0, 0, 0, 1)))
    world.step(150)
    assert pairs(watch.drain()) == PLATE_BALL
    # a pair with a model deleted since it was seen is dropped
    world.step(20)
    world.remove_model("ball")
    assert watch.drain() == []
    world.add_urdf("ball", ball_urdf(), pose=((0, 0, 1.15), (0, 0, 0, 1)))
    world.step(150)
    assert pairs(watch.drain()) == PLATE_BALL    # the ball of the same name, spawned again
    # deleting the watched model closes its watch
    world.step(20)
    world.remove_model("chute")
    assert watch.closed and watch.drain() == []
    world.step(50)
    assert watch.drain() == []


@pytest.mark.parametrize("native", BACKENDS)
def test_reset_and_reset_world_drop_what_was_seen(native):
    for reset in ("reset_world", "reset"):
        world, chute, ball = chute_world(native)
        watch = world.watch_contacts([chute.links["plate"]])
        world.step(150)                           # the ball has landed
        getattr(world, reset)()
        assert watch.drain() == []                # back at its spawn pose, above the plate
        world.step(50)
        assert watch.drain() == []
        world.step(150)
        assert pairs(watch.drain()) == PLATE_BALL, reset


@pytest.mark.parametrize("native", BACKENDS)
def test_a_watch_on_a_model_the_guard_froze_keeps_watching(native):
    """A slider pushed far past the guard's speed limit at every step is frozen (held still as a
    kinematic body); a ball dropped on its base link is still reported."""
    world = World(time_step=0.001, native=native)
    inert = H.inertial(1.0, 0.01, 0.01, 0.01)
    links = ('<link name="a">%s<collision><geometry><box size="0.4 0.4 0.1"/></geometry></collision></link>'
             '<link name="b">%s</link>' % (inert, inert))
    s = H.joint("s", "prismatic", "a", "b", axis="1 0 0", limit=(-100.0, 100.0, 10.0, 1.0))
    slider = world.add_urdf("slider", H.robot("slider", links + s), pose=((0, 0, 5), (0, 0, 0, 1)))
    slider.joints["s"].effort_limit = 1e6
    world.add_step_hook(before=lambda t, dt: slider.joints["s"].set_effort(1e6))
    watch = world.watch_contacts([slider.links["a"]])
    for _ in range(20000):
        world.step(1)
        if world.frozen_models:
            break
    assert list(world.frozen_models) == ["slider"]
    world.pop_events()
    assert watch.drain() == []
    world.add_urdf("ball", ball_urdf(), pose=((0, 0, 5.2), (0, 0, 0, 1)))
    world.step(300)
    assert pairs(watch.drain()) == [("a", "ball", "ball")]
    assert 5.05 < world.models["ball"].pose[0][2] < 5.2   # it rests on the frozen model


def test_bad_watches_are_refused_with_what_to_do():
    world, chute, ball = chute_world(False)
    with pytest.raises(InputError, match="no link given; give the Links of one model"):
        world.watch_contacts([])
    with pytest.raises(InputError, match="is not a link of model 'chute'; a watch takes links of one model"):
        world.watch_contacts([chute.links["plate"], ball.links["ball"]])
    other = World()
    with pytest.raises(InputError, match="model 'ball' is not in this World"):
        other.watch_contacts([ball.links["ball"]])
    world.remove_model("ball")
    with pytest.raises(InputError, match="model 'ball' is not in this World"):
        world.watch_contacts([ball.links["ball"]])
