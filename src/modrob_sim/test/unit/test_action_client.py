"""modrob_sim.action_client: a goal's transitions that arrive before send_goal returns are handled
as the goal's, not refused as "a goal handle that we're not tracking"."""
import types

from actionlib.action_client import CommState
from actionlib import simple_action_client
from actionlib.simple_action_client import SimpleGoalState

from modrob_sim import action_client


class FakeHandle(object):
    def __init__(self, goal_id):
        self.comm_state_machine = types.SimpleNamespace(
            action_goal=types.SimpleNamespace(goal_id=types.SimpleNamespace(id=goal_id)))
        self.state = CommState.WAITING_FOR_GOAL_ACK

    def get_comm_state(self):
        return self.state

    def get_goal_status(self):
        return 3

    def get_result(self):
        return "result"


class FastServer(object):
    """An ActionClient whose server accepts (and finishes) the goal before send_goal returns."""

    def __init__(self, final_state):
        self.final_state = final_state
        self.n = 0
        self.ns = "/arm/follow_joint_trajectory"

    def send_goal(self, goal, transition_cb, feedback_cb):
        self.n += 1
        gh = FakeHandle("goal%d" % self.n)
        gh.state = CommState.ACTIVE
        transition_cb(gh)
        if self.final_state == CommState.DONE:
            gh.state = CommState.DONE
            transition_cb(gh)
        return gh


def client(server):
    # the client's state without actionlib's __init__ (which needs a ROS node)
    c = action_client.SimpleActionClient.__new__(action_client.SimpleActionClient)
    c._transition_lock, c._sending, c._early = action_client.threading.RLock(), False, set()
    c.action_client, c.gh, c.simple_state = server, None, SimpleGoalState.DONE
    c.done_condition = action_client.threading.Condition()
    return c


def test_an_early_active_transition_calls_active_cb(monkeypatch):
    errors = []
    monkeypatch.setattr(simple_action_client.rospy, "logerr", errors.append)
    c = client(FastServer(CommState.ACTIVE))
    active = []
    c.send_goal("goal", active_cb=lambda: active.append(1))
    assert active == [1] and c.simple_state == SimpleGoalState.ACTIVE and errors == []


def test_a_goal_done_before_send_goal_returns_is_done_once(monkeypatch):
    errors = []
    monkeypatch.setattr(simple_action_client.rospy, "logerr", errors.append)
    c = client(FastServer(CommState.DONE))
    done = []
    c.send_goal("goal", done_cb=lambda status, result: done.append((status, result)))
    assert done == [(3, "result")] and c.simple_state == SimpleGoalState.DONE and errors == []
    c.send_goal("goal")   # the next goal: the old one's handle is not confused with it
    assert c.gh.comm_state_machine.action_goal.goal_id.id == "goal2" and errors == []
