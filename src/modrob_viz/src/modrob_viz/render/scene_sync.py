"""Which tf time a batch of camera frames is drawn at (pure: no rospy, no Qt).

RViz draws frame-locked markers (the simulator's scene) at its frame manager's time, which the
renderer sets to the time T it stamps the images with. T must be a time at which tf has every
frame the images depend on: the cameras' frames (their pose is looked up at T) and the frames
the scene's frame-locked markers hang on (a marker whose frame has no tf at T is not drawn).
:class:`SceneFrames` keeps the set of those scene frames from the marker messages,
:func:`common_stamp` picks T. Stamps are integer nanoseconds; 0 means a static transform
(valid at every time).
"""

ADD, DELETE, DELETEALL = 0, 2, 3     # visualization_msgs/Marker actions (MODIFY == ADD)


class SceneFrames(object):
    """The tf frames of the frame-locked markers received on each scene topic, following the
    markers' ADD / DELETE / DELETEALL actions as RViz's marker displays do."""

    def __init__(self):
        self._topics = {}       # topic -> {(ns, id): frame}

    def update(self, topic, markers):
        """``markers``: the visualization_msgs/Marker messages of one message (a MarkerArray's
        list, or a one-element list for a Marker topic), in order."""
        table = self._topics.setdefault(topic, {})
        for mk in markers:
            if mk.action == DELETEALL:
                table.clear()
            elif mk.action == DELETE:
                table.pop((mk.ns, mk.id), None)
            elif mk.frame_locked and mk.header.frame_id:
                table[(mk.ns, mk.id)] = mk.header.frame_id.lstrip("/")
            else:                   # drawn once, where its frame was when it came: not RViz's time
                table.pop((mk.ns, mk.id), None)

    def frames(self):
        out = set()
        for table in self._topics.values():
            out.update(table.values())
        return out


def common_stamp(camera_stamps, scene_stamps, max_lag_ns):
    """(T, left_out): the newest time at which tf has every camera frame and every scene frame.

    ``camera_stamps``: the newest stamp of each camera frame of the batch (0: static);
    ``scene_stamps``: {frame: newest stamp, 0 static, None not in tf}. A scene frame whose newest
    stamp is more than ``max_lag_ns`` older than the newest of all (its publisher stopped) would
    hold every image back: it is left out of T and listed in ``left_out`` (RViz cannot draw it at
    T). Frames not in tf are ignored (RViz cannot draw them at any time). T is 0 when nothing
    moves (every frame static): RViz then uses its newest tf."""
    moving_cams = [s for s in camera_stamps if s]
    moving_scene = {f: s for f, s in scene_stamps.items() if s}
    every = moving_cams + list(moving_scene.values())
    if not every:
        return 0, []
    newest = max(every)
    left_out = sorted(f for f, s in moving_scene.items() if newest - s > max_lag_ns)
    kept = moving_cams + [s for f, s in moving_scene.items() if newest - s <= max_lag_ns]
    return min(kept), left_out
