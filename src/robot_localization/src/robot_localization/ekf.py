"""The filter core, pure (numpy only): robot_localization's 15-variable state and its 3D
omnidirectional constant-acceleration model, an extended Kalman filter over it.

State (this order everywhere, as robot_localization's config vectors): x y z (world frame),
roll pitch yaw (of base_link in the world frame), vx vy vz and vroll vpitch vyaw (base_link frame),
ax ay az (base_link frame).

Prediction over dt: the position moves by R(rpy at mid-step) (v dt + a dt^2 / 2), the Euler
angles by the body rates mapped to Euler rates, the velocities by a dt. The Jacobian of that model is taken by
central differences. The covariance grows by F P F^T + Q dt (Q: ``process_noise_covariance``).
A measurement corrects the variables its mask selects (Joseph form), angles compared the short way
round; an innovation whose Mahalanobis distance exceeds the measurement's threshold is rejected.
The first measurement initialises the variables it measures (value and covariance), as
robot_localization does.
"""
import math

import numpy as np

N = 15
X, Y, Z, ROLL, PITCH, YAW, VX, VY, VZ, VROLL, VPITCH, VYAW, AX, AY, AZ = range(N)
NAMES = ("x", "y", "z", "roll", "pitch", "yaw", "vx", "vy", "vz", "vroll", "vpitch", "vyaw", "ax", "ay", "az")
ANGLES = (ROLL, PITCH, YAW)
#: the variables two_d_mode pins to 0 in every measurement
TWO_D = (Z, ROLL, PITCH, VZ, VROLL, VPITCH, AZ)
MIN_VARIANCE = 1e-9
TWO_D_VARIANCE = 1e-6

# robot_localization's default process noise diagonal and initial estimate covariance
DEFAULT_PROCESS_NOISE = np.diag([0.05, 0.05, 0.06, 0.03, 0.03, 0.06, 0.025, 0.025, 0.04, 0.01, 0.01, 0.02,
                                 0.01, 0.01, 0.015])
DEFAULT_INITIAL_COVARIANCE = np.eye(N) * 1e-9


def wrap(angle):
    """To [-pi, pi)."""
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


def rotation(roll, pitch, yaw):
    """Body -> world rotation matrix of fixed-axis roll, pitch, yaw (R = Rz Ry Rx)."""
    return rotations(np.array([[roll, pitch, yaw]]))[0]


def rotations(rpy):
    """Rotation matrices (M, 3, 3) of the rows (roll, pitch, yaw) of ``rpy`` (M, 3)."""
    cr, sr = np.cos(rpy[:, 0]), np.sin(rpy[:, 0])
    cp, sp = np.cos(rpy[:, 1]), np.sin(rpy[:, 1])
    cy, sy = np.cos(rpy[:, 2]), np.sin(rpy[:, 2])
    r = np.empty((rpy.shape[0], 3, 3))
    r[:, 0, 0], r[:, 0, 1], r[:, 0, 2] = cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr
    r[:, 1, 0], r[:, 1, 1], r[:, 1, 2] = sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr
    r[:, 2, 0], r[:, 2, 1], r[:, 2, 2] = -sp, cp * sr, cp * cr
    return r


def rpy_of_matrix(m):
    pitch = math.asin(max(-1.0, min(1.0, -m[2, 0])))
    return math.atan2(m[2, 1], m[2, 2]), pitch, math.atan2(m[1, 0], m[0, 0])


def euler_rates(rpy, w):
    """Body angular velocities ``w`` (M, 3) -> (roll, pitch, yaw) rates (M, 3) at ``rpy``."""
    cr, sr = np.cos(rpy[:, 0]), np.sin(rpy[:, 0])
    cp = np.cos(rpy[:, 1])
    cp = np.where(np.abs(cp) < 1e-6, np.copysign(1e-6, cp), cp)      # gimbal lock: finite rates
    tp = np.sin(rpy[:, 1]) / cp
    out = np.empty_like(w)
    out[:, 0] = w[:, 0] + sr * tp * w[:, 1] + cr * tp * w[:, 2]
    out[:, 1] = cr * w[:, 1] - sr * w[:, 2]
    out[:, 2] = (sr * w[:, 1] + cr * w[:, 2]) / cp
    return out


def motions(states, dt):
    """The states (M, 15) after ``dt`` seconds of the constant-acceleration model. The position
    moves along the orientation at mid-step (second order in dt)."""
    s = states.copy()
    rates = euler_rates(s[:, ROLL:YAW + 1], s[:, VROLL:VYAW + 1])
    r = rotations(s[:, ROLL:YAW + 1] + 0.5 * dt * rates)
    step = s[:, VX:VZ + 1] * dt + 0.5 * dt * dt * s[:, AX:AZ + 1]
    s[:, X:Z + 1] += np.einsum("mij,mj->mi", r, step)
    s[:, ROLL:YAW + 1] += rates * dt
    s[:, VX:VZ + 1] += s[:, AX:AZ + 1] * dt
    s[:, ROLL:YAW + 1] = (s[:, ROLL:YAW + 1] + math.pi) % (2.0 * math.pi) - math.pi
    return s


def motion(state, dt):
    """The state after ``dt`` seconds (see :func:`motions`)."""
    return motions(state[None, :], dt)[0]


def difference(a, b):
    """a - b with angles the short way round (rows of 2-D arrays too)."""
    d = a - b
    d[..., ROLL:YAW + 1] = (d[..., ROLL:YAW + 1] + math.pi) % (2.0 * math.pi) - math.pi
    return d


def jacobian(state, dt, eps=1e-6):
    """d motion / d state by central differences, the 30 perturbed states in one batch."""
    e = np.eye(N) * eps
    moved = motions(np.vstack((state + e, state - e)), dt)
    return (difference(moved[:N], moved[N:]) / (2.0 * eps)).T


class Measurement(object):
    """One measurement in state space: ``values`` and ``covariance`` (15, 15x15; only the masked
    rows and columns are read), ``mask`` (15 bools), ``time`` (s), ``threshold`` (Mahalanobis
    distance beyond which it is rejected; inf = never), ``source`` (the topic, for messages)."""
    __slots__ = ("values", "covariance", "mask", "time", "threshold", "source")

    def __init__(self, values, covariance, mask, time, threshold=math.inf, source=""):
        self.values = np.asarray(values, dtype=float)
        self.covariance = np.asarray(covariance, dtype=float)
        self.mask = np.asarray(mask, dtype=bool)
        self.time, self.threshold, self.source = time, threshold, source


class Ekf(object):
    def __init__(self, process_noise=None, initial_covariance=None, two_d_mode=False):
        self.q = np.array(DEFAULT_PROCESS_NOISE if process_noise is None else process_noise, dtype=float)
        self.p0 = np.array(DEFAULT_INITIAL_COVARIANCE if initial_covariance is None else initial_covariance,
                           dtype=float)
        self.two_d_mode = two_d_mode
        self.reset()

    def reset(self):
        self.state = np.zeros(N)
        self.covariance = self.p0.copy()
        self.initialized = False
        self.time = None            # time of the state
        self.rejected = 0

    def predict(self, t):
        """Move the state to time ``t`` (nothing when ``t`` is not after the state's time)."""
        if self.time is None:
            self.time = t
            return
        dt = t - self.time
        if dt <= 0.0:
            return
        f = jacobian(self.state, dt)
        self.state = motion(self.state, dt)
        self.covariance = f.dot(self.covariance).dot(f.T) + self.q * dt
        self.covariance = 0.5 * (self.covariance + self.covariance.T)
        self.time = t

    def predicted(self, t):
        """(state, covariance) predicted to time ``t``, the filter itself unchanged (for output
        between measurements: later measurements still find the filter at their own time)."""
        saved = self.state, self.covariance, self.time
        try:
            self.predict(t)
            return self.state.copy(), self.covariance.copy()
        finally:
            self.state, self.covariance, self.time = saved

    def _two_d(self, m):
        values, cov, mask = m.values.copy(), m.covariance.copy(), m.mask.copy()
        for i in TWO_D:
            values[i] = 0.0
            cov[i, :] = 0.0
            cov[:, i] = 0.0
            cov[i, i] = TWO_D_VARIANCE
            mask[i] = True
        return values, cov, mask

    def process(self, m):
        """Predict to the measurement's time, then correct with it. Returns False when rejected."""
        values, cov, mask = self._two_d(m) if self.two_d_mode else (m.values, m.covariance, m.mask)
        idx = np.flatnonzero(mask)
        if idx.size == 0:
            return True
        r = cov[np.ix_(idx, idx)].copy()
        for k in range(idx.size):
            r[k, k] = max(abs(r[k, k]), MIN_VARIANCE)
        if not self.initialized:
            self.state[idx] = values[idx]
            self.covariance[np.ix_(idx, idx)] = r
            self.initialized = True
            self.time = m.time if self.time is None else max(self.time, m.time)
            return True
        self.predict(m.time)
        y = values[idx] - self.state[idx]
        for k, i in enumerate(idx):
            if i in ANGLES:
                y[k] = wrap(y[k])
        p = self.covariance
        ph = p[:, idx]
        s = ph[idx, :] + r
        try:
            s_inv = np.linalg.inv(s)
        except np.linalg.LinAlgError:
            s_inv = np.linalg.pinv(s)
        if math.isfinite(m.threshold):
            d2 = float(y.dot(s_inv).dot(y))
            if d2 > m.threshold * m.threshold:
                self.rejected += 1
                return False
        k_gain = ph.dot(s_inv)
        self.state = self.state + k_gain.dot(y)
        for i in ANGLES:
            self.state[i] = wrap(self.state[i])
        ikh = np.eye(N)
        ikh[:, idx] -= k_gain
        self.covariance = ikh.dot(p).dot(ikh.T) + k_gain.dot(r).dot(k_gain.T)
        return True

    def set_state(self, values, covariance, mask, t):
        """set_pose: the masked variables take ``values`` and their covariance, the rest are
        zeroed with the initial covariance; the filter restarts from ``t``."""
        self.reset()
        idx = np.flatnonzero(np.asarray(mask, dtype=bool))
        self.state[idx] = np.asarray(values, dtype=float)[idx]
        self.covariance[np.ix_(idx, idx)] = np.asarray(covariance, dtype=float)[np.ix_(idx, idx)]
        self.initialized = True
        self.time = t
