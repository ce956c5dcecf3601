"""modrob_sim.physics: the pure-Python physics core (no rospy) on ODE through PyODE.

    from modrob_sim.physics import World
    world = World(time_step=0.001, seed=0)
    robot = world.add_urdf("arm", urdf_text)
    world.step(1000)

See docs/design/sim_core_api.md (the contract) and docs/physics.md (the design).
"""
from .contact_watch import ContactWatch, SeenContact
from .description import PluginSpec
from .model import Joint, Link, Model
from .world import DEFAULT_PARAMS, ContactPoint, GuardEvent, World

__all__ = ["World", "Model", "Link", "Joint", "GuardEvent", "ContactPoint", "ContactWatch", "SeenContact",
           "PluginSpec", "DEFAULT_PARAMS"]
