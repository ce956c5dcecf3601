"""Facts about the package's worlds that code needs (the indoor football field)."""
from collections import namedtuple

Field = namedtuple("Field", "centre_x centre_y length width")

#: The field marked on inside_world.world's floor (worlds/generate_worlds.py draws it from this).
FIELD = Field(centre_x=3.5, centre_y=0.0, length=6.0, width=4.0)
