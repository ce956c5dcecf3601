"""scenario.physics_paused: the simulation paused around the planning and unpaused whatever happens;
a simulation someone else paused stays paused; without the services the plan runs all the same."""
import pytest
import rospy

from modrob_motion.bulbs_and_slides import ScenarioError, scenario


class FakeGazebo(object):
    def __init__(self, paused=False, present=True):
        self.paused, self.present, self.calls = paused, present, []

    def wait_for_service(self, name, timeout=None):
        if not self.present:
            raise rospy.ROSException("timeout exceeded while waiting for service %s" % name)

    def proxy(self, name, _type):
        def call(*_args):
            self.calls.append(name.rsplit("/", 1)[-1])
            if name.endswith("get_physics_properties"):
                return type("Res", (), {"pause": self.paused})()
            self.paused = name.endswith("/pause_physics")
        return call


@pytest.fixture
def gazebo(monkeypatch):
    def make(**kw):
        g = FakeGazebo(**kw)
        monkeypatch.setattr(scenario.rospy, "wait_for_service", g.wait_for_service)
        monkeypatch.setattr(scenario.rospy, "ServiceProxy", g.proxy)
        monkeypatch.setattr(scenario.rospy, "logwarn", lambda *a: g.calls.append("warn"))
        return g
    return make


def test_paused_while_planning_then_unpaused(gazebo):
    g = gazebo()
    with scenario.physics_paused():
        assert g.paused
    assert not g.paused
    assert g.calls == ["get_physics_properties", "pause_physics", "unpause_physics"]


def test_unpaused_when_the_planning_fails(gazebo):
    g = gazebo()
    with pytest.raises(ScenarioError):
        with scenario.physics_paused():
            raise ScenarioError("no grasp")
    assert not g.paused


def test_a_simulation_paused_by_someone_else_stays_paused(gazebo):
    g = gazebo(paused=True)
    with scenario.physics_paused():
        pass
    assert g.paused and g.calls == ["get_physics_properties"]


def test_without_the_services_it_warns_and_plans(gazebo):
    g = gazebo(present=False)
    ran = []
    with scenario.physics_paused():
        ran.append(True)
    assert ran and g.calls == ["warn"]
