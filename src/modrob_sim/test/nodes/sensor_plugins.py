#!/usr/bin/env python3
"""rostest node: the simulated sensors through /gazebo, each spawned with Gazebo's unchanged
plugin XML. ``sensor_plugins.py CASE`` runs one case (laser, gpu_laser, imu_sensor, imu_model,
velodyne, gps, p3d, bumper, ft_sensor, range, hector; several as a comma list share one /gazebo);
every .test file starts its own /gazebo."""
import importlib.util
import math
import os
import subprocess
import sys
import unittest

import numpy as np
import rospy
import rostest
from gazebo_msgs.msg import ContactsState, ModelStates
from geometry_msgs.msg import Pose, Vector3Stamped, WrenchStamped
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu, LaserScan, NavSatFix, PointCloud, PointCloud2, Range
from rosgraph_msgs.msg import Clock
from std_srvs.srv import Empty

from modrob_sim.waits import wait_until

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sim_helpers import Gazebo, Latest  # noqa: E402

_FIX = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures", "sensors")
_spec = importlib.util.spec_from_file_location("sensor_fixtures", os.path.join(_FIX, "sensor_fixtures.py"))
F = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(F)

CASE = sys.argv[1] if len(sys.argv) > 1 and not sys.argv[1].startswith("_") else "laser"


def pose(x=0.0, y=0.0, z=0.0, yaw=0.0):
    p = Pose()
    p.position.x, p.position.y, p.position.z = x, y, z
    p.orientation.z, p.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
    return p


def next_msg(latest, after_count, timeout=30.0):
    ok = wait_until(lambda: latest.count > after_count, timeout)
    return latest.get() if ok else None


class SensorPlugins(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.gz = Gazebo()
        r = cls.gz.spawn_sdf_model(model_name="ground_plane", model_xml=F.GROUND_MODEL, robot_namespace="",
                                   initial_pose=pose(), reference_frame="")
        assert r.success, r.status_message

    def spawn_urdf(self, name, xml, **kw):
        r = self.gz.spawn_urdf_model(model_name=name, model_xml=xml, robot_namespace="",
                                     initial_pose=pose(**kw), reference_frame="")
        self.assertTrue(r.success, r.status_message)

    def spawn_sdf(self, name, xml, **kw):
        r = self.gz.spawn_sdf_model(model_name=name, model_xml=xml, robot_namespace="",
                                    initial_pose=pose(**kw), reference_frame="")
        self.assertTrue(r.success, r.status_message)

    # ---- laser -------------------------------------------------------------------------------
    def check_laser(self, plugin, sensor_type, topic):
        b = math.radians(-40.0)
        self.spawn_sdf("target", F.static_shape("target", F.box((0.4, 0.4, 0.4)), (0, 0, 0)),
                       x=2.5 * math.cos(b), y=2.5 * math.sin(b), z=0.25)
        xml = F.sensor_robot(F.laser_sensor(plugin=plugin, topic=topic, frame="sensor_link", samples=360,
                                            rmin=0.1, rmax=8.0, rate=20, sensor_type=sensor_type))
        scans = Latest("/" + topic.lstrip("/"), LaserScan)
        self.spawn_urdf("laser_bot", xml, z=0.1)
        msg = next_msg(scans, 1)
        self.assertIsNotNone(msg, "no LaserScan on %s" % topic)
        self.assertEqual(msg.header.frame_id, "sensor_link")
        self.assertEqual(len(msg.ranges), 360)
        self.assertEqual(len(msg.intensities), 360)
        self.assertAlmostEqual(msg.angle_min, -math.pi, places=5)
        self.assertAlmostEqual(msg.angle_max, math.pi, places=5)
        self.assertAlmostEqual(msg.angle_increment, 2 * math.pi / 359, places=6)
        self.assertEqual(msg.time_increment, 0.0)
        self.assertEqual(msg.scan_time, 0.0)
        self.assertAlmostEqual(msg.range_min, 0.1, places=5)
        self.assertAlmostEqual(msg.range_max, 8.0, places=5)
        i = int(round((b - msg.angle_min) / msg.angle_increment))
        # sensor at 0.25 m height; the axis-aligned cube's face nearest the sensor is the plane
        # x = cx - 0.2 (cx = 2.5 cos b)
        cx = 2.5 * math.cos(b)
        ang = msg.angle_min + i * msg.angle_increment
        expected = (cx - 0.2) / math.cos(ang)
        self.assertLess(abs(msg.ranges[i] - expected), 0.01, (msg.ranges[i], expected))
        far = (i + 180) % 360
        self.assertTrue(math.isinf(msg.ranges[far]) and msg.ranges[far] > 0, msg.ranges[far])
        # stamps are simulated time at 20 Hz
        m2 = next_msg(scans, scans.count)
        periods = (m2.header.stamp - msg.header.stamp).to_sec() / 0.05
        self.assertGreaterEqual(periods, 0.99)
        self.assertLess(abs(periods - round(periods)), 0.02, periods)

    def test_laser(self):
        self.check_laser("libgazebo_ros_laser.so", "ray", "scan")

    def test_gpu_laser(self):
        self.check_laser("libgazebo_ros_gpu_laser.so", "gpu_ray", "/gpu/scan")

    # ---- IMU ---------------------------------------------------------------------------------
    def test_imu_sensor(self):
        xml = F.sensor_robot("<sensor name='imu_sensor' type='imu'><always_on>true</always_on>"
                             "<update_rate>100</update_rate><visualize>true</visualize><topic>imu</topic>"
                             "<plugin filename='libgazebo_ros_imu_sensor.so' name='imu_plugin'>"
                             "<topicName>imu</topicName><bodyName>sensor_link</bodyName>"
                             "<updateRateHZ>10.0</updateRateHZ><gaussianNoise>0.0</gaussianNoise>"
                             "<xyzOffset>0 0 0</xyzOffset><rpyOffset>0 0 0</rpyOffset>"
                             "<frameName>sensor_link</frameName></plugin><pose>0 0 0 0 0 0</pose></sensor>",
                             static=False)
        imu = Latest("/imu", Imu)
        self.spawn_urdf("imu_bot", xml, z=0.11)
        self.assertTrue(wait_until(lambda: imu.count >= 15, 60.0), "too few Imu messages")
        m = imu.get()
        self.assertEqual(m.header.frame_id, "sensor_link")
        self.assertLess(abs(m.linear_acceleration.z - 9.81), 0.01, m.linear_acceleration)
        self.assertLess(abs(m.angular_velocity.z), 1e-3)
        self.assertEqual(list(m.orientation_covariance), [0.0] * 9)

    def test_imu_model(self):
        extra = ("<gazebo><plugin name='imu_plugin' filename='libgazebo_ros_imu.so'><alwaysOn>true</alwaysOn>"
                 "<bodyName>base_link</bodyName><topicName>imu_data</topicName>"
                 "<serviceName>imu_service</serviceName>"
                 "<gaussianNoise>0.01</gaussianNoise><updateRate>50.0</updateRate></plugin></gazebo>")
        xml = F.sensor_robot("", static=False, extra=extra)
        imu = Latest("/imu_data", Imu)
        self.spawn_urdf("imu_bot", xml, z=0.11)
        self.assertTrue(wait_until(lambda: imu.count >= 50, 60.0), "too few Imu messages")
        m = imu.get()
        self.assertEqual(m.header.frame_id, "base_link")
        self.assertLess(abs(m.linear_acceleration.z - 9.81), 0.06)
        self.assertAlmostEqual(m.linear_acceleration_covariance[0], 1e-4)
        rospy.wait_for_service("/imu_service", 10.0)
        rospy.ServiceProxy("/imu_service", Empty)()

    # ---- Velodyne ----------------------------------------------------------------------------
    def test_velodyne(self):
        # a ring of 8 cones (cylinders) 4 m around the sensor
        for k in range(8):
            a = k * math.pi / 4 + 0.1
            self.spawn_sdf("cone%d" % k, F.static_shape("cone%d" % k, F.cylinder(0.3, 2.0), (0, 0, 0)),
                           x=4 * math.cos(a), y=4 * math.sin(a), z=1.0)
        xacro = os.path.join(_FIX, "velodyne_bot.urdf.xacro")
        xml = subprocess.check_output(["xacro", xacro], text=True)
        cloud = Latest("/velodyne_points2", PointCloud2)
        self.spawn_urdf("velodyne_bot", xml, z=0.1)
        msg = next_msg(cloud, 0, 60.0)
        self.assertIsNotNone(msg, "no PointCloud2 on /velodyne_points2")
        self.assertEqual(msg.header.frame_id, "velodyne2")
        self.assertEqual(msg.point_step, 22)
        self.assertEqual([(f.name, f.offset, f.datatype, f.count) for f in msg.fields],
                         [("x", 0, 7, 1), ("y", 4, 7, 1), ("z", 8, 7, 1), ("intensity", 12, 7, 1),
                          ("ring", 16, 4, 1), ("time", 18, 7, 1)])
        self.assertEqual(msg.height, 1)
        self.assertEqual(msg.row_step, msg.width * 22)
        self.assertTrue(msg.is_dense)
        dt = np.dtype({"names": ["x", "y", "z", "intensity", "ring", "time"],
                       "formats": ["<f4", "<f4", "<f4", "<f4", "<u2", "<f4"],
                       "offsets": [0, 4, 8, 12, 16, 18], "itemsize": 22})
        pts = np.frombuffer(msg.data, dtype=dt)
        self.assertEqual(len(pts), msg.width)
        self.assertTrue(set(np.unique(pts["ring"])) <= set(range(32)))
        # points on the cones (0.3 m radius, 4 m away, at the cone azimuths): every point near a
        # cone lies on its surface (within the 8 mm range noise), and every cone is seen
        azimuths = [k * math.pi / 4 + 0.1 for k in range(8)]
        centres = [(4 * math.cos(a), 4 * math.sin(a)) for a in azimuths]
        for k, (cx, cy) in enumerate(centres):
            d = np.hypot(pts["x"] - cx, pts["y"] - cy)
            near = (d < 0.6) & (pts["z"] > -(0.1 + 1.0 + 0.09081) + 0.05)   # not the ground around it
            self.assertGreater(near.sum(), 10, "cone %d not seen" % k)
            self.assertLess(np.abs(d[near] - 0.3).max(), 0.04, "cone %d: points off its surface" % k)
        # ground points: z of the lower lasers = -(sensor height) in the sensor frame
        ground = pts[(pts["ring"] == 0) & (np.hypot(pts["x"], pts["y"]) < 3.0)]
        self.assertGreater(len(ground), 100)
        self.assertLess(np.abs(ground["z"] + (0.1 + 1.0 + 0.09081)).max(), 0.04)

    # ---- GPS ---------------------------------------------------------------------------------
    def test_gps(self):
        extra = ("<gazebo><plugin name='novatel_gps_sim' filename='libhector_gazebo_ros_gps.so'>"
                 "<alwaysOn>1</alwaysOn><updateRate>10.0</updateRate><bodyName>base_link</bodyName>"
                 "<topicName>fix</topicName><velocityTopicName>fix_velocity</velocityTopicName>"
                 "<drift>5.0 5.0 5.0</drift><gaussianNoise>0.1 0.1 0.1</gaussianNoise>"
                 "<velocityDrift>0 0 0</velocityDrift>"
                 "<velocityGaussianNoise>0.1 0.1 0.1</velocityGaussianNoise>"
                 "</plugin></gazebo>")
        fix = Latest("/fix", NavSatFix)
        vel = Latest("/fix_velocity", Vector3Stamped)
        self.spawn_urdf("gps_bot", F.sensor_robot("", static=True, extra=extra), z=0.1)
        self.assertTrue(wait_until(lambda: fix.count >= 3 and vel.count >= 3, 60.0))
        m = fix.get()
        self.assertEqual(m.header.frame_id, "/world")
        self.assertEqual(list(m.position_covariance), [25.01, 0, 0, 0, 25.01, 0, 0, 0, 25.01])
        self.assertEqual(m.position_covariance_type, 2)
        self.assertEqual(m.status.status, 0)
        self.assertLess(abs(m.latitude - 49.9), 1e-3)        # within ~100 m of the reference
        self.assertLess(abs(m.longitude - 8.9), 2e-3)

    # ---- range finders (gazebo_ros_range, hector sonar, block laser) -------------------------
    def test_range(self):
        self.spawn_sdf("wall", F.static_shape("wall", F.box((0.2, 2.0, 1.0)), (0, 0, 0)), x=1.6, z=0.5)
        cone = F.ray_block(samples=5, min_angle=-0.1, max_angle=0.1, rmin=0.05, rmax=3.0, v_samples=3,
                           v_min=-0.05, v_max=0.05)
        sensors = ("<sensor type='ray' name='ir'><update_rate>20</update_rate>%s"
                   "<plugin name='ir' filename='libgazebo_ros_range.so'><topicName>range_ir</topicName>"
                   "<frameName>sensor_link</frameName><radiation>infrared</radiation><fov>0.2</fov></plugin>"
                   "</sensor>" % cone)
        sonar = ("<gazebo reference='base_link'><sensor type='ray' name='us'><update_rate>20</update_rate>%s"
                 "<plugin name='us' filename='libhector_gazebo_ros_sonar.so'><topicName>sonar</topicName>"
                 "<frameId>base_link</frameId></plugin></sensor>"
                 "<sensor type='ray' name='block'><update_rate>10</update_rate>%s"
                 "<plugin name='bl' filename='libgazebo_ros_block_laser.so'><topicName>block</topicName>"
                 "<frameName>base_link</frameName></plugin></sensor></gazebo>" % (cone, cone))
        ir, us, block = Latest("/range_ir", Range), Latest("/sonar", Range), Latest("/block", PointCloud)
        self.spawn_urdf("range_bot", F.sensor_robot(sensors, static=True, extra=sonar), z=0.1)
        self.assertTrue(wait_until(lambda: ir.count > 1 and us.count > 1 and block.count > 1, 60.0))
        m = ir.get()
        self.assertEqual((m.header.frame_id, m.radiation_type), ("sensor_link", Range.INFRARED))
        self.assertAlmostEqual(m.field_of_view, 0.2)
        self.assertAlmostEqual(m.range, 1.5, delta=0.01)       # the wall's face, from x = 0
        m = us.get()
        self.assertEqual((m.header.frame_id, m.radiation_type), ("base_link", Range.ULTRASOUND))
        self.assertAlmostEqual(m.field_of_view, 0.1)
        self.assertAlmostEqual(m.range, 1.5, delta=0.01)
        c = block.get()
        self.assertEqual(len(c.points), 15)
        self.assertEqual(len(c.channels[0].values), 15)
        self.assertTrue(all(abs(p.x - 1.5) < 0.01 for p in c.points))

    # ---- hector IMU and magnetometer ----------------------------------------------------------
    def test_hector(self):
        extra = ("<gazebo><plugin name='imu' filename='libhector_gazebo_ros_imu.so'>"
                 "<updateRate>50</updateRate>"
                 "<bodyName>base_link</bodyName><topicName>imu/data</topicName>"
                 "<accelGaussianNoise>0.01 0.01 0.01</accelGaussianNoise></plugin>"
                 "<plugin name='mag' filename='libhector_gazebo_ros_magnetic.so'><updateRate>20</updateRate>"
                 "<bodyName>base_link</bodyName><topicName>magnetic</topicName><magnitude>1.0</magnitude>"
                 "</plugin></gazebo>")
        imu, bias = Latest("/imu/data", Imu), Latest("/imu/data/bias", Imu)
        mag = Latest("/magnetic", Vector3Stamped)
        self.spawn_urdf("hector_bot", F.sensor_robot("", static=True, extra=extra), z=0.1)
        self.assertTrue(wait_until(lambda: imu.count > 5 and bias.count > 0 and mag.count > 1, 60.0))
        m = imu.get()
        self.assertEqual(m.header.frame_id, "base_link")
        self.assertAlmostEqual(m.linear_acceleration.z, 9.81, delta=0.1)
        self.assertAlmostEqual(m.linear_acceleration_covariance[0], 1e-4)
        rospy.wait_for_service("/imu/data/calibrate", 10.0)
        rospy.ServiceProxy("/imu/data/calibrate", Empty)()
        f = mag.get().vector
        self.assertAlmostEqual(f.x, 0.5, delta=1e-6)
        self.assertAlmostEqual(f.z, -math.sqrt(3) / 2, delta=1e-6)

    # ---- p3d ---------------------------------------------------------------------------------
    def test_p3d(self):
        extra = ("<gazebo><plugin name='p3d_base_controller' filename='libgazebo_ros_p3d.so'>"
                 "<alwaysOn>true</alwaysOn><updateRate>50.0</updateRate><bodyName>base_link</bodyName>"
                 "<topicName>ground_truth/state</topicName><gaussianNoise>0.0</gaussianNoise>"
                 "<frameName>world</frameName><xyzOffsets>0 0 0</xyzOffsets><rpyOffsets>0 0 0</rpyOffsets>"
                 "</plugin></gazebo>")
        odom = Latest("/ground_truth/state", Odometry)
        states = Latest("/gazebo/model_states", ModelStates)
        self.spawn_urdf("p3d_bot", F.sensor_robot("", static=False, extra=extra),
                        x=1.0, y=-2.0, z=0.5, yaw=0.7)
        self.assertTrue(wait_until(lambda: odom.count >= 5, 60.0))
        # compare at rest: odom is a 50 Hz sample, model_states the pose of the last step, so a
        # falling body would differ by up to 20 ms of its motion between the two

        def at_rest():
            t = odom.get().twist.twist
            return max(abs(t.linear.x), abs(t.linear.y), abs(t.linear.z),
                       abs(t.angular.x), abs(t.angular.y), abs(t.angular.z)) < 1e-3
        self.assertTrue(wait_until(at_rest, 60.0), "p3d_bot did not come to rest")
        self.gz.pause_physics()
        c = odom.count
        wait_until(lambda: odom.count > c, 2.0)   # nothing new once paused
        s = states.get()
        wait_until(lambda: states.get() is not s, 5.0)
        s = states.get()
        o = odom.get()
        k = list(s.name).index("p3d_bot")
        p = s.pose[k]
        self.assertEqual(o.header.frame_id, "world")
        self.assertEqual(o.child_frame_id, "base_link")
        for a, b in ((o.pose.pose.position.x, p.position.x), (o.pose.pose.position.y, p.position.y),
                     (o.pose.pose.position.z, p.position.z), (o.pose.pose.orientation.z, p.orientation.z),
                     (o.pose.pose.orientation.w, p.orientation.w)):
            self.assertAlmostEqual(a, b, places=3)
        self.gz.unpause_physics()

    # ---- bumper ------------------------------------------------------------------------------
    def test_bumper(self):
        sensor = ("<sensor name='plate_contact' type='contact'><always_on>true</always_on>"
                  "<update_rate>50</update_rate>"
                  "<contact><collision>sensor_link_collision</collision></contact>"
                  "<plugin name='bumper' filename='libgazebo_ros_bumper.so'><bumperTopicName>plate_bumper"
                  "</bumperTopicName><frameName>world</frameName></plugin></sensor>")
        bumper = Latest("/plate_bumper", ContactsState)
        self.spawn_urdf("bumper_bot", F.sensor_robot(sensor, static=True), z=0.1)
        # the sensor link's 5 cm cube top is at 0.1 + 0.15 + 0.025 = 0.275: drop a box on it
        self.spawn_sdf("weight", F.static_shape("weight", F.box((0.1, 0.1, 0.1)), (0, 0, 0))
                       .replace("<static>true</static>", "<static>false</static>")
                       .replace("<link name='link'>",
                                "<link name='link'><inertial><mass>0.5</mass></inertial>"),
                       z=0.33)
        ok = wait_until(lambda: bumper.get() is not None and any(
            "weight" in st.collision2_name for st in bumper.get().states), 60.0)
        self.assertTrue(ok, "the box resting on the sensor link is not reported")
        st = [s for s in bumper.get().states if "weight" in s.collision2_name][0]
        self.assertEqual(st.collision1_name, "bumper_bot::sensor_link::sensor_link_collision")
        self.assertGreater(len(st.contact_positions), 0)
        self.assertLess(abs(st.contact_positions[0].z - 0.275), 0.01)

        # once it rests, the contact forces on the sensor's link carry the 0.5 kg box's weight
        def weight_on_plate():
            m = bumper.get()
            s = [x for x in m.states if "weight" in x.collision2_name] if m is not None else []
            return s[0] if s and abs(s[0].total_wrench.force.z + 0.5 * 9.81) < 0.01 * 0.5 * 9.81 else None
        st = wait_until(weight_on_plate, 30.0)     # the state judged below (a later one may differ)
        self.assertTrue(st, "the contact forces on the plate do not settle at the box's weight: %s"
                        % [x.total_wrench for x in bumper.get().states])
        self.assertEqual(len(st.wrenches), len(st.contact_positions))
        self.assertAlmostEqual(sum(w.force.z for w in st.wrenches), st.total_wrench.force.z, places=9)

        # a contact only pushes: each contact's force along its normal has the sign of the whole
        # weight's along it (friction lies across the normal, so a normal tilted by 1e-8 rad gives
        # a contact's force a z of that order either way: the sign of z alone says nothing)
        def along(f, n):
            return f.x * n.x + f.y * n.y + f.z * n.z
        pulls = [(w.force, n) for w, n in zip(st.wrenches, st.contact_normals)
                 if along(w.force, n) * along(st.total_wrench.force, n) < -1e-12]
        self.assertFalse(pulls, "a contact force pulls (against the weight along its normal): %s" % pulls)

    # ---- force/torque on a joint ---------------------------------------------------------------
    def test_ft_sensor(self):
        # test/fixtures/force/ft_arm.urdf: a 2 kg load, centre 0.1 m out, on a vertical wrist joint;
        # gazebo_ros_ft_sensor (100 Hz, child frame, child_to_parent) and a force_torque sensor
        # (50 Hz, parent frame, parent_to_child) with the plugin inside
        with open(os.path.join(os.path.dirname(_FIX), "force", "ft_arm.urdf")) as f:
            urdf = f.read()
        ft = Latest("/ft_sensor", WrenchStamped)
        wrist = Latest("/wrist_ft", WrenchStamped)
        self.spawn_urdf("ft_arm", urdf, x=3.0)
        weight = 2.0 * 9.81
        ok = wait_until(lambda: ft.count > 2 and wrist.count > 2, 30.0)
        self.assertTrue(ok, "no WrenchStamped on /ft_sensor and /wrist_ft")
        m = ft.get()
        self.assertEqual(m.header.frame_id, "load")
        self.assertAlmostEqual(m.wrench.force.z, -weight, delta=0.01 * weight)
        self.assertAlmostEqual(m.wrench.torque.y, 0.1 * weight, delta=0.01 * 0.1 * weight)
        w = wrist.get()
        self.assertEqual(w.header.frame_id, "post")
        self.assertAlmostEqual(w.wrench.force.z, weight, delta=0.01 * weight)
        # the rates: 100 Hz and 50 Hz of simulated time (a message may be dropped on the way: every
        # gap is a whole number of periods, the smallest one period)
        for topic, period in (("/ft_sensor", 0.01), ("/wrist_ft", 0.02)):
            stamps = []
            sub = rospy.Subscriber(topic, WrenchStamped, lambda m: stamps.append(m.header.stamp.to_sec()),
                                   queue_size=100)
            self.assertTrue(wait_until(lambda: len(stamps) >= 30, 30.0), "%s: too few messages" % topic)
            sub.unregister()
            gaps = [b - a for a, b in zip(stamps, stamps[1:])]
            self.assertTrue(all(g > 0 and abs(g / period - round(g / period)) < 1e-4 for g in gaps),
                            "%s: stamps off the %g s grid: %s" % (topic, period, gaps))
            self.assertAlmostEqual(min(gaps), period, places=6)

    # ---- arm projects' plugins: grasp fix and mimic joint, loaded by the node from the URDF --------
    def test_arm_plugins(self):
        force = os.path.join(os.path.dirname(_FIX), "force")

        def read(name):
            with open(os.path.join(force, name)) as f:
                return f.read()
        clock = Latest("/clock", Clock)
        self.assertTrue(wait_until(lambda: clock.get() is not None, 10.0), "no /clock")

        def after(seconds):
            """Until that much simulated time has passed from the simulator's time now (the /clock
            message last taken here can be a simulated second old at real_time_factor 0)."""
            t0 = self.gz.sim_time()
            return wait_until(lambda: clock.get().clock.to_sec() >= t0 + seconds, 30.0)

        def z(link):
            return self.gz.get_link_state(link_name=link, reference_frame="").link_state.pose.position.z

        def effort(joint, f):
            self.gz.clear_joint_forces(joint_name="grasp_rig::" + joint)
            r = self.gz.apply_joint_effort(joint_name="grasp_rig::" + joint, effort=f,
                                           start_time=rospy.Time(0), duration=rospy.Duration(-1))
            self.assertTrue(r.success, r.status_message)
        # test/fixtures/force: the rig's fingers squeeze a slippery can (its friction carries 1 N of
        # its 2.9 N weight); after three gripping 20 Hz updates the grasp fix welds it to the palm
        self.spawn_urdf("grasp_rig", read("grasp_rig.urdf"), x=6.0)
        self.spawn_urdf("can", read("can.urdf"), x=6.0)
        self.assertTrue(after(0.3))
        effort("left_finger_joint", 5.0)
        effort("right_finger_joint", 5.0)
        self.assertTrue(after(0.4))
        effort("lift", 30.0)          # the palm goes up to its stop (0.3 m), the can with it
        self.assertTrue(wait_until(lambda: z("can::can") > 0.25, 30.0),
                        "the can did not go up with the palm (z %.3f): not attached" % z("can::can"))
        effort("left_finger_joint", -5.0)
        effort("right_finger_joint", -5.0)
        self.assertTrue(wait_until(lambda: z("can::can") < 0.05, 30.0),
                        "the can was not let go when the fingers opened (z %.3f)" % z("can::can"))

        # the left finger mimics the right one (-1, +0.05 rad): tipped over, the right one falls to
        # its stop at 0.8 rad and the left one follows to -0.75
        self.spawn_urdf("fingers", read("mimic_fingers.urdf"), x=-6.0)
        r = self.gz.set_model_configuration(model_name="fingers", urdf_param_name="",
                                            joint_names=["right_finger_joint"], joint_positions=[0.3])
        self.assertTrue(r.success, r.status_message)

        # the same with <hasPID>: its gains from the parameters the original reads
        rospy.set_param("/pid_fingers/gazebo_ros_control/pid_gains/left_finger_joint",
                        {"p": 5.0, "i": 20.0, "d": 0.02, "i_clamp": 0.5})
        pid = read("mimic_fingers.urdf").replace("<maxEffort>5.0</maxEffort>",
                                                 "<maxEffort>5.0</maxEffort><hasPID/>")
        r = self.gz.spawn_urdf_model(model_name="pid_fingers", model_xml=pid, robot_namespace="/pid_fingers",
                                     initial_pose=pose(x=-6.0, y=2.0), reference_frame="")
        self.assertTrue(r.success, r.status_message)
        r = self.gz.set_model_configuration(model_name="pid_fingers", urdf_param_name="",
                                            joint_names=["right_finger_joint"], joint_positions=[0.3])
        self.assertTrue(r.success, r.status_message)

        def q(model, j):
            return self.gz.get_joint_properties(joint_name=model + "::" + j).position[0]

        for model in ("fingers", "pid_fingers"):
            def followed():
                right, left = q(model, "right_finger_joint"), q(model, "left_finger_joint")
                return right > 0.79 and abs(left - (-right + 0.05)) < 1e-3
            self.assertTrue(wait_until(followed, 30.0), "%s: right %.4f left %.4f" % (
                model, q(model, "right_finger_joint"), q(model, "left_finger_joint")))

        # the PID's gains are live, as control_toolbox's Pid::init serves them: all zero, nothing
        # holds the follower at -0.75 any more and it sinks onto its stop at -0.8
        from dynamic_reconfigure.client import Client
        gains = Client("/pid_fingers/gazebo_ros_control/pid_gains/left_finger_joint", timeout=20)
        gains.update_configuration({"p": 0.0, "i": 0.0, "d": 0.0})
        self.assertTrue(wait_until(lambda: q("pid_fingers", "left_finger_joint") < -0.79, 30.0),
                        "left %.4f" % q("pid_fingers", "left_finger_joint"))


if __name__ == "__main__":
    _cases = ["test_" + c for c in CASE.split(",")]
    for _name in [n for n in vars(SensorPlugins) if n.startswith("test_") and n not in _cases]:
        delattr(SensorPlugins, _name)
    rospy.init_node("sensor_plugins_test")
    rostest.rosrun("modrob_sim", "sensor_plugins_" + CASE.replace(",", "_"), SensorPlugins)
