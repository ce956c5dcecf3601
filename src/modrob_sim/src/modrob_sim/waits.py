"""Waits measured in wall-clock time, for clients of the simulator (scenarios, teleops, tests).

With ``use_sim_time`` set, actionlib's ``wait_for_server(timeout)``, ``rospy.sleep`` and
``rospy.get_time`` run on the simulator's clock: at ``real_time_factor`` 0 a minute of simulated
time can pass in a fraction of a wall second (before the controller spawner has even started the
action servers), and while the simulator is paused or not yet publishing ``/clock`` it never
passes. How long a client is willing to wait for the rest of the system is a wall-clock question.
"""
import time

import rospy

POLL = 0.02  # wall seconds between two looks at a condition


def wait_for_action_servers(clients, timeout):
    """Wait until every ``(SimpleActionClient, name)`` in ``clients`` has its server.

    Returns the name of the first server still missing after ``timeout`` wall seconds (or at
    shutdown), None when all are there.
    """
    end = time.monotonic() + timeout
    for client, name in clients:
        # the short sim-time timeout only bounds one look; the loop's limit is wall time
        while not client.wait_for_server(rospy.Duration(0.05)):
            if rospy.is_shutdown() or time.monotonic() > end:
                return name
            time.sleep(POLL)
    return None


def wait_until(condition, timeout):
    """Poll ``condition()`` until it is true (True) or ``timeout`` wall seconds pass (False)."""
    end = time.monotonic() + timeout
    while not rospy.is_shutdown():
        if condition():
            return True
        if time.monotonic() > end:
            return False
        time.sleep(POLL)
    return False


def stop_following_clock():
    """For a node that needs no simulated time any more (it only serves or waits for shutdown,
    with wall-clock timeouts): drop rospy's /clock subscription. With ``use_sim_time`` every rospy
    node subscribes to /clock at init_node, and an idle one still takes every message (~150 us of
    CPU each at the launch files' 250 per wall second: 4 % of a core per node, beside a simulator
    that wants the cores). rospy's time then stays at the last /clock received (the stamps of
    its later log messages too). True when a subscription was dropped."""
    from rospy.impl import simtime
    sub = getattr(simtime, "_clock_sub", None)
    if sub is None:
        return False
    sub.unregister()
    simtime._clock_sub = None
    return True
