"""Module database, gripper, meshes, worlds (Bulbs and Slides) and small test robots."""
