"""actionlib's SimpleActionClient without its goal-tracking race, for clients of the simulator.

actionlib's SimpleActionClient.send_goal learns which goal it tracks only when the inner
ActionClient.send_goal returns. A server that accepts sooner (the simulator's controllers answer
within one batch of steps, and a loaded machine can hold the client's thread longer) delivers the
goal's first transition before that: actionlib then logs "[ERROR] Got a transition callback on a
goal handle that we're not tracking" and the goal's ACTIVE (active_cb) is lost, although nothing
is wrong. This subclass keeps transitions that arrive while a goal is being sent and hands the
goal's own to actionlib's handling once the goal is known; everything else is actionlib's.
"""
import threading

import actionlib
from actionlib.simple_action_client import SimpleGoalState


def _goal_id(gh):
    return gh.comm_state_machine.action_goal.goal_id.id


class SimpleActionClient(actionlib.SimpleActionClient):

    def __init__(self, ns, ActionSpec):
        self._transition_lock = threading.RLock()   # user callbacks may send the next goal
        self._sending = False
        self._early = set()   # goal ids whose transitions came before send_goal returned
        super(SimpleActionClient, self).__init__(ns, ActionSpec)

    def send_goal(self, goal, done_cb=None, active_cb=None, feedback_cb=None):
        with self._transition_lock:
            self.stop_tracking_goal()
            self.done_cb, self.active_cb, self.feedback_cb = done_cb, active_cb, feedback_cb
            self.simple_state = SimpleGoalState.PENDING
            self._sending = True
            self._early.clear()
        # outside the lock: actionlib's goal list lock is taken here, and its callback thread holds
        # that one while it calls _handle_transition
        gh = self.action_client.send_goal(goal, self._handle_transition, self._handle_feedback)
        with self._transition_lock:
            self.gh = gh
            self._sending = False
            missed = _goal_id(gh) in self._early
            self._early.clear()
            if missed:
                # the goal's current state covers the transitions it went through meanwhile
                super(SimpleActionClient, self)._handle_transition(gh)

    def _handle_transition(self, gh):
        with self._transition_lock:
            if self._sending and gh != self.gh:
                self._early.add(_goal_id(gh))   # most likely the goal being sent: decided above
                return
            super(SimpleActionClient, self)._handle_transition(gh)
