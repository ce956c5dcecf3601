"""Gains that no explicit PID can run at the step size.

An explicit PID's damping term is applied as an effort for the whole next step: with a damping
gain ``k`` (the ``d`` of a position PID, the ``p`` of a velocity PID) on a joint that moves an
effective inertia ``I``, one step changes the velocity error by the factor ``1 - k dt / I``; when
``k dt / I > 2`` that factor is below -1 and the error grows every step, so the joint chatters at
its effort limit. Gazebo applies the same explicit effort and shows the same. ``I`` is the inertia
of everything beyond the joint moving with it (the joints beyond held by their own controllers),
about the joint's axis at the configuration the controller is loaded in: for the last joint of a
chain that is its link alone (a light hand with a large d chatters), for a shoulder the whole arm
(ur_gazebo's d = 200 on a UR5's shoulder_pan_joint runs; its shoulder link alone would not carry
it)."""
import math

from modrob_sim.ros_control.transmissions import EFFORT

#: k * dt / I beyond this diverges
STABILITY_LIMIT = 2.0


def unstable_gains(controller, dt):
    """[(joint name, gain name, gain, largest stable gain, effective inertia)] for a loaded
    controller at step ``dt``; empty when every gain can run."""
    out = []
    for res, pid, gain_name in _pid_loops(controller):
        inertia = effective_inertia(res.sim)
        if pid is None or not inertia or inertia <= 0.0 or dt <= 0.0:
            continue
        k = abs(getattr(pid.gains, gain_name))
        limit = STABILITY_LIMIT * inertia / dt
        if k > limit:
            out.append((res.name, gain_name, k, limit, inertia))
    return out


def effective_inertia(joint):
    """Inertia (kg m^2, revolute) or mass (kg, prismatic) of the links beyond physics ``joint``
    moving together, about (along) its axis now; None when the joint has no ODE joint."""
    oj = getattr(joint, "ode_joint", None)
    model = getattr(joint, "model", None)
    if oj is None or model is None:
        return None
    beyond = {}
    for j in model.joints.values():
        beyond.setdefault(j.parent, []).append(j.child)
    bodies, seen, todo = {}, set(), [joint.child]
    while todo:
        name = todo.pop()
        if name in seen:
            continue
        seen.add(name)
        link = model.links.get(name)
        body = getattr(link, "body", None)
        if body is not None:
            bodies[id(body)] = body
        todo.extend(beyond.get(name, ()))
    if joint.type not in ("revolute", "continuous"):
        return sum(b.getMass().mass for b in bodies.values())
    a, p = oj.getAxis(), oj.getAnchor()
    total = 0.0
    for b in bodies.values():
        m = b.getMass()
        R = b.getRotation()          # row-major; the body's inertia m.I is in its own frame
        ab = [sum(R[3 * r + c] * a[r] for r in range(3)) for c in range(3)]     # R^T a
        total += sum(ab[r] * m.I[r][c] * ab[c] for r in range(3) for c in range(3))
        d = [x - y for x, y in zip(b.getPosition(), p)]
        along = sum(x * y for x, y in zip(d, a))
        total += m.mass * max(0.0, sum(x * x for x in d) - along * along)
    return total if math.isfinite(total) else None


def _pid_loops(controller):
    """(joint resource, Pid, name of its damping gain) of the controller's explicit PIDs whose
    output is an effort (a PID that writes velocities is not such a loop)."""
    if controller.INTERFACE != EFFORT:
        return
    pids = getattr(controller, "pids", None)
    joints = getattr(controller, "joints", None)
    if pids is not None and joints is not None:
        for res, pid in zip(joints, pids):
            yield res, pid, "d"
        return
    pid = getattr(controller, "pid", None)
    res = getattr(controller, "joint", None)
    if pid is not None and res is not None:
        yield res, pid, "p" if "Velocity" in controller.TYPE else "d"


def message(controller_name, joint, gain_name, k, limit, inertia, dt):
    return ("controller '%s' joint '%s': %s = %g cannot run at the %g s step: the joint moves an "
            "effective inertia of %.3g (kg m^2 or kg), so %s*dt/I = %.3g > %g and the explicit PID "
            "diverges (the joint chatters at its effort limit, in Gazebo too). The largest stable %s "
            "is %.3g; use about half of it or less, or a smaller time step"
            % (controller_name, joint, gain_name, k, dt, inertia, gain_name, k * dt / inertia,
               STABILITY_LIMIT, gain_name, limit))
