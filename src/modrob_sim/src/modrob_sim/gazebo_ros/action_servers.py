"""actionlib's servers when reset_simulation sends the clock back.

actionlib orders goals by their stamps (the client's clock when it sent them): a
SimpleActionServer refuses a goal stamped before its current or next goal ("canceled because
another goal was received by the simple action server"), and every ActionServer cancels a goal
stamped at or before the last cancel request's stamp. After reset_simulation the clients' clock
starts again from 0, so every goal they send is stamped before those of the goals sent before the
reset: the server would refuse them all until the clock passes the old stamps again. The plugins
and adapters that own a server call :func:`restamp_after_reset` from their reset hook.
"""
import rospy


def restamp_after_reset(server, now):
    """Stamps of ``server`` (an actionlib ActionServer or SimpleActionServer) later than ``now``
    (simulated seconds, the clock after the reset) become ``now``: its current and next goal (a
    SimpleActionServer's; their ids stay, the clients match goals by id) and the last cancel
    request's time. Stamps not after ``now`` (reset_world keeps the clock) stay as they are."""
    t = rospy.Time.from_sec(now)
    base = getattr(server, "action_server", server)     # a SimpleActionServer wraps an ActionServer
    # the locks in actionlib's own order: the ActionServer's, then the SimpleActionServer's
    with base.lock:
        if base.last_cancel > t:
            base.last_cancel = t
        if base is server:
            return
        with server.execute_condition:
            for handle in (server.current_goal, server.next_goal):
                if handle.get_goal() is not None and handle.get_goal_id().stamp > t:
                    handle.get_goal_id().stamp = t
