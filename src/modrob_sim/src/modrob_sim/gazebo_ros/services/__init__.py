"""The /gazebo node's services, one group per responsibility (docs/simulator.md, "Services"):
models.py (spawn, delete, states, configuration), properties.py (world/model/joint/link
properties), forces.py (wrenches and efforts), physics.py (pause, reset, physics properties, step).
Every handler runs its work in the simulation loop thread through ServiceGroup.run."""
