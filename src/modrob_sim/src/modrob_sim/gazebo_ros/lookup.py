"""Names in requests -> objects of the World: models, scoped links and joints (``model::link``),
reference frames. Pure; used in the loop thread only."""
from modrob_sim.errors import RequestError

NO_LINK = "link [%s] does not exist; use the scoped name model::link"
WORLD_FRAMES = ("", "world", "map", "/map", "/world")


class Lookup(object):
    def __init__(self, world):
        self.world = world

    def model(self, name, what="model"):
        m = self.world.models.get(name)
        if m is None:
            raise RequestError("%s [%s] does not exist (models: %s)"
                               % (what, name, ", ".join(self.world.models) or "none"))
        return m

    def find_link(self, name):
        """A link by scoped name model::link, or by a link name unique in the world; None if none."""
        if "::" in name:
            mname, lname = name.rsplit("::", 1)
            m = self.world.models.get(mname)
            return m.links.get(lname) if m is not None else None
        found = [m.links[name] for m in self.world.models.values() if name in m.links]
        return found[0] if len(found) == 1 else None

    def link(self, name, message=NO_LINK):
        link = self.find_link(name)
        if link is None:
            raise RequestError(message % name)
        return link

    def find_joint(self, name):
        if "::" in name:
            mname, jname = name.rsplit("::", 1)
            m = self.world.models.get(mname)
            return m.joints.get(jname) if m is not None else None
        for m in self.world.models.values():
            if name in m.joints:
                return m.joints[name]
        return None

    def joint(self, name):
        joint = self.find_joint(name)
        if joint is None:
            raise RequestError("joint [%s] does not exist" % name)
        return joint

    def frame(self, name, field="reference_frame"):
        """(pose, twist) of a reference frame, or None for the world; RequestError when unknown."""
        if name in WORLD_FRAMES:
            return None
        m = self.world.models.get(name)
        if m is not None:
            return m.pose, m.twist
        link = self.find_link(name)
        if link is not None:
            return link.pose, link.twist
        raise RequestError("%s [%s] is neither a model nor a link; use \"world\", a model name or a scoped "
                           "link name model::link" % (field, name))
