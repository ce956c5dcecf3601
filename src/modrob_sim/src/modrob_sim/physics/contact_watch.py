"""The World's contact watches (``World.watch_contacts``): which collisions a few links of one model
touched at ANY step since the watch was last asked, not only in the last step (``World.contacts``),
and in how many steps. A check that runs now and then (Gazebo's ``<gripper>``, every 0.75 s, which
counts one contact per pair of collisions per step) thus sees the contacts of every step between
its runs while the steps between them run natively.

The pairs are noted and counted by the backend where it makes the contacts (the C loop's near
callback, the pure-Python path's); the watch hands them out by name.
"""
import weakref
from collections import namedtuple

#: a pair of collisions a contact watch saw: the watched link's name and its collision's, the other
#: side's model, link and collision names, and in how many steps the pair made contacts
SeenContact = namedtuple("SeenContact", "link collision other_model other_link other_collision steps")


class ContactWatch(object):
    """A contact watch on links of one model (made by ``World.watch_contacts``).

    * ``drain()``: a SeenContact for each pair of collisions (one of a watched link, the other
      anywhere) that made contacts at any step since the last drain (or since the watch was made,
      or the world was reset), with the number of those steps, sorted; then forgotten. Only pairs
      whose other side is on a body count (static collisions do not, as Gazebo's gripper drops
      them); two watched links touching each other are there both ways round.
    * ``clear()``: forget what was seen (the World does it at reset and reset_world).
    * ``close()``: stop watching. Deleting the watched model closes its watches; a pair with a
      model deleted since it was seen is dropped. A closed watch drains nothing.
    """

    def __init__(self, backend, model_name, link_names, handle):
        # weak: the backend's tables lead to the model, the model to its grippers and them to this
        # watch; a strong reference would make a cycle of ODE objects, which the cycle collector
        # frees in any order (the World tears them down in order, docs/physics.md)
        self._backend = weakref.ref(backend)
        self.model_name = model_name
        self.links = frozenset(link_names)
        self._handle = handle
        self._closed = False

    @property
    def closed(self):
        return self._closed

    def drain(self):
        backend = None if self._closed else self._backend()
        if backend is None:
            return []
        steps = {}
        for mine, other, n in backend.drain_watch(self._handle):
            key = (mine.link.name, mine.collision, other.model.name, other.link.name, other.collision)
            steps[key] = steps.get(key, 0) + n
        return sorted(SeenContact(*(key + (n,))) for key, n in steps.items())

    def clear(self):
        backend = None if self._closed else self._backend()
        if backend is not None:
            backend.drain_watch(self._handle)

    def close(self):
        if not self._closed:
            self._closed = True
            backend = self._backend()
            if backend is not None:
                backend.close_watch(self._handle)

    def __repr__(self):
        return "<ContactWatch of model '%s' links %s%s>" % (
            self.model_name, ", ".join(sorted(self.links)), " (closed)" if self._closed else "")
