"""PID gains for the effort_controllers/JointPositionController of every joint, from the link
inertias and the effort limit (a reasoned starting point; the PID auto-tuner refines them).

Per revolute joint k, with the chain straight (all joints at 0) and s_i the position along the
chain of the centre of mass of distal body i (mass m_i, principal moments I_i):

* lever arm rho_i: for an elbow joint (axis across the chain) rho_i = s_i - s_k, the straight
  chain being the farthest the distal bodies get from the axis; for an inline joint (axis along
  the chain) rho_i = s_i - s_e beyond the first elbow e after k (which can bend the rest of the
  chain across the axis), 0 before it;
* J_max = sum_i (max(I_i) + m_i rho_i^2): an upper bound of the inertia about the axis;
* J_min = the inertia about the axis of the rigid group right after the joint (up to the next
  actuated joint), which includes the drive's reflected rotor inertia (armature): the smallest
  inertia the controller can ever see;
* G = g sum_i m_i rho_i: the largest static gravity torque; 0 for an inline joint with only
  inline joints before it (bases stand upright, so its axis is vertical).

The loop J q'' = tau - b q' with tau = Kp e - Kd q' + Ki int(e) is tuned on J_max:

    omega = min(omega_target,
                sqrt(effort / (e_sat J_max)),           # a step of e_sat does not saturate P
                kappa J_min / (2 zeta dt J_max))        # Kd dt / J_min <= kappa: the explicit
                                                        # 1 ms step stays stable at J_min
    Kp = J_max omega^2,  Kd = max(0, 2 zeta J_max omega - b),  Ki = Kp omega / 2 (Ti = 2/omega,
    2.8 times the Routh bound Ti > 1/(2 zeta omega)),  i_clamp = min(effort, 1.5 G)
    (0.1 effort where G = 0).

Prismatic gripper fingers use the same formulas with the finger mass for J and lengths for
angles (e_sat 5 mm), so a finger commanded to close on an object saturates at its effort limit
(the grip force).
"""
import math

GRAVITY = 9.81
ZETA = 0.7
TIME_STEP = 0.001
KAPPA = 0.2
ARM_OMEGA = 2 * math.pi * 2.0      # 2 Hz closed-loop bandwidth target for arm joints
ARM_E_SAT = 0.1                    # rad
FINGER_OMEGA = 100.0               # rad/s
FINGER_E_SAT = 0.005               # m
GRIPPER_PAYLOAD = (0.37 + 0.05, 0.08)   # gripper (0.27 + 2 x 0.05 kg) + a bulb, COM 8 cm past ee


class JointLoad(object):
    """What the gains are computed from (kept for the documentation table)."""

    def __init__(self, joint, effort, damping, j_min, j_max, gravity_torque):
        self.joint = joint
        self.effort = effort
        self.damping = damping
        self.j_min = j_min
        self.j_max = j_max
        self.gravity_torque = gravity_torque


class Gains(object):
    def __init__(self, p, i, d, i_clamp, omega):
        self.p, self.i, self.d, self.i_clamp, self.omega = p, i, d, i_clamp, omega

    def as_dict(self):
        return {"p": round(self.p, 4), "i": round(self.i, 4), "d": round(self.d, 4),
                "i_clamp": round(self.i_clamp, 4), "antiwindup": True}


def _chain_bodies(robot, payload):
    """[(s_com, mass, inertia, link_name)] along the straight chain, plus joint positions."""
    bodies, joint_s = [], {}
    s = 0.0
    for joint in robot.joints:
        if joint.name != "world_joint":
            s += joint.xyz[2]
        if joint.actuated:
            joint_s[joint.name] = s
        link = next(lk for lk in robot.links if lk.name == joint.child)
        if link.body is not None:
            bodies.append((s + link.com[2], link.mass, link.inertia, link.name, joint.name))
    if payload and payload[0] > 0.0:
        bodies.append((s + payload[1], payload[0], (0.0, 0.0, 0.0), "payload", "ee_joint"))
    return bodies, joint_s


def joint_loads(robot, payload=None):
    """JointLoad for every actuated joint of a RobotModel (arm joints only)."""
    bodies, joint_s = _chain_bodies(robot, payload)
    actuated = robot.actuated_joints
    loads = []
    for idx, joint in enumerate(actuated):
        s_k = joint_s[joint.name]
        axis = "xyz".index(joint.module.axis)
        names_after = [j.name for j in robot.joints]
        start = names_after.index(joint.name)
        distal = [b for b in bodies if names_after.index(b[4]) >= start]
        next_joint = actuated[idx + 1].name if idx + 1 < len(actuated) else None
        stop = names_after.index(next_joint) if next_joint else len(names_after)
        rigid = [b for b in distal if names_after.index(b[4]) < stop]
        if joint.module.axis == "z":
            elbows = [joint_s[j.name] for j in actuated[idx + 1:] if j.module.axis != "z"]
            pivot = elbows[0] if elbows else None
        else:
            pivot = s_k
        j_max = g_torque = 0.0
        for s_com, mass, inertia, _, _ in distal:
            rho = max(0.0, s_com - pivot) if pivot is not None else 0.0
            j_max += max(inertia) + mass * rho * rho
            g_torque += GRAVITY * mass * rho
        j_min = 0.0
        for s_com, mass, inertia, _, _ in rigid:
            rho = (s_com - s_k) if joint.module.axis != "z" else 0.0
            j_min += inertia[axis] + mass * rho * rho
        if joint.module.axis == "z" and all(j.module.axis == "z" for j in actuated[:idx]):
            g_torque = 0.0   # vertical axis: gravity exerts no torque about it
        loads.append(JointLoad(joint.name, joint.module.effort, joint.module.damping, j_min,
                               max(j_max, j_min), g_torque))
    return loads


def pid_from_load(load, omega_target=ARM_OMEGA, e_sat=ARM_E_SAT, dt=TIME_STEP):
    omega = min(omega_target,
                math.sqrt(load.effort / (e_sat * load.j_max)),
                KAPPA * load.j_min / (2.0 * ZETA * dt * load.j_max))
    p = load.j_max * omega ** 2
    d = max(0.0, 2.0 * ZETA * load.j_max * omega - load.damping)
    i = p * omega / 2.0
    i_clamp = min(load.effort, 1.5 * load.gravity_torque) if load.gravity_torque > 0 else 0.1 * load.effort
    return Gains(p, i, d, i_clamp, omega)


def finger_load(joint, grip_force, finger_mass=0.05, damping=0.5):
    return JointLoad(joint, grip_force, damping, finger_mass, finger_mass, 0.0)


def finger_gains(load, dt=TIME_STEP):
    g = pid_from_load(load, omega_target=FINGER_OMEGA, e_sat=FINGER_E_SAT, dt=dt)
    # the integral drives a blocked finger up to the full grip force
    g.i_clamp = load.effort
    return g
