"""Simulated sensors as Gazebo's ROS plugins (docs/sensors.md).

Pure cores (no rospy; unit-testable on a bare physics World):

    ray_sensor   <sensor type="ray"/"gpu_ray"> geometry, ranges as Gazebo reports them
    raycast      batched ray casting on the physics' geoms (ODE from C; numpy baseline)
    laser        sensor_msgs/LaserScan fields (gazebo_ros_laser / gazebo_ros_gpu_laser)
    velodyne     PointCloud2 packing of velodyne_simulator (x y z intensity ring time, 22 bytes)
    imu          Gazebo's ImuSensor + gazebo_ros_imu_sensor, and the gazebo_ros_imu model plugin
    gps          hector_gazebo_ros_gps: flat-earth WGS84 and hector's drift model
    p3d          gazebo_ros_p3d ground truth
    contact      Gazebo's contact sensor + gazebo_ros_bumper

The ROS layer (``ros_plugins``) registers the plugin file names with the /gazebo node.
"""
