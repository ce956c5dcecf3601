"""The ROS layer of the simulated sensors: registers Gazebo's plugin file names with the /gazebo
node (modrob_sim.gazebo_ros.plugins) and publishes what the pure cores measure.

The plugins follow the node's plugin contract (docs/plugins.md: ModelPlugin / SensorPlugin, hooks
in the simulation loop thread, a seed per plugin). Each decimates to its own rate in simulated
time and measures only when its topic has subscribers (a sensor nobody listens to costs its
bookkeeping only); big messages (LaserScan, PointCloud2) are built and serialised on the node's
publishing thread (publish_later) from what the hook took at its instant: the ray sensors' rays
are cast there too, on the scene the hook prepared (RaySensor.prepare_scan).
"""
import functools
import math
import threading

import rospy
from geometry_msgs.msg import Point32, Vector3, Vector3Stamped, Wrench, WrenchStamped
from gazebo_msgs.msg import ContactsState, ContactState
from nav_msgs.msg import Odometry
from sensor_msgs.msg import (ChannelFloat32, Imu, LaserScan, MagneticField, NavSatFix, PointCloud,
                             PointCloud2, PointField, Range)
from std_srvs.srv import Empty, EmptyResponse

from modrob_sim.gazebo_ros.plugin_base import ModelPlugin, RateGate, SensorPlugin
from modrob_sim.gazebo_ros.plugins import register_plugin
from modrob_sim.physics.due import IdleLook, is_due

from . import laser, velodyne
from .contact import ContactSensor
from .core import where
from .errors import SensorConfigError
from .force_torque import JointWrench
from .gps import HectorGps
from .hector import HectorImu, HectorMagnetic
from .imu import ImuModelPlugin, ImuSensor, covariance
from .p3d import P3d
from .range_sensor import BlockLaser, GazeboRange, HectorSonar
from .ray_sensor import RaySensor
from .sdf import Params, join_ns, tf_resolve


def plugin_namespace(spec, context):
    """The namespace a plugin's topics go under (its robotNamespace, else the spawn's)."""
    ns = spec.robot_namespace if spec.robot_namespace is not None else getattr(context, "robot_namespace", "")
    return ns or ""


def tf_prefix(ns):
    """The tf_prefix parameter in the plugin's namespace ("" without a ROS node, e.g. in tests)."""
    if not rospy.core.is_initialized():
        return ""
    try:
        return rospy.get_param(join_ns(ns, "tf_prefix"), "")
    except (KeyError, OSError, rospy.ROSException):
        return ""


def stamp(t):
    return rospy.Time.from_sec(max(0.0, t))


def _check_type(plugin, types):
    if plugin.sensor_type not in types:
        raise SensorConfigError("%s: needs a sensor of type %s, not '%s'"
                                % (plugin.name, " or ".join(types), plugin.sensor_type))


def _reseed(context):
    """reset() follows reset_simulation (time back to 0: noise restarts from the seed) or
    reset_world (time kept: the noise goes on)."""
    return context.world.time == 0.0


def _on_grid_from(rate, until):
    """The first time of ``rate``'s grid (its ``next_time`` plus whole ``period``s) from ``until``
    on: the update times stay those of a sensor that never idled."""
    nxt = rate.next_time
    if rate.period <= 0.0 or nxt == -math.inf or nxt >= until:
        return max(nxt, until) if rate.period <= 0.0 else nxt
    return nxt + math.ceil((until - nxt) / rate.period - 1e-9) * rate.period


class _Publishing(object):
    """Publisher gating shared by the sensor plugins: a sensor that keeps no history (the laser,
    the Velodyne, a noiseless IMU) idles while nobody listens, looking for a subscriber only every
    IDLE_LOOK of simulated time (physics.due.IdleLook)."""

    pubs = ()

    def __init__(self, *args, **kw):
        super(_Publishing, self).__init__(*args, **kw)
        self.idle = IdleLook()

    def active(self):
        return any(p.has_subscribers for p in self.pubs)

    def look(self, t):
        """``active()``, remembering an idle look at simulated time ``t``."""
        return self.idle.look(t, self.active())

    def idle_due(self, rate, due):
        """A hook's due time ``due`` (on ``rate``'s grid), or while idle the next look's."""
        return due if self.idle.until is None else _on_grid_from(rate, self.idle.until)

    def shutdown(self):
        for p in self.pubs:
            p.unregister()
        self.pubs = ()


class LaserPlugin(_Publishing, SensorPlugin):
    """libgazebo_ros_laser.so / libgazebo_ros_gpu_laser.so -> sensor_msgs/LaserScan."""

    def load(self, model, spec, context):
        _check_type(self, ("ray", "gpu_ray"))
        w = where(model, spec.link, spec.filename, spec.sensor)
        p = Params(spec.element, w)
        self.ray = RaySensor(context.world, model, spec.link, spec.sensor, spec.filename, seed=context.seed)
        ns = plugin_namespace(spec, context)
        self.topic = join_ns(ns, p.string("topicName", "/world"))
        self.frame = tf_resolve(tf_prefix(ns), p.string("frameName", "/world"))
        self.fields = laser.laser_fields(self.ray.spec)
        self.pub = context.advertise(self.topic, LaserScan, queue_size=2)
        self.pubs = (self.pub,)
        rospy.loginfo("%s: LaserScan on %s (frame %s, %d x %d rays, %g Hz)"
                      % (w, self.topic, self.frame, self.ray.spec.count, self.ray.spec.v_count,
                         self.update_rate))

    def reset(self):
        SensorPlugin.reset(self)
        if _reseed(self.context):
            self.ray.reseed()

    def after_due(self):
        return self.idle_due(self.gate, SensorPlugin.after_due(self))

    def sense(self, t):
        if not self.look(t):
            return
        self.pub.publish_later(functools.partial(self._message, t, self.ray.prepare_scan()))

    def _message(self, t, scan):
        ranges, intensities = scan()        # the rays, in the publishing thread (RaySensor.prepare_scan)
        msg = LaserScan()
        msg.header.stamp = stamp(t)
        msg.header.frame_id = self.frame
        for k, v in self.fields.items():
            setattr(msg, k, v)
        msg.ranges = ranges.astype("float32").tolist()
        msg.intensities = intensities.astype("float32").tolist()
        return msg


class VelodynePlugin(_Publishing, SensorPlugin):
    """libgazebo_ros_velodyne_laser.so / _gpu_laser.so -> sensor_msgs/PointCloud2 (22-byte points)."""

    def load(self, model, spec, context):
        _check_type(self, ("ray", "gpu_ray"))
        w = where(model, spec.link, spec.filename, spec.sensor)
        p = Params(spec.element, w)
        self.ray = RaySensor(context.world, model, spec.link, spec.sensor, spec.filename, seed=context.seed)
        self.cfg = velodyne.VelodyneConfig(p, self.ray.spec)
        ns = spec.robot_namespace or "/"
        self.topic = join_ns(ns, p.string("topicName", "/points"))
        prefix = tf_prefix(ns) if ns in ("/", "") else ns
        self.frame = tf_resolve(prefix.strip("/"), p.string("frameName", "/world"))
        self.fields = [PointField(name=n, offset=o, datatype=d, count=c) for n, o, d, c in velodyne.FIELDS]
        self.pub = context.advertise(self.topic, PointCloud2, queue_size=1)
        self.pubs = (self.pub,)
        rospy.loginfo("%s: Velodyne PointCloud2 on %s (frame %s, %d lasers x %d samples, %g Hz)"
                      % (w, self.topic, self.frame, self.ray.spec.v_count, self.ray.spec.count,
                         self.update_rate))

    def reset(self):
        SensorPlugin.reset(self)
        if _reseed(self.context):
            self.ray.reseed()

    def after_due(self):
        return self.idle_due(self.gate, SensorPlugin.after_due(self))

    def sense(self, t):
        if not self.look(t):
            return
        scan = self.ray.prepare_scan()
        sigma = self.cfg.gaussian_noise
        noise = self.ray.rng.normal(0.0, sigma, self.ray.ray_count) if sigma else None
        self.pub.publish_later(functools.partial(self._message, t, scan, noise))

    def _message(self, t, scan, noise):
        ranges, intensities = scan()        # the rays, in the publishing thread (RaySensor.prepare_scan)
        data, width, height, row_step, dense = velodyne.pack_cloud(
            self.ray.spec, self.cfg, ranges, intensities, noise=noise)
        msg = PointCloud2()
        msg.header.stamp = stamp(t)
        msg.header.frame_id = self.frame
        msg.fields = self.fields
        msg.is_bigendian = False
        msg.point_step = velodyne.POINT_STEP
        msg.width, msg.height, msg.row_step, msg.is_dense = width, height, row_step, dense
        msg.data = data
        return msg


def _fill_imu(msg, orientation, angular_velocity, linear_acceleration):
    o, w, a = msg.orientation, msg.angular_velocity, msg.linear_acceleration
    o.x, o.y, o.z, o.w = orientation
    w.x, w.y, w.z = angular_velocity
    a.x, a.y, a.z = linear_acceleration


def _imu_msg(r, frame, t, sigma):
    msg = Imu()
    msg.header.stamp = stamp(t)
    msg.header.frame_id = frame
    _fill_imu(msg, r.orientation, r.angular_velocity, r.linear_acceleration)
    c = covariance(sigma)
    msg.orientation_covariance = c
    msg.angular_velocity_covariance = c
    msg.linear_acceleration_covariance = c
    return msg


class ImuSensorPlugin(_Publishing, SensorPlugin):
    """libgazebo_ros_imu_sensor.so on a <sensor type="imu">."""

    def load(self, model, spec, context):
        _check_type(self, ("imu",))
        self.imu = ImuSensor(context.world, model, spec.link, spec.sensor, spec.element, spec.filename,
                             seed=context.seed)
        ns = plugin_namespace(spec, context)
        self.topic = join_ns(ns, self.imu.topic)
        self.frame = self.imu.frame
        self.pub = context.advertise(self.topic, Imu, queue_size=10)
        self.pubs = (self.pub,)
        rospy.loginfo("%s: Imu on %s (frame %s, %g Hz)"
                      % (self.imu.where, self.topic, self.frame, self.imu.publish_rate))

    def reset(self):
        SensorPlugin.reset(self)
        self.imu.reset(_reseed(self.context))
        self.idle.reset()

    def after_step(self, t, dt):
        imu = self.imu
        if self.idle.until is not None:
            if not is_due(t, self.idle.until) or not is_due(t, imu.sensor_rate.next_time):
                return          # idle, or (called early) not an update time of the sensor
            if not self.look(t):
                imu.sensor_rate.due(t)          # the update times go on
                return
            # back from idle: this reading starts the velocity history, the next one publishes
            imu.core.reset()
            imu.step(t)
            return
        r = imu.step(t)         # keeps the velocity history while someone listens
        if r is None:
            return
        if imu.noise > 0.0:
            # a noisy IMU takes every reading: its noise stream is the same whoever listens
            if self.active():
                self.pub.publish(_imu_msg(r, self.frame, t, imu.noise))
        elif self.look(t):
            self.pub.publish(_imu_msg(r, self.frame, t, imu.noise))

    def after_due(self):
        return self.idle_due(self.imu.sensor_rate, self.imu.sensor_rate.next_time)


class ImuModelRosPlugin(_Publishing, ModelPlugin):
    """libgazebo_ros_imu.so (model plugin) with its serviceName (std_srvs/Empty, a no-op
    calibration as in gazebo_ros_imu)."""

    def load(self, model, spec, context):
        w = where(model, None, spec.filename)
        self.imu = ImuModelPlugin(context.world, model, spec.element, w, seed=context.seed)
        ns = plugin_namespace(spec, context)
        self.topic = join_ns(ns, self.imu.topic)
        self.frame = self.imu.frame
        self.pub = context.advertise(self.topic, Imu, queue_size=10)
        self.pubs = (self.pub,)
        self.srv = rospy.Service(join_ns(ns, self.imu.service), Empty, lambda req: EmptyResponse())
        rospy.loginfo("%s: Imu on %s (link %s)" % (w, self.topic, self.imu.link.name))

    def reset(self):
        self.imu.reset(_reseed(self.context))

    def after_step(self, t, dt):
        r = self.imu.step(t)
        if r is not None and self.active():
            self.pub.publish(_imu_msg(r, self.frame, t, self.imu.noise))

    def after_due(self):
        return self.imu.rate.next_time

    def shutdown(self):
        _Publishing.shutdown(self)
        self.srv.shutdown()


class GpsPlugin(_Publishing, ModelPlugin):
    """libhector_gazebo_ros_gps.so -> sensor_msgs/NavSatFix + geometry_msgs/Vector3Stamped."""

    def load(self, model, spec, context):
        w = where(model, None, spec.filename)
        self.gps = HectorGps(context.world, model, spec.element, w, seed=context.seed)
        ns = plugin_namespace(spec, context)
        self.fix_pub = context.advertise(join_ns(ns, self.gps.topic), NavSatFix, queue_size=10)
        self.vel_pub = context.advertise(join_ns(ns, self.gps.velocity_topic), Vector3Stamped, queue_size=10)
        self.pubs = (self.fix_pub, self.vel_pub)
        rospy.loginfo("%s: NavSatFix on %s, velocity on %s" % (w, self.fix_pub.name, self.vel_pub.name))

    def reset(self):
        self.gps.reset(_reseed(self.context))

    def after_due(self):
        return self.gps.rate.next_time

    def after_step(self, t, dt):
        f = self.gps.step(t)       # the error processes run whether or not anyone listens
        if f is None or not self.active():
            return
        fix = NavSatFix()
        fix.header.stamp = stamp(t)
        fix.header.frame_id = self.gps.frame_id
        fix.status.status = self.gps.status
        fix.status.service = self.gps.service
        fix.latitude, fix.longitude, fix.altitude = f.latitude, f.longitude, f.altitude
        fix.position_covariance = f.covariance
        fix.position_covariance_type = NavSatFix.COVARIANCE_TYPE_DIAGONAL_KNOWN
        vel = Vector3Stamped()
        vel.header = fix.header
        vel.vector.x, vel.vector.y, vel.vector.z = f.velocity
        self.fix_pub.publish(fix)
        self.vel_pub.publish(vel)


class P3dPlugin(_Publishing, ModelPlugin):
    """libgazebo_ros_p3d.so -> nav_msgs/Odometry."""

    def load(self, model, spec, context):
        w = where(model, None, spec.filename)
        self.p3d = P3d(context.world, model, spec.element, w, seed=context.seed)
        ns = plugin_namespace(spec, context)
        self.topic = join_ns(ns, self.p3d.topic)
        self.frame = tf_resolve(tf_prefix(ns), self.p3d.frame)
        self.pub = context.advertise(self.topic, Odometry, queue_size=10)
        self.pubs = (self.pub,)
        rospy.loginfo("%s: Odometry of %s on %s" % (w, self.p3d.body, self.topic))

    def reset(self):
        self.p3d.reset(_reseed(self.context))

    def after_due(self):
        return self.p3d.rate.next_time

    def after_step(self, t, dt):
        # the rate keeps its grid whether or not anyone listens (a due time of its own), but the
        # pose is only taken (and noise only drawn) for a subscriber
        s = self.p3d.step(t, measure=self.active())
        if s is None:
            return
        pos, rot, v, w = s
        msg = Odometry()
        msg.header.stamp = stamp(t)
        msg.header.frame_id = self.frame
        msg.child_frame_id = self.p3d.body
        pp = msg.pose.pose
        pp.position.x, pp.position.y, pp.position.z = pos
        pp.orientation.x, pp.orientation.y, pp.orientation.z, pp.orientation.w = rot
        msg.twist.twist.linear.x, msg.twist.twist.linear.y, msg.twist.twist.linear.z = v
        msg.twist.twist.angular.x, msg.twist.twist.angular.y, msg.twist.twist.angular.z = w
        c = self.p3d.covariance()
        msg.pose.covariance = c
        msg.twist.covariance = c
        self.pub.publish(msg)


class BumperPlugin(_Publishing, SensorPlugin):
    """libgazebo_ros_bumper.so on a <sensor type="contact"> -> gazebo_msgs/ContactsState."""

    def load(self, model, spec, context):
        _check_type(self, ("contact",))
        self.contact = ContactSensor(context.world, model, spec.link, spec.sensor, spec.element,
                                     spec.filename)
        ns = plugin_namespace(spec, context)
        self.topic = join_ns(ns, self.contact.topic)
        self.frame = self.contact.frame
        self.pub = context.advertise(self.topic, ContactsState, queue_size=10)
        self.pubs = (self.pub,)
        rospy.loginfo("%s: ContactsState on %s" % (self.contact.where, self.topic))

    def sense(self, t):
        pairs = self.contact.contacts()     # also keeps touching bodies awake: always run
        if not self.active():
            return
        msg = ContactsState()
        msg.header.stamp = stamp(t)
        msg.header.frame_id = self.frame
        for k, pair in enumerate(pairs.values()):
            st = ContactState()
            st.info = "Debug:  i:(%d/%d)     my geom:%s   other geom:%s" % (
                k, len(pairs), pair.collision1, pair.collision2)
            st.collision1_name = pair.collision1
            st.collision2_name = pair.collision2
            for pos, n, d, f, tq in zip(pair.positions, pair.normals, pair.depths, pair.forces, pair.torques):
                st.contact_positions.append(Vector3(*pos))
                st.contact_normals.append(Vector3(*n))
                st.depths.append(d)
                st.wrenches.append(Wrench(Vector3(*f), Vector3(*tq)))
            f, tq = pair.total()
            st.total_wrench = Wrench(Vector3(*f), Vector3(*tq))
            msg.states.append(st)
        self.pub.publish(msg)


class _FtPublishing(_Publishing):
    """What both forms of libgazebo_ros_ft_sensor.so share: the WrenchStamped with noise."""

    def _advertise(self, spec, context, topic, frame):
        ns = plugin_namespace(spec, context)
        self.frame = tf_resolve(tf_prefix(ns), frame)
        self.noise = self.param("gaussianNoise", 0.0, float)
        if self.noise < 0:
            raise SensorConfigError("%s: <gaussianNoise> must not be negative" % self.name)
        self.pub = context.advertise(join_ns(ns, topic), WrenchStamped, queue_size=1)
        self.pubs = (self.pub,)
        rospy.loginfo("%s: WrenchStamped of joint '%s' in frame '%s' on %s"
                      % (self.name, self.ft.joint.name, self.frame, self.pub.name))

    def publish_wrench(self, t):
        (fx, fy, fz), (tx, ty, tz) = self.ft.read()
        msg = WrenchStamped()
        msg.header.stamp = stamp(t)
        msg.header.frame_id = self.frame
        n = [self.rng.gauss(0.0, self.noise) for _ in range(6)] if self.noise else (0.0,) * 6
        msg.wrench.force = Vector3(fx + n[0], fy + n[1], fz + n[2])
        msg.wrench.torque = Vector3(tx + n[3], ty + n[4], tz + n[5])
        self.pub.publish(msg)


class FtModelPlugin(_FtPublishing, ModelPlugin):
    """libgazebo_ros_ft_sensor.so as gazebo_plugins has it: a model plugin naming <jointName>,
    publishing on <topicName> what the joint transmits, child link frame, child_to_parent."""

    def load(self, model, spec, context):
        joint_name = self.param("jointName")
        topic = self.param("topicName")
        joint = model.joints.get(joint_name)
        if joint is None:
            raise SensorConfigError("%s: <jointName> '%s' is not a joint of the model (joints: %s)"
                                    % (self.name, joint_name, ", ".join(model.joints)))
        self.ft = JointWrench(joint, self.name)
        rate = self.param("updateRate", 0.0, float)
        if rate < 0:
            raise SensorConfigError("%s: <updateRate> must not be negative" % self.name)
        self.gate = RateGate(rate)
        self._advertise(spec, context, topic, joint.child)

    def after_due(self):
        return self.gate.next_time

    def after_step(self, t, dt):
        if self.gate.due(t) and self.active():
            self.publish_wrench(t)

    def reset(self):
        self.gate.reset()


class FtSensorPlugin(_FtPublishing, SensorPlugin):
    """libgazebo_ros_ft_sensor.so inside a <sensor type="force_torque"> (on a joint): the sensor's
    <update_rate>, <force_torque><frame> and <measure_direction>; <topicName> (default
    ``<sensor name>/wrench``), <frameName> (default: the link of the chosen frame, or the sensor's
    name for frame 'sensor'), <gaussianNoise>. The joint is the one whose child the sensor's link
    is (the joint itself for <gazebo reference="joint">)."""

    def load(self, model, spec, context):
        _check_type(self, ("force_torque",))
        joint = self.link.parent_joint
        if joint is None:
            raise SensorConfigError("%s: sensor '%s' is on link '%s', which hangs on no joint: put the "
                                    "force_torque sensor on a joint (<gazebo reference=\"joint\">)"
                                    % (self.name, self.sensor_name, self.link.name))
        ft = self.sensor.find("force_torque")
        frame = self.param("frame", "child", element=ft) if ft is not None else "child"
        direction = self.param("measure_direction", "child_to_parent", element=ft) if ft is not None \
            else "child_to_parent"
        self.ft = JointWrench(joint, self.name, frame, direction, self.sensor_pose)
        default_frame = {"child": joint.child, "parent": joint.parent, "sensor": self.sensor_name}[frame]
        topic = self.param("topicName", "%s/wrench" % (self.sensor_name or joint.name))
        self._advertise(spec, context, topic, self.param("frameName", default_frame))

    def sense(self, t):
        if self.active():
            self.publish_wrench(t)


def ft_sensor_plugin(model, spec, context):
    """libgazebo_ros_ft_sensor.so: a model plugin (gazebo_plugins), or inside a force_torque
    sensor (as gazebo_ros 2 has it)."""
    cls = FtSensorPlugin if spec.sensor is not None else FtModelPlugin
    return cls(model, spec, context)


class RangePlugin(_Publishing, SensorPlugin):
    """libgazebo_ros_range.so on a ray sensor -> sensor_msgs/Range (the nearest ray)."""

    def load(self, model, spec, context):
        _check_type(self, ("ray", "gpu_ray"))
        w = where(model, spec.link, spec.filename, spec.sensor)
        self.ray = RaySensor(context.world, model, spec.link, spec.sensor, spec.filename, seed=context.seed)
        self.core = GazeboRange(self.ray, spec.element, w)
        ns = plugin_namespace(spec, context)
        self.frame = tf_resolve(tf_prefix(ns), self.core.frame)
        self.pub = context.advertise(join_ns(ns, self.core.topic), Range, queue_size=1)
        self.pubs = (self.pub,)
        rospy.loginfo("%s: Range (%s) on %s" % (w, self.core.radiation, self.pub.name))

    def reset(self):
        SensorPlugin.reset(self)
        self.core.rate.reset()
        if _reseed(self.context):
            self.ray.reseed()

    def sense(self, t):
        if not self.active() or not self.core.rate.due(t):
            return
        s = self.ray.spec
        msg = Range()
        msg.header.stamp = stamp(t)
        msg.header.frame_id = self.frame
        msg.radiation_type = Range.ULTRASOUND if self.core.radiation == "ultrasound" else Range.INFRARED
        msg.field_of_view = self.core.fov
        msg.min_range, msg.max_range = s.range_min, s.range_max
        msg.range = self.core.read()
        self.pub.publish(msg)


class HectorSonarPlugin(_Publishing, SensorPlugin):
    """libhector_gazebo_ros_sonar.so on a ray sensor -> sensor_msgs/Range (ULTRASOUND)."""

    def load(self, model, spec, context):
        _check_type(self, ("ray", "gpu_ray"))
        w = where(model, spec.link, spec.filename, spec.sensor)
        self.ray = RaySensor(context.world, model, spec.link, spec.sensor, spec.filename, seed=context.seed)
        self.core = HectorSonar(self.ray, spec.element, w)
        ns = plugin_namespace(spec, context)
        self.pub = context.advertise(join_ns(ns, self.core.topic), Range, queue_size=1)
        self.pubs = (self.pub,)
        period = self.core.rate.period
        rospy.loginfo("%s: Range (sonar) on %s at %g Hz"
                      % (w, self.pub.name, 1.0 / period if period else 0.0))

    def reset(self):
        SensorPlugin.reset(self)
        if _reseed(self.context):
            self.ray.reseed()
        self.core.reset()

    def after_due(self):
        return self.core.rate.next_time

    def after_step(self, t, dt):
        if not self.core.rate.due(t):
            return
        r = self.core.read(t)      # the drift runs whether or not anyone listens
        if not self.active():
            return
        s = self.ray.spec
        msg = Range()
        msg.header.stamp = stamp(t)
        msg.header.frame_id = self.core.frame_id
        msg.radiation_type = Range.ULTRASOUND
        msg.field_of_view = self.core.fov
        msg.min_range, msg.max_range = s.range_min, s.range_max
        msg.range = r
        self.pub.publish(msg)


class BlockLaserPlugin(_Publishing, SensorPlugin):
    """libgazebo_ros_block_laser.so on a ray sensor -> sensor_msgs/PointCloud."""

    def load(self, model, spec, context):
        _check_type(self, ("ray", "gpu_ray"))
        w = where(model, spec.link, spec.filename, spec.sensor)
        self.ray = RaySensor(context.world, model, spec.link, spec.sensor, spec.filename, seed=context.seed)
        self.core = BlockLaser(self.ray, spec.element, w)
        ns = plugin_namespace(spec, context)
        self.frame = tf_resolve(tf_prefix(ns), self.core.frame)
        self.pub = context.advertise(join_ns(ns, self.core.topic), PointCloud, queue_size=1)
        self.pubs = (self.pub,)
        rospy.loginfo("%s: PointCloud on %s (%d rays)" % (w, self.pub.name, len(self.core._dirs)))

    def reset(self):
        SensorPlugin.reset(self)
        self.core.rate.reset()
        if _reseed(self.context):
            self.ray.reseed()

    def sense(self, t):
        if not self.active() or not self.core.rate.due(t):
            return
        points, intensities = self.core.read()
        self.pub.publish_later(lambda: self._message(t, points, intensities))

    def _message(self, t, points, intensities):
        msg = PointCloud()
        msg.header.stamp = stamp(t)
        msg.header.frame_id = self.frame
        msg.points = [Point32(float(x), float(y), float(z)) for x, y, z in points]
        msg.channels = [ChannelFloat32(name="", values=intensities.tolist())]
        return msg


def _imu_covariances(msg, covariances):
    msg.orientation_covariance, msg.angular_velocity_covariance, msg.linear_acceleration_covariance = \
        covariances


class HectorImuPlugin(_Publishing, ModelPlugin):
    """libhector_gazebo_ros_imu.so -> sensor_msgs/Imu on topicName, the biases on biasTopicName,
    std_srvs/Empty serviceName (calibrate: the rate drift back to zero)."""

    def load(self, model, spec, context):
        w = where(model, None, spec.filename)
        self.imu = HectorImu(context.world, model, spec.element, w, seed=context.seed)
        self._lock = threading.Lock()
        self._calibrate = False
        ns = plugin_namespace(spec, context)
        self.pub = context.advertise(join_ns(ns, self.imu.topic), Imu, queue_size=10) \
            if self.imu.topic else None
        self.bias_pub = context.advertise(join_ns(ns, self.imu.bias_topic), Imu, queue_size=10) \
            if self.imu.bias_topic else None
        self.pubs = tuple(p for p in (self.pub, self.bias_pub) if p is not None)
        self.srv = rospy.Service(join_ns(ns, self.imu.service), Empty, self._on_calibrate) \
            if self.imu.service else None
        rospy.loginfo("%s: Imu on %s (link %s)"
                      % (w, self.pub.name if self.pub else "(none)", self.imu.link.name))

    def _on_calibrate(self, req):
        with self._lock:
            self._calibrate = True
        return EmptyResponse()

    def reset(self):
        self.imu.reset(_reseed(self.context))

    def after_due(self):
        return self.imu.timer.next_time

    def after_step(self, t, dt):
        with self._lock:
            calibrate, self._calibrate = self._calibrate, False
        if calibrate:
            self.imu.calibrate()
        r = self.imu.step(t)       # the drifts run whether or not anyone listens
        if r is None or not self.active():
            return
        msg = Imu()
        msg.header.stamp = stamp(t)
        msg.header.frame_id = self.imu.frame_id
        _fill_imu(msg, r.orientation, r.angular_velocity, r.linear_acceleration)
        _imu_covariances(msg, self.imu.covariances())
        if self.pub is not None:
            self.pub.publish(msg)
        if self.bias_pub is not None:
            bias = Imu()
            bias.header = msg.header
            _fill_imu(bias, r.bias_orientation, r.rate_bias, r.accel_bias)
            self.bias_pub.publish(bias)

    def shutdown(self):
        _Publishing.shutdown(self)
        if self.srv is not None:
            self.srv.shutdown()


class HectorMagneticPlugin(_Publishing, ModelPlugin):
    """libhector_gazebo_ros_magnetic.so -> geometry_msgs/Vector3Stamped (or
    sensor_msgs/MagneticField with useMagneticFieldMsgs) on topicName."""

    def load(self, model, spec, context):
        w = where(model, None, spec.filename)
        self.mag = HectorMagnetic(context.world, model, spec.element, w, seed=context.seed)
        ns = plugin_namespace(spec, context)
        kind = MagneticField if self.mag.use_magnetic_field_msgs else Vector3Stamped
        self.pub = context.advertise(join_ns(ns, self.mag.topic), kind, queue_size=1)
        self.pubs = (self.pub,)
        rospy.loginfo("%s: %s on %s" % (w, kind.__name__, self.pub.name))

    def reset(self):
        self.mag.reset(_reseed(self.context))

    def after_due(self):
        return self.mag.timer.next_time

    def after_step(self, t, dt):
        field = self.mag.step(t)
        if field is None or not self.active():
            return
        if self.mag.use_magnetic_field_msgs:
            msg = MagneticField()
            vec = msg.magnetic_field
        else:
            msg = Vector3Stamped()
            vec = msg.vector
        msg.header.stamp = stamp(t)
        msg.header.frame_id = self.mag.frame_id
        vec.x, vec.y, vec.z = field
        self.pub.publish(msg)


PLUGINS = {
    "libgazebo_ros_laser.so": LaserPlugin,
    "libgazebo_ros_gpu_laser.so": LaserPlugin,
    "libgazebo_ros_velodyne_laser.so": VelodynePlugin,
    "libgazebo_ros_velodyne_gpu_laser.so": VelodynePlugin,
    "libgazebo_ros_imu_sensor.so": ImuSensorPlugin,
    "libgazebo_ros_imu.so": ImuModelRosPlugin,
    "libhector_gazebo_ros_gps.so": GpsPlugin,
    "libgazebo_ros_p3d.so": P3dPlugin,
    "libgazebo_ros_bumper.so": BumperPlugin,
    "libgazebo_ros_ft_sensor.so": ft_sensor_plugin,
    "libgazebo_ros_range.so": RangePlugin,
    "libgazebo_ros_block_laser.so": BlockLaserPlugin,
    "libhector_gazebo_ros_sonar.so": HectorSonarPlugin,
    "libhector_gazebo_ros_imu.so": HectorImuPlugin,
    "libhector_gazebo_ros_magnetic.so": HectorMagneticPlugin,
}

for _name, _cls in PLUGINS.items():
    register_plugin(_name, _cls)
