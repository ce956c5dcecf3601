"""The Polaris' dimensions as the seed's URDF gives them (appendix 4, figure 12)."""

WHEEL_RADIUS = 0.32          # m
WHEEL_WIDTH = 0.23           # m
WHEELBASE = 1.88             # m: rear axle (x = -0.85) to the steering pivots (x = 1.03), chassis frame
STEER_TRACK = 1.0            # m: between the steering pivots (y = +-0.5); the wheel axes pass through them
REAR_TRACK_CENTRES = 1.2     # m: between the rear wheel centres (y = +-0.6)
# The wheels are rigid cylinders with the seed's 0.05 rad camber (roll 1.52 rad instead of pi/2):
# each touches the ground at the inner edge of its tread, 0.115 m inside its centre, so the
# wheels roll on circles 0.97 m apart. The Ackermann node uses that track for the wheel rates
# (with 1.2 m the velocity loops fight each other by ~0.07 rad/s in a 5 m turn).
REAR_TRACK = REAR_TRACK_CENTRES - WHEEL_WIDTH
STEER_LIMIT = 0.8727         # rad: the steering joints' limit

JOINTS = {
    "steer_left": "polaris_ranger_ev__front_left_steering_joint",
    "steer_right": "polaris_ranger_ev__front_right_steering_joint",
    "rear_left": "polaris_ranger_ev__rear_left_wheel_joint",
    "rear_right": "polaris_ranger_ev__rear_right_wheel_joint",
    "front_left": "polaris_ranger_ev__front_left_wheel_joint",
    "front_right": "polaris_ranger_ev__front_right_wheel_joint",
}
CONTROLLERS = {
    "steer_left": "front_left_steering_position_controller",
    "steer_right": "front_right_steering_position_controller",
    "rear_left": "rear_left_velocity_controller",
    "rear_right": "rear_right_velocity_controller",
    "front_left": "front_left_velocity_controller",
    "front_right": "front_right_velocity_controller",
}
