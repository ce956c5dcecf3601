"""The tf time a batch of camera frames is drawn at: the scene's frame-locked frames follow the
markers' actions, and T is the newest time at which tf has every camera and scene frame."""
from types import SimpleNamespace

from modrob_viz.render.scene_sync import ADD, DELETE, DELETEALL, SceneFrames, common_stamp

MS = 1000000


def marker(frame, mid, action=ADD, locked=True, ns="m"):
    return SimpleNamespace(header=SimpleNamespace(frame_id=frame), ns=ns, id=mid, action=action,
                           frame_locked=locked)


def test_scene_frames_follow_add_delete_and_deleteall():
    s = SceneFrames()
    s.update("/scene", [marker("world", 0, DELETEALL), marker("gazebo/ball/link", 0),
                        marker("/gazebo/robot/base", 1), marker("world", 2, locked=False)])
    assert s.frames() == {"gazebo/ball/link", "gazebo/robot/base"}
    s.update("/other", [marker("cam_mount", 0)])
    s.update("/scene", [marker("gazebo/robot/base", 1, DELETE)])
    assert s.frames() == {"gazebo/ball/link", "cam_mount"}
    s.update("/scene", [marker("gazebo/ball/link", 0, locked=False)])     # re-sent unlocked
    assert s.frames() == {"cam_mount"}
    s.update("/other", [marker("x", 0, DELETEALL)])
    assert s.frames() == set()


def test_same_id_in_two_namespaces_are_two_markers():
    s = SceneFrames()
    s.update("/scene", [marker("a", 0, ns="one"), marker("b", 0, ns="two")])
    s.update("/scene", [marker("a", 0, DELETE, ns="one")])
    assert s.frames() == {"b"}


def test_stamp_is_the_newest_time_every_frame_has():
    # the camera's tf is newer than the ball's: drawing at the camera's newest would need the
    # ball's pose from the future
    t, out = common_stamp([1000 * MS], {"ball": 980 * MS, "floor": 0}, 1000 * MS)
    assert (t, out) == (980 * MS, [])
    t, out = common_stamp([950 * MS, 990 * MS], {"ball": 980 * MS}, 1000 * MS)
    assert (t, out) == (950 * MS, [])


def test_static_and_missing_frames_do_not_hold_the_time():
    assert common_stamp([0], {"ball": 500 * MS, "ghost": None}, 1000 * MS) == (500 * MS, [])
    assert common_stamp([700 * MS], {"ghost": None, "wall": 0}, 1000 * MS) == (700 * MS, [])


def test_nothing_moves_gives_zero_the_newest_tf():
    assert common_stamp([0, 0], {"wall": 0, "ghost": None}, 1000 * MS) == (0, [])
    assert common_stamp([], {}, 1000 * MS) == (0, [])


def test_a_scene_frame_whose_publisher_stopped_is_left_out_and_named():
    t, out = common_stamp([5000 * MS], {"ball": 4990 * MS, "dead": 1000 * MS, "dead2": 3900 * MS},
                          1000 * MS)
    assert t == 4990 * MS
    assert out == ["dead", "dead2"]
    # a camera is never left out: its pose must be the one of the stamp
    t, out = common_stamp([1000 * MS], {"ball": 5000 * MS}, 1000 * MS)
    assert (t, out) == (1000 * MS, [])
