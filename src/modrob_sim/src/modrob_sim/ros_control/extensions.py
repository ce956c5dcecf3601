"""Hardware and controller types that other packages add to the ros_control emulation.

On Gazebo, a ``<robotSimType>`` (gazebo_ros_control's RobotHWSim) and a controller ``type`` are
pluginlib classes that any package exports. Here a package registers Python classes for those
names, and says so in its package.xml so that the simulator imports the module when a model or a
controller configuration first names the type::

    <export>
      <modrob_sim robot_sim_type="franka_gazebo/FrankaHWSim" module="franka_sim.hw_sim"/>
      <modrob_sim controller_type="franka_gazebo/FrankaGripperSim" module="franka_sim.gripper"/>
    </export>

The module calls, at import:

- ``register_robot_sim_type(name, factory)``: ``factory(plugin, model, transmissions, pid_gains,
  warn)`` returns the hardware (a :class:`~modrob_sim.ros_control.hardware.RobotHWSim`); ``plugin``
  is the gazebo_ros_control plugin (its ``namespace``, ``context`` for publishers);
- ``register_controller_type(cls, adapter=None)``: ``cls`` is a controller class (its ``TYPE`` is
  the type name, built as ``cls(name, hw, params)``); ``adapter(plugin, controller)`` builds its
  ROS side (topics, actions), else the generic one is used.

Pure apart from the package lookup (rospkg, no rospy).
"""
import logging
import threading

LOG = logging.getLogger("modrob_sim.ros_control")

_lock = threading.Lock()
_sim_types = {}
_controller_types = {}
_adapters = {}
_exports = None
_tried = set()


def register_robot_sim_type(name, factory):
    with _lock:
        _sim_types[name] = factory


def register_controller_type(cls, adapter=None):
    with _lock:
        _controller_types[cls.TYPE] = cls
        if adapter is not None:
            _adapters[cls.TYPE] = adapter


def adapter_factory(type_name):
    """The ROS adapter registered with a controller type, or None."""
    with _lock:
        return _adapters.get(type_name)


def set_package_exports(exports):
    """Look types up in this PackageExports (tests; the node uses every package on
    ROS_PACKAGE_PATH); None: back to the default."""
    global _exports
    with _lock:
        _exports = exports
        _tried.clear()


def _package_exports():
    global _exports
    if _exports is None:
        from modrob_sim.gazebo_ros.package_exports import PackageExports
        _exports = PackageExports()
    return _exports


def _import_exported(kind, name):
    """Import the modules packages export for ``kind`` ('robot_sim_type' or 'controller_type')
    ``name``, once each. Returns the texts of import errors."""
    from modrob_sim.gazebo_ros.package_exports import import_exported_module
    errors = []
    for export in _package_exports().type_exports(kind, name):
        key = (kind, export.package, export.module)
        if key in _tried:
            continue
        _tried.add(key)
        error = import_exported_module(export)
        if error is not None:
            LOG.error(error)
            errors.append(error)
    return errors


def robot_sim_type(name):
    """(factory or None, why not): the registered factory, importing an exported module first
    when needed."""
    with _lock:
        factory = _sim_types.get(name)
    if factory is None:
        errors = _import_exported("robot_sim_type", name)
        with _lock:
            factory = _sim_types.get(name)
        if factory is None:
            return None, ("; ".join(errors) if errors else
                          "no package exports it (<export><modrob_sim robot_sim_type=\"%s\" "
                          "module=\"<pkg>.<module>\"/></export>)" % name)
    return factory, ""


def controller_type(name):
    """The controller class registered for ``name`` (importing an exported module first), or None."""
    with _lock:
        cls = _controller_types.get(name)
    if cls is None:
        _import_exported("controller_type", name)
        with _lock:
            cls = _controller_types.get(name)
    return cls


def registered_controller_types():
    with _lock:
        return dict(_controller_types)
