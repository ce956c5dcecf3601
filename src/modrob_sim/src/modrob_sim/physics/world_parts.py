"""What a World shares with its backend (world.py, backends.py), and the two rules both use."""
import logging

LOG = logging.getLogger("modrob_sim.physics")


def may_sleep(model, params):
    """Whether ``model``'s body may fall asleep under the physics ``params``: only a free
    single-body model, and only while auto_disable is on (the World and its backends ask this)."""
    return bool(params["auto_disable"]) and len(model.bodies) == 1 and not model.articulated


class WorldParts(object):
    """What a World shares with its backend, handed over once at construction: the ODE world,
    spaces and contact group, the geom and model tables, the caches the World rebuilds when models
    come or go (dynamic models, damped joints with their coefficient, turn-counting joints, mimic
    pairs, soft-limit joints), the step settings (time step, gravity, physics parameters and what
    follows from them) and the warnings already given. The World writes them; the backend reads
    them and never sees the World."""
    __slots__ = ("ode_world", "static_space", "dyn_space", "contact_group", "geom_info", "entries",
                 "dynamic_models", "damped", "unwrap", "mimics", "soft", "params", "pair_cache",
                 "max_contacts", "layer", "world_step", "vmax2", "wmax2", "gravity", "dt", "warned")


def warn_once(warned, key, message):
    """Log ``message`` once per ``key`` (``warned``: the World's set of keys already warned)."""
    if key not in warned:
        warned.add(key)
        LOG.warning(message)
