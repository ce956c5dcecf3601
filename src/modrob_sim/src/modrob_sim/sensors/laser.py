"""sensor_msgs/LaserScan as gazebo_ros_laser / gazebo_ros_gpu_laser fill it from a ray sensor.

gazebo_ros (Noetic) copies Gazebo's scan: angle_min/angle_max = the horizontal min/max angle,
angle_increment = the angle step, time_increment = 0 and scan_time = 0 (an instantaneous scan),
range_min/range_max = the <range> block, ranges = Gazebo's ranges (+inf nothing hit, -inf at or
below the minimum, see ray_sensor.py), intensities = the <laserRetro> of what was hit (0 if nothing). With a
<vertical> block of more than one sample gazebo_ros copies every range, rows one after the
other; so does this.
"""


def laser_fields(spec):
    """The constant LaserScan fields of a RaySpec (a dict of field -> value)."""
    return dict(angle_min=spec.h_min, angle_max=spec.h_max, angle_increment=spec.angle_step,
                time_increment=0.0, scan_time=0.0, range_min=spec.range_min,
                range_max=spec.range_max)
