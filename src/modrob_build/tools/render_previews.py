#!/usr/bin/env python3
"""Render PNG previews of every module of Modules.csv and of the seed robots with RViz (for
docs/modules.md). Needs a display (Xvfb) and a running master:

    Xvfb :N -screen 0 1280x1024x24 &  roscore -p PORT &
    DISPLAY=:N ROS_MASTER_URI=http://localhost:PORT python3 render_previews.py OUT_DIR

Each image: robot_state_publisher on the generated URDF, joint states from this script, RViz
(python bindings) with a white background, a 10 cm grid and the TF frames of the model,
grabbed after the scene has settled.
"""
import math
import os
import subprocess
import sys
import tempfile
import threading

import rospy
import yaml
from sensor_msgs.msg import JointState

from modrob_build.build import RobotSpec, build_robot_set
from modrob_build.demo_robot import DEMO_ORDER
from modrob_build.module_database import load_database
from modrob_build.robot_model import build_robot_model
from modrob_build.urdf_writer import robot_urdf
from modrob_kinematics.kdl_urdf import KinematicChain

WIDTH, HEIGHT = 800, 600


def rviz_config(focal, distance, show_tf, yaw=0.9, pitch=0.35):
    displays = [
        {"Class": "rviz/Grid", "Name": "Grid", "Enabled": True, "Cell Size": 0.1,
         "Plane Cell Count": 30, "Color": "160; 160; 164",
         "Reference Frame": "<Fixed Frame>"},
        {"Class": "rviz/RobotModel", "Name": "RobotModel", "Enabled": True,
         "Robot Description": "robot_description", "Visual Enabled": True, "Collision Enabled": False,
         "Alpha": 1},
    ]
    if show_tf:
        displays.append({"Class": "rviz/TF", "Name": "TF", "Enabled": True, "Marker Scale": 0.25,
                         "Show Arrows": False, "Show Axes": True, "Show Names": False})
    view = {"Class": "rviz/Orbit", "Distance": distance, "Pitch": pitch, "Yaw": yaw,
            "Focal Point": {"X": focal[0], "Y": focal[1], "Z": focal[2]}, "Near Clip Distance": 0.01,
            "Target Frame": "<Fixed Frame>"}
    manager = {"Class": "", "Displays": displays, "Enabled": True,
               "Global Options": {"Background Color": "255; 255; 255", "Fixed Frame": "world",
                                  "Frame Rate": 30},
               "Views": {"Current": view}}
    window = {"Height": HEIGHT, "Width": WIDTH, "Hide Left Dock": True, "Hide Right Dock": True}
    return {"Panels": [], "Visualization Manager": manager, "Window Geometry": window}


class JointPublisher(object):
    def __init__(self):
        self.pub = rospy.Publisher("/joint_states", JointState, queue_size=1)
        self.positions = {}  # name -> position
        self.lock = threading.Lock()
        self.timer = rospy.Timer(rospy.Duration(0.05), self._tick, reset=True)

    def _tick(self, _):
        with self.lock:
            names, values = list(self.positions), list(self.positions.values())
        msg = JointState(name=names, position=values)
        msg.header.stamp = rospy.Time.now()
        self.pub.publish(msg)


def render_job(job):
    """Render one image in this process (RViz's Ogre allows one VisualizationFrame per process)."""
    from python_qt_binding.QtWidgets import QApplication, QToolBar
    from rviz import bindings as rviz
    app = QApplication([sys.argv[0]])
    rospy.init_node("render_preview", anonymous=True, disable_signals=True)
    rospy.set_param("/robot_description", job["urdf"])
    joints_pub = JointPublisher()
    joints_pub.positions = dict(job["positions"])
    rsp = subprocess.Popen(["rosrun", "robot_state_publisher", "robot_state_publisher"],
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        with tempfile.NamedTemporaryFile("w", suffix=".rviz", delete=False) as f:
            yaml.safe_dump(rviz_config(job["focal"], job["distance"], job["show_tf"], job["yaw"],
                                       job["pitch"]), f)
            cfg_path = f.name
        frame = rviz.VisualizationFrame()
        frame.setSplashPath("")
        frame.initialize()
        config = rviz.Config()
        rviz.YamlConfigReader().readFile(config, cfg_path)
        frame.load(config)
        frame.setMenuBar(None)
        frame.setStatusBar(None)
        frame.setHideButtonVisibility(False)
        for toolbar in frame.findChildren(QToolBar):
            toolbar.hide()
        frame.resize(WIDTH, HEIGHT)
        frame.show()
        deadline = rospy.Time.now() + rospy.Duration(4.0)
        while rospy.Time.now() < deadline:
            app.processEvents()
            rospy.sleep(0.02)
        QApplication.primaryScreen().grabWindow(frame.winId()).save(job["out"])
        os.unlink(cfg_path)
    finally:
        rsp.terminate()
        rsp.wait()
    print("wrote %s" % job["out"])


def render(urdf, positions, out_path, focal, distance, show_tf, yaw=0.9, pitch=0.35):
    if not isinstance(focal, (list, tuple)):
        focal = (0.0, 0.0, focal)
    job = {"urdf": urdf, "positions": positions, "out": out_path, "focal": [float(v) for v in focal],
           "distance": distance, "show_tf": show_tf, "yaw": yaw, "pitch": pitch}
    with tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False) as f:
        yaml.safe_dump(job, f)
    subprocess.run([sys.executable, os.path.abspath(__file__), "--job", f.name], check=True)
    os.unlink(f.name)


def main():
    if sys.argv[1] == "--job":
        with open(sys.argv[2]) as f:
            return render_job(yaml.safe_load(f))
    out_dir = sys.argv[1]
    os.makedirs(out_dir, exist_ok=True)
    db = load_database()
    for module in db.modules.values():
        robot = build_robot_model([module], [module.id], index=0, prefix="", name=module.name)
        positions = {j.name: 0.6 for j in robot.actuated_joints}
        render(robot_urdf(robot), positions, os.path.join(out_dir, "module_%d.png" % module.id),
               focal=module.length / 2, distance=max(0.45, 3.0 * module.length), show_tf=True)
    robots = [
        ("seed_3dof", [59, 3, 55, 63, 57, 5], False, {"joint2": 0.5, "joint3": 0.3}),
        ("seed_6dof", [59, 3, 55, 63, 64, 4, 66, 4, 67, 5, 56, 5], False,
         {"joint2": 0.5, "joint3": 0.0, "joint4": 0.9, "joint5": 0.0, "joint6": 0.0}),
        ("seed_6dof_gripper", [59, 3, 55, 63, 64, 4, 66, 4, 67, 5, 56, 5], True,
         {"joint2": 0.5, "joint4": 0.9, "joint5": 0.0, "gripper_finger1_joint": 0.035,
          "gripper_finger2_joint": 0.035}),
        ("demo_4dof", DEMO_ORDER, False, {"joint2": 0.4, "joint3": 0.6, "joint4": 0.5}),
    ]
    for name, order, gripper, pos in robots:
        result = build_robot_set([RobotSpec(order)], gripper=gripper, db=db)
        robot = result.robots[0]
        positions = {j.name: 0.0 for j in robot.actuated_joints}
        positions.update({k: v for k, v in pos.items()})
        urdf = result.files["modrob0.urdf"]
        chain = KinematicChain.from_urdf_string(urdf, "world", robot.ee_link)
        tip = chain.fk_position([positions[n] for n in chain.joint_names])
        focal = (tip[0] / 2, tip[1] / 2, tip[2] / 2)
        span = math.sqrt(sum(v * v for v in tip))
        render(urdf, positions, os.path.join(out_dir, "robot_%s.png" % name), focal=focal,
               distance=1.5 * span, show_tf=False, yaw=math.radians(70), pitch=0.3)
    # the gripper close up, holding a 60 mm sphere (a bulb's glass) at its grasp centre
    result = build_robot_set([RobotSpec([59, 57, 3])], gripper=True, db=db)
    bulb = ('<link name="bulb_glass"><visual><geometry><sphere radius="0.03"/></geometry>'
            '<material name="glass"><color rgba="1.0 0.95 0.6 0.8"/></material></visual></link>'
            '<joint name="bulb_joint" type="fixed"><parent link="modrob0_gripper_tcp"/>'
            '<child link="bulb_glass"/></joint></robot>')
    render(result.files["modrob0.urdf"].replace("</robot>", bulb),
           {"joint1": 0.0, "gripper_finger1_joint": 0.0346, "gripper_finger2_joint": 0.0346},
           os.path.join(out_dir, "gripper.png"), focal=0.35, distance=0.45,
           show_tf=True, yaw=0.5, pitch=0.5)


if __name__ == "__main__":
    main()
