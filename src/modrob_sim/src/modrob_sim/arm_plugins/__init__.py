"""Third-party Gazebo model plugins that arm projects load: roboticsgroup's mimic joint plugin
(``mimic_joint``) and gazebo-pkgs' grasp fix (``grasp_fix``). Registered with the /gazebo node
through ``modrob_sim.gazebo_ros.plugins.PLUGIN_MODULES``; docs/plugins.md and docs/sensors.md."""
