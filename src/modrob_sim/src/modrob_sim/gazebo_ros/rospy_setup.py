"""How the /gazebo process sets up rospy: /use_sim_time, its own clock, the pure libraries'
Python logging forwarded to rosout."""
import logging
import sys

import rospy


def ensure_use_sim_time():
    """Set /use_sim_time to true when nobody has set it, as gazebo_ros does (call before
    rospy.init_node so that this process's rospy also follows /clock)."""
    import rosgraph
    try:
        master = rosgraph.Master("/gazebo_setup")
        if not master.hasParam("/use_sim_time"):
            master.setParam("/use_sim_time", True)
    except Exception as exc:  # noqa: B902 - no master yet: init_node will report it
        sys.stderr.write("gazebo: could not check /use_sim_time: %s\n" % exc)


class _RospyHandler(logging.Handler):
    """Python logging of the pure libraries (modrob_sim.physics ...) to rosout."""

    def emit(self, record):
        text = self.format(record)
        if record.levelno >= logging.ERROR:
            rospy.logerr(text)
        elif record.levelno >= logging.WARNING:
            rospy.logwarn(text)
        elif record.levelno >= logging.INFO:
            rospy.loginfo(text)
        else:
            rospy.logdebug(text)


def forward_python_logging(name):
    logger = logging.getLogger(name)
    if not any(isinstance(h, _RospyHandler) for h in logger.handlers):
        logger.addHandler(_RospyHandler())
        logger.setLevel(logging.INFO)
        logger.propagate = False


def take_over_sim_time():
    """In this process rospy would follow /clock by subscribing to it: the node would send every
    clock message to itself. Drop that subscription; the loop sets rospy's time directly before
    each step instead (so rospy.Time.now() in plugins is the step's time). True when sim time is
    in use here."""
    from rospy.impl import simtime
    sub = getattr(simtime, "_clock_sub", None)
    if sub is None or rospy.rostime.is_wallclock():
        return False
    sub.unregister()
    simtime._clock_sub = None
    return True
