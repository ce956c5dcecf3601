"""PID tuning for ros_control's effort_controllers/JointPositionController (pure, no rospy).

* :mod:`.loops`     -- where a joint is exercised: the ODE physics core (fast, no ROS) or a
                       one-joint integrator model for tests; the ROS backend lives in tune_pid.
* :mod:`.relay`     -- Astrom-Hagglund relay feedback: ultimate gain Ku and period Tu.
* :mod:`.rules`     -- Ziegler-Nichols style tables from (Ku, Tu) to p, i, d.
* :mod:`.sine`      -- the seed's method: a sinusoidal set-point, measured vs commanded, and a
                       search over the gains that makes them align.
* :mod:`.metrics`   -- step-response figures (rise, overshoot, settling, steady-state error).
* :mod:`.report`    -- gains to ros_control YAML, and the before/after plot (PNG).
"""
from modrob_sim.errors import ModrobError


class TuningError(ModrobError):
    """A tuning experiment that could not be run or analysed (no oscillation, unknown joint ...)."""
