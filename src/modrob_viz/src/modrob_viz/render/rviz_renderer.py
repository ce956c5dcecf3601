"""RViz hosted in this process as a 3D renderer: one VisualizationFrame loads a scene config
(MarkerArray of the world, lights, background), one ``rviz/Camera`` display per camera renders
that scene through the pinhole of a ``sensor_msgs/CameraInfo`` from a tf frame, and its render
panel (a native window on the X server) is grabbed into a numpy image.

Everything here must run in the Qt (main) thread. Each camera's panel is a floating dock placed
so that no two overlap (an X server without compositing only keeps visible pixels).
"""
import ctypes

import numpy as np

from python_qt_binding.QtCore import QPoint
from python_qt_binding.QtWidgets import QApplication, QDockWidget
from rviz import bindings as rviz

from modrob_viz.errors import ConfigError

TITLE_SPACE = 40     # px left above each panel for the dock's title bar
MARGIN = 8


def disable_antialiasing():
    """rviz --disable-anti-aliasing (before the first render window): RViz asks OGRE for 4x
    multisampling, which Mesa's software rasterizer pays per sample (most of a frame's CPU).
    False when librviz does not have the switch."""
    try:
        lib = ctypes.CDLL("librviz.so")
        fn = getattr(lib, "_ZN4rviz12RenderSystem19disableAntiAliasingEv")
    except (OSError, AttributeError):
        return False
    fn.restype = None
    fn()
    return True


def _plugin_function(name, restype, argtypes):
    """ctypes handle on one of the ClipCamera plugin's C functions (in the library pluginlib
    loaded), or None."""
    path = "libmodrob_viz_rviz_plugins.so"
    try:
        with open("/proc/self/maps") as f:
            for line in f:
                if line.rstrip().endswith("/libmodrob_viz_rviz_plugins.so"):
                    path = line.split()[-1]
                    break
        fn = getattr(ctypes.CDLL(path), name)
    except (OSError, AttributeError):
        return None
    fn.restype, fn.argtypes = restype, argtypes
    return fn


def _pixel_reader():
    """The ClipCamera plugin's pixel copy, or None: then panels are grabbed from the X server."""
    return _plugin_function("modrob_viz_clip_camera_copy", ctypes.c_long,
                            [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_int, ctypes.c_int])


class _FrameSync(object):
    """RViz's FrameManager in exact time sync, driven through librviz's C++ symbols (the Python
    bindings do not wrap the FrameManager). Every tf lookup RViz makes for "the latest" (frame-
    locked markers, robot links, a camera image with stamp 0) then uses the time given to
    :meth:`sync` instead of the newest tf it has."""

    EXACT = 1       # rviz::FrameManager::SyncExact

    def __init__(self, manager):
        lib = ctypes.CDLL("librviz.so")
        get = lib._ZNK4rviz20VisualizationManager15getFrameManagerEv
        get.restype, get.argtypes = ctypes.c_void_p, [ctypes.c_void_p]
        mode = lib._ZN4rviz12FrameManager11setSyncModeENS0_8SyncModeE
        mode.restype, mode.argtypes = None, [ctypes.c_void_p, ctypes.c_int]
        # ros::Time {uint32 sec, nsec} is trivially copyable: passed by value in one register
        self._sync = lib._ZN4rviz12FrameManager8syncTimeEN3ros4TimeE
        self._sync.restype, self._sync.argtypes = None, [ctypes.c_void_p, ctypes.c_uint64]
        # adjustTime(ros::Time&) replaces a zero time by the sync time: reads the time back
        self._adjust = lib._ZN4rviz12FrameManager10adjustTimeERN3ros4TimeE
        self._adjust.restype, self._adjust.argtypes = None, [ctypes.c_void_p, ctypes.c_void_p]
        address = _address(manager)
        self._fm = get(address) if address else None
        if not self._fm:
            raise OSError("no FrameManager behind the VisualizationManager")
        mode(self._fm, self.EXACT)

    def sync(self, secs, nsecs):
        """Draw the scene at (secs, nsecs) from RViz's next update on; (0, 0): its newest tf."""
        self._sync(self._fm, (int(nsecs) << 32) | int(secs))

    def time(self):
        """(secs, nsecs) RViz draws the scene at."""
        t = (ctypes.c_uint32 * 2)(0, 0)
        self._adjust(self._fm, ctypes.addressof(t))
        return int(t[0]), int(t[1])


def _address(obj):
    """Address of the C++ object behind a sip wrapper (None if sip is not importable)."""
    try:
        from PyQt5 import sip
    except ImportError:
        try:
            import sip
        except ImportError:
            return None
    return int(sip.unwrapinstance(obj))


def _has_prop(disp, name):
    """True if the display has a property ``name`` (subProp returns a stand-in when it has not)."""
    if disp is None:
        return False
    prop = disp.subProp(name)
    return prop is not None and prop.getName() == name


class RvizScene(object):
    """``config`` is an .rviz file with the scene displays (no cameras)."""

    def __init__(self, config, frame_rate=30.0, max_cameras=8, antialiasing=False, pixels="gl"):
        """``antialiasing``: RViz's 4x multisampling (off: a frame costs Mesa a quarter of the CPU);
        ``pixels``: "gl" reads each render from OpenGL through the ClipCamera plugin, "x11" grabs
        the panel from the X server (the fallback without the plugin)."""
        if pixels not in ("gl", "x11"):
            raise ConfigError("pixels must be 'gl' or 'x11', got %r" % (pixels,))
        self.pixels = pixels
        self.app = QApplication.instance() or QApplication(["camera_renderer"])
        if not antialiasing:
            disable_antialiasing()
        self.frame = rviz.VisualizationFrame()
        self.frame.setSplashPath("")
        self.frame.initialize()
        cfg = rviz.Config()
        reader = rviz.YamlConfigReader()
        reader.readFile(cfg, config)
        if reader.error():
            raise ConfigError("cannot read the scene config %s (an .rviz YAML file): %s"
                              % (config, reader.errorMessage()))
        self.frame.load(cfg)
        self.frame.setMenuBar(None)
        self.frame.setStatusBar(None)
        self.frame.setHideButtonVisibility(False)
        self.manager = self.frame.getManager()
        try:
            self._frame_sync = _FrameSync(self.manager)
        except (OSError, AttributeError) as err:    # another librviz: the scene at RViz's newest tf
            print("camera_renderer: cannot put RViz's tf in exact time sync (%s): the scene is drawn "
                  "at RViz's newest tf, which can be later than an image's stamp" % err, flush=True)
            self._frame_sync = None
        self.set_frame_rate(frame_rate)
        self.frame.resize(160, 120)
        self.frame.move(0, 0)
        self.frame.show()
        for dock in self.frame.findChildren(QDockWidget):    # Displays, Views, Time ... panels
            dock.hide()
        central = self.frame.centralWidget()
        if central is not None:     # the main 3D view costs a render per frame: keep it tiny
            central.setFixedSize(8, 8)
        self.cameras = {}           # name -> dict(display, dock, panel, size)
        self.max_cameras = max_cameras
        self.clip_supported = None  # the ClipCamera plugin loaded (set by _make_display)
        self._copy = None           # the plugin's pixel copy function (set by _make_display)
        self._copy_depth = None     # the plugin's depth copy function (set by _make_display)
        self._drawn = None          # the plugin's report of the last render (set by _make_display)
        self._can_transform = None  # the plugin's look-up in RViz's tf buffer (set by _make_display)
        self._pool = [self._make_display(i) for i in range(max_cameras)]
        self._origin = (0, 130)

    def set_frame_rate(self, rate):
        opts = self.manager.getRootDisplayGroup().subProp("Global Options")
        prop = opts.subProp("Frame Rate") if opts is not None else None
        if prop is not None:
            prop.setValue(int(max(1, min(120, round(rate)))))

    @property
    def time_sync(self):
        """True when the scene is drawn at the time given to :meth:`sync_time`."""
        return self._frame_sync is not None

    def sync_time(self, secs, nsecs):
        """RViz looks every "latest" transform up at (secs, nsecs) from its next update on: the
        frame-locked scene is drawn as it was then. (0, 0): at its newest tf."""
        if self._frame_sync is not None:
            self._frame_sync.sync(secs, nsecs)

    def synced_time(self):
        """(secs, nsecs) the scene is drawn at ((0, 0): the newest tf; None without time sync)."""
        return self._frame_sync.time() if self._frame_sync is not None else None

    def scene_topics(self):
        """[(topic, "MarkerArray" | "Marker")] of the scene config's enabled marker displays."""
        out = []

        def walk(group):
            for i in range(group.numDisplays()):
                disp = group.getDisplayAt(i)
                if disp is None or not disp.isEnabled():
                    continue
                cls = disp.getClassId()
                if cls in ("rviz/MarkerArray", "rviz/Marker") and _has_prop(disp, "Marker Topic"):
                    out.append((str(disp.subProp("Marker Topic").getValue()), cls.split("/")[1]))
                elif hasattr(disp, "numDisplays"):
                    walk(disp)

        walk(self.manager.getRootDisplayGroup())
        return out

    def screen_size(self):
        g = self.app.primaryScreen().geometry()
        return g.width(), g.height()

    def _make_display(self, slot):
        # modrob_viz/ClipCamera (this package's rviz plugin) is rviz/Camera with near/far clip
        disp = None
        if self.clip_supported is not False:
            disp = self.manager.createDisplay("modrob_viz/ClipCamera", "cam%d" % slot, False)
        if not _has_prop(disp, "Near Clip"):
            if self.clip_supported is not False:
                print("camera_renderer: the rviz plugin modrob_viz/ClipCamera is not available (build "
                      "the workspace: bash scripts/build.sh); cameras clip at RViz's 0.01 m and 100 m",
                      flush=True)
            self.clip_supported = False
            disp = self.manager.createDisplay("rviz/Camera", "cam%d" % slot, False)
        else:
            self.clip_supported = True
            disp.subProp("Capture Pixels").setValue(self.pixels == "gl")
        if disp is None:
            raise ConfigError("RViz could not create an rviz/Camera display (is the rviz package complete?)")
        disp.subProp("Image Rendering").setValue("background")   # a 1x1 image of the background colour
        disp.subProp("Overlay Alpha").setValue(0.0)
        disp.subProp("Zoom Factor").setValue(1.0)
        dock = None
        for d in self.frame.findChildren(QDockWidget):
            if d.windowTitle() == "cam%d" % slot:
                dock = d
        if dock is None or dock.widget() is None:
            raise ConfigError("the Camera display cam%d has no render panel" % slot)
        dock.setFloating(True)
        dock.hide()
        ptr = _address(disp) if self.pixels == "gl" and _has_prop(disp, "Capture Pixels") else None
        if ptr is not None and self._copy is None:
            self._copy = _pixel_reader()
            self._copy_depth = _plugin_function(
                "modrob_viz_clip_camera_copy_depth", ctypes.c_long,
                [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_int, ctypes.c_int])
        clip = _address(disp) if _has_prop(disp, "Capture Pixels") else None
        if clip is not None and self._drawn is None:
            self._drawn = _plugin_function("modrob_viz_clip_camera_drawn", ctypes.c_long,
                                           [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p])
            self._can_transform = _plugin_function(
                "modrob_viz_clip_camera_can_transform", ctypes.c_int,
                [ctypes.c_void_p, ctypes.POINTER(ctypes.c_char_p), ctypes.c_int, ctypes.c_uint,
                 ctypes.c_uint])
        return dict(display=disp, dock=dock, panel=dock.widget(), size=None, ptr=ptr, clip=clip)

    def add_camera(self, name, topic_prefix):
        """Give a Camera display of the pool to ``name``: it reads ``<prefix>/image`` (a 1x1 image
        of the background colour whose header names the tf frame) and ``<prefix>/camera_info``
        (the pinhole). RViz crashes when displays are created inside the event loop, so the
        displays are made at start-up and only enabled here."""
        if name in self.cameras:
            return
        if not self._pool:
            raise ConfigError("camera '%s': all %d camera slots are in use (raise ~max_cameras)"
                              % (name, self.max_cameras))
        cam = self._pool.pop(0)
        cam["size"] = None
        cam["display"].subProp("Image Topic").setValue(topic_prefix + "/image")
        cam["display"].setEnabled(True)
        cam["dock"].setFloating(True)
        cam["dock"].hide()          # shown by _layout once the camera has a size
        self.cameras[name] = cam

    def resize_camera(self, name, width, height):
        cam = self.cameras[name]
        if cam["size"] == (width, height):
            return
        cam["size"] = (width, height)
        cam["panel"].setFixedSize(width, height)
        cam["dock"].adjustSize()
        self._layout()

    def _layout(self):
        """Shelf packing of the docks (title bar + panel) on the screen, in insertion order;
        cameras without a size yet stay hidden."""
        sw, sh = self.screen_size()
        x, y = self._origin
        row = 0
        for cam in self.cameras.values():
            if cam["size"] is None:
                cam["dock"].hide()
                continue
            w, h = cam["size"]
            dock = cam["dock"]
            dock.adjustSize()
            dw = max(w, dock.frameGeometry().width())
            dh = max(h + TITLE_SPACE, dock.frameGeometry().height())
            if x + dw > sw and x > 0:
                x, y, row = 0, y + row + MARGIN, 0
            dock.move(x, y)
            dock.show()
            cam["fits"] = x + dw <= sw and y + dh <= sh
            x += dw + MARGIN
            row = max(row, dh)

    def set_clip(self, name, near, far):
        """Nothing nearer than ``near`` or farther than ``far`` (m) is drawn by camera ``name``
        (False when the ClipCamera plugin is missing: RViz's 0.01 m and 100 m apply)."""
        disp = self.cameras[name]["display"]
        if not _has_prop(disp, "Near Clip"):
            return False
        disp.subProp("Far Clip").setValue(float(far))
        disp.subProp("Near Clip").setValue(float(near))
        return True

    def fits(self, name):
        return self.cameras[name].get("fits", False)

    def set_depth(self, name, on):
        """Read each render's depth too (False when the ClipCamera plugin cannot: no depth)."""
        cam = self.cameras[name]
        if cam["ptr"] is None or self._copy_depth is None or not _has_prop(cam["display"], "Capture Depth"):
            return False
        cam["display"].subProp("Capture Depth").setValue(bool(on))
        return True

    def grab_depth(self, name):
        """float32 (height, width) metres along the optical axis (inf: nothing drawn) of the render
        :meth:`grab` gave last, or None."""
        cam = self.cameras.get(name)
        if cam is None or cam["size"] is None or cam["ptr"] is None or self._copy_depth is None:
            return None
        w, h = cam["size"]
        out = np.empty((h, w), np.float32)
        serial = self._copy_depth(cam["ptr"], out.ctypes.data, w, h)
        return out if serial > 0 else None

    def set_active(self, name, active):
        """Enable or disable the camera's display: a disabled one is not rendered (and forgets its
        image and CameraInfo, which the renderer gives again when it is enabled)."""
        cam = self.cameras.get(name)
        if cam is not None:
            cam["display"].setEnabled(bool(active))

    def remove_camera(self, name):
        cam = self.cameras.pop(name, None)
        if cam is None:
            return
        cam["display"].setEnabled(False)
        if _has_prop(cam["display"], "Capture Depth"):
            cam["display"].subProp("Capture Depth").setValue(False)
        cam["dock"].hide()
        cam["size"] = None
        cam["panel"].setMinimumSize(0, 0)
        cam["panel"].setMaximumSize(16777215, 16777215)
        self._pool.append(cam)
        self._layout()

    def status(self, name):
        """{category: text} of the camera display's status (Image, Camera Info, Transform ...)."""
        cam = self.cameras.get(name)
        out = {}
        if cam is None:
            return out
        disp = cam["display"]
        for i in range(disp.numChildren()):
            child = disp.childAt(i)
            if child is not None and child.getName().startswith("Status"):
                for j in range(child.numChildren()):
                    c = child.childAt(j)
                    out[c.getName()] = str(c.getValue())
        return out

    def ready(self, name):
        """True once RViz has the camera's (blank) image and CameraInfo: before that the panel
        shows "No Image"."""
        st = self.status(name)
        return not (st.get("Image", "No Image").startswith("No Image")
                    or st.get("Camera Info", "No CameraInfo").startswith("No CameraInfo"))

    def images_received(self, name):
        """How many (placeholder) images the camera's display has taken so far (RViz's status
        'N images received'); 0 before the first."""
        text = self.status(name).get("Image", "")
        head = text.split(" ", 1)[0]
        return int(head) if head.isdigit() else 0

    def drawn(self, name):
        """What the camera's last render showed: (renders so far, image stamp (secs, nsecs), scene
        time (secs, nsecs), camera at the image frame's pose of that stamp), or None without the
        ClipCamera plugin."""
        cam = self.cameras.get(name)
        if cam is None or cam.get("clip") is None or self._drawn is None:
            return None
        stamps = (ctypes.c_uint * 4)()
        pose_ok = ctypes.c_int(0)
        renders = self._drawn(cam["clip"], ctypes.addressof(stamps), ctypes.addressof(pose_ok))
        if renders < 0:
            return None
        return int(renders), (stamps[0], stamps[1]), (stamps[2], stamps[3]), bool(pose_ok.value)

    def rviz_has_tf(self, frames, secs, nsecs):
        """Whether RViz's own tf buffer (its listener thread can be behind the renderer's) has every
        one of ``frames`` at that time; None when the ClipCamera plugin cannot tell."""
        fn = self._can_transform
        clip = next((c["clip"] for c in self.cameras.values() if c.get("clip") is not None), None)
        if fn is None or clip is None:
            return None
        names = [f.lstrip("/").encode() for f in frames]
        arr = (ctypes.c_char_p * max(1, len(names)))(*names)
        got = fn(clip, arr, len(names), secs, nsecs)
        return None if got < 0 else bool(got)

    def process_events(self):
        self.app.processEvents()

    def grab(self, name):
        """RGB uint8 array (height, width, 3) of what the camera's panel shows, or None."""
        cam = self.cameras.get(name)
        if cam is None or cam["size"] is None:
            return None
        w, h = cam["size"]
        if cam["ptr"] is not None and self._copy is not None:
            # the render's pixels as the plugin copied them from OpenGL: one copy, already RGB
            rgb = np.empty((h, w, 3), np.uint8)
            serial = self._copy(cam["ptr"], rgb.ctypes.data, w, h)
            return rgb if serial > 0 else None
        panel = cam["panel"]
        pos = panel.mapToGlobal(QPoint(0, 0))
        pix = self.app.primaryScreen().grabWindow(0, pos.x(), pos.y(), w, h)
        img = pix.toImage().convertToFormat(4)    # QImage.Format_RGB32 (B, G, R, 255 in memory)
        if img.width() != w or img.height() != h:
            return None
        ptr = img.constBits()
        ptr.setsize(img.byteCount())
        arr = np.frombuffer(ptr, np.uint8).reshape(h, img.bytesPerLine() // 4, 4)
        return np.ascontiguousarray(arr[:, :w, 2::-1])

    def close(self):
        self.frame.close()
