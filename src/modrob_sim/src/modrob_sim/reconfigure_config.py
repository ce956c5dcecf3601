"""What dynamic_reconfigure's Python server expects of a generated ``<Name>Config`` module, built at
run time (Debian ships the server but none of the generated Config modules this workspace needs).

``ConfigType(params)`` with ``params`` a list of ``Param(name, type, default, min, max,
description)`` (type ``"double"``, ``"int"``, ``"bool"`` or ``"str"``) has ``defaults``, ``min``,
``max`` and ``config_description`` in the dict layout the cfg generator writes, so
``dynamic_reconfigure.server.Server(ConfigType(params), callback, namespace=ns)`` serves them.
"""
import collections

Param = collections.namedtuple("Param", "name type default min max description")

_CAST = {"double": float, "int": int, "bool": bool, "str": str}


class ConfigType(object):
    def __init__(self, params):
        self.defaults, self.min, self.max = {}, {}, {}
        described = []
        for p in params:
            cast = _CAST[p.type]
            # a YAML value written as 30 must reach clients as the declared type (a double)
            self.defaults[p.name] = cast(p.default)
            self.min[p.name] = cast(p.min)
            self.max[p.name] = cast(p.max)
            described.append({"name": p.name, "type": p.type, "default": self.defaults[p.name],
                              "level": 1, "description": p.description, "min": self.min[p.name],
                              "max": self.max[p.name], "edit_method": "", "srcline": 0, "srcfile": "",
                              "ctype": p.type})
        self.config_description = {"name": "Default", "type": "", "state": True, "cstate": "true",
                                   "id": 0, "parent": 0, "parameters": described, "groups": [],
                                   "srcline": 0, "srcfile": "", "class": "DEFAULT", "parentclass": "",
                                   "parentname": "Default", "field": "default", "upper": "DEFAULT",
                                   "lower": "groups"}


def shutdown_server(server):
    """Take a dynamic_reconfigure Server's service and topics off the master."""
    server.set_service.shutdown()
    server.descr_topic.unregister()
    server.update_topic.unregister()
