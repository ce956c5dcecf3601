"""hector_gazebo_plugins' sensor error model (SensorModel), shared by the hector plugins (GPS,
IMU, magnetometer, sonar).

Per axis: measured = value * scaleError + error, error = offset + drift + N(0, gaussianNoise);
the drift is a first-order Gauss-Markov process, drift_k = exp(-dt f) drift_{k-1} +
dt N(0, sqrt(2 f) drift) with f = driftFrequency, and starts at N(0, drift) on every reset. The
parameters are ``<prefix>Offset``, ``<prefix>Drift``, ``<prefix>DriftFrequency``,
``<prefix>GaussianNoise``, ``<prefix>ScaleError`` (``offset`` ... without a prefix); defaults 0,
0, 1/3600 Hz, 0, 1. A vector parameter may be given as one number for every axis.
"""
import math


class SensorModel(object):
    def __init__(self, p, prefix, rng, axes=3):
        def name(base):
            return prefix + base[0].upper() + base[1:] if prefix else base
        self.axes = axes
        self.offset = p.floats(name("offset"), axes, (0.0,) * axes)
        self.drift = p.floats(name("drift"), axes, (0.0,) * axes)
        self.drift_frequency = p.floats(name("driftFrequency"), axes, (1.0 / 3600.0,) * axes)
        self.gaussian_noise = p.floats(name("gaussianNoise"), axes, (0.0,) * axes)
        self.scale_error = p.floats(name("scaleError"), axes, (1.0,) * axes)
        for what, v in (("drift", self.drift), ("driftFrequency", self.drift_frequency),
                        ("gaussianNoise", self.gaussian_noise)):
            if any(x < 0 for x in v):
                p.fail(name(what), v, "must not be negative")
        self.rng = rng
        self.reset()

    def reset(self, drift=None):
        """A new drift drawn from N(0, drift) (hector's reset()), or the given one (reset(value):
        the calibration and set-bias services)."""
        if drift is None:
            self.current_drift = [self.rng.normal(0.0, d) if d > 0 else 0.0 for d in self.drift]
        else:
            self.current_drift = [float(x) for x in drift]
        self.current_error = [0.0] * self.axes

    def update(self, dt):
        """Advance the drift by ``dt`` and draw the noise: the error of this reading."""
        for i in range(self.axes):
            f, d = self.drift_frequency[i], self.drift[i]
            kick = self.rng.normal(0.0, math.sqrt(2 * f) * d) if f > 0 and d > 0 else 0.0
            self.current_drift[i] = math.exp(-dt * f) * self.current_drift[i] + dt * kick
            noise = self.rng.normal(0.0, self.gaussian_noise[i]) if self.gaussian_noise[i] > 0 else 0.0
            self.current_error[i] = self.offset[i] + self.current_drift[i] + noise
        return tuple(self.current_error)

    def apply(self, value, dt):
        """``value`` (a sequence of ``axes`` numbers) as the sensor measures it."""
        error = self.update(dt)
        return tuple(v * s + e for v, s, e in zip(value, self.scale_error, error))

    @property
    def bias(self):
        """offset + drift (hector's getCurrentBias)."""
        return tuple(o + d for o, d in zip(self.offset, self.current_drift))
