"""teleop_twist_keyboard's key map and state, and its terminal and publishing helpers."""
