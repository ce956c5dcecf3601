"""Launch files for a set of generated robots (Gazebo's launch files with gazebo_ros and
controller_manager replaced by modrob_sim):

* modrob_spawn.launch: per robot a group ns=modrob<N> (robot_description, spawn_model, the
  controller YAML, the spawner, robot_state_publisher on /modrob<N>/joint_states);
* modrob_robots.launch: modrob_sim's empty_world.launch plus modrob_spawn.launch.
"""
import xml.etree.ElementTree as ET


def _arg(parent, name, default):
    ET.SubElement(parent, "arg", name=name, default=default)


def _text(root):
    ET.indent(root, space="  ")
    return '<?xml version="1.0"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def spawn_launch(entries, comment):
    """entries: [(robot name, urdf path, yaml path, [controller names])]."""
    root = ET.Element("launch")
    root.append(ET.Comment(comment))
    for name, urdf_path, yaml_path, controllers in entries:
        group = ET.SubElement(root, "group", ns=name)
        ET.SubElement(group, "param", name="robot_description", textfile=urdf_path)
        ET.SubElement(group, "node", name="spawn_model", pkg="modrob_sim", type="spawn_model",
                      output="screen", args="-urdf -param robot_description -model %s" % name)
        ET.SubElement(group, "rosparam", file=yaml_path, command="load", ns="/")
        ET.SubElement(group, "node", name="controller_spawner", pkg="modrob_sim", type="spawner",
                      respawn="false", output="screen", args=" ".join(controllers))
        rsp = ET.SubElement(group, "node", name="robot_state_publisher", pkg="robot_state_publisher",
                            type="robot_state_publisher")
        ET.SubElement(rsp, "param", name="publish_frequency", type="double", value="50.0")
        ET.SubElement(rsp, "remap", attrib={"from": "joint_states", "to": "/%s/joint_states" % name})
    return _text(root)


def robots_launch(spawn_path, comment):
    root = ET.Element("launch")
    root.append(ET.Comment(comment))
    _arg(root, "world_name", "worlds/empty.world")
    _arg(root, "paused", "false")
    _arg(root, "gui", "true")
    _arg(root, "headless", "false")
    _arg(root, "real_time_factor", "1.0")
    inc = ET.SubElement(root, "include", file="$(find modrob_sim)/launch/empty_world.launch")
    for name in ("world_name", "paused", "gui", "headless", "real_time_factor"):
        ET.SubElement(inc, "arg", name=name, value="$(arg %s)" % name)
    ET.SubElement(root, "include", file=spawn_path)
    return _text(root)
