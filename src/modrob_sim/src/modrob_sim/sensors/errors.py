"""Errors of the simulated sensors."""
from modrob_sim.errors import ModelError


class SensorConfigError(ModelError):
    """A sensor or sensor-plugin parameter that cannot be used; the message names the model, the
    link, the element and the value."""
