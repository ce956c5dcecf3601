"""The HTTP server (ROS's web_video_server URLs):

    /                          index: every sensor_msgs/Image topic, with stream and snapshot links
    /stream?topic=T            multipart/x-mixed-replace MJPEG (also type=mjpeg); quality, width, height
    /stream_viewer?topic=T     an HTML page showing the stream
    /snapshot?topic=T          one JPEG of the next (or latest) image

A topic is subscribed while someone watches it (the first request subscribes); rospy callbacks
only store the latest message, HTTP threads encode.
"""
import html
import threading
import time
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from urllib.parse import parse_qs, quote, urlparse

import rospy
from sensor_msgs.msg import Image

from web_video_server.encoding import EncodingError, jpeg, to_bgr

BOUNDARY = "boundarydonotcross"


class TopicSource(object):
    """The latest image of one topic, with a condition to wait for the next."""

    def __init__(self, topic):
        self.topic = topic
        self.cond = threading.Condition()
        self.msg = None
        self.count = 0
        self.users = 0
        self.sub = rospy.Subscriber(topic, Image, self._on_image, queue_size=1, buff_size=2 ** 24)

    def _on_image(self, msg):
        with self.cond:
            self.msg = msg
            self.count += 1
            self.cond.notify_all()

    def next(self, after_count, timeout):
        """(msg, count) of an image newer than ``after_count``, or (None, after_count)."""
        end = time.monotonic() + timeout
        with self.cond:
            while self.count <= after_count:
                left = end - time.monotonic()
                if left <= 0 or rospy.is_shutdown():
                    return None, after_count
                self.cond.wait(left)
            return self.msg, self.count


class VideoServer(object):
    def __init__(self, address="0.0.0.0", port=8080, default_quality=95, image_timeout=5.0):
        self.default_quality = default_quality
        self.image_timeout = image_timeout
        self.lock = threading.Lock()
        self.sources = {}
        server = self

        class Handler(BaseHTTPRequestHandler):
            protocol_version = "HTTP/1.0"

            def do_GET(self):
                server.handle(self)

            def log_message(self, fmt, *args):
                rospy.logdebug("web_video_server: " + fmt, *args)

        self.httpd = ThreadingHTTPServer((address, port), Handler)
        self.httpd.daemon_threads = True
        self.port = self.httpd.server_address[1]
        self.thread = threading.Thread(target=self.httpd.serve_forever, name="web_video_server", daemon=True)

    def start(self):
        self.thread.start()

    def shutdown(self):
        self.httpd.shutdown()
        self.httpd.server_close()

    # ---- sources ---------------------------------------------------------------------------------
    def _acquire(self, topic):
        with self.lock:
            src = self.sources.get(topic)
            if src is None:
                src = self.sources[topic] = TopicSource(topic)
            src.users += 1
            return src

    def _release(self, src):
        with self.lock:
            src.users -= 1
            if src.users <= 0 and self.sources.get(src.topic) is src:
                src.sub.unregister()
                del self.sources[src.topic]

    # ---- requests --------------------------------------------------------------------------------
    def handle(self, req):
        url = urlparse(req.path)
        q = {k: v[-1] for k, v in parse_qs(url.query).items()}
        try:
            if url.path in ("/", "/index.html"):
                return self._index(req)
            if url.path == "/stream" and q.get("type", "mjpeg") in ("mjpeg", "ros_compressed"):
                return self._stream(req, q)
            if url.path == "/stream_viewer":
                return self._viewer(req, q)
            if url.path == "/snapshot":
                return self._snapshot(req, q)
            if url.path == "/stream":
                return self._error(req, 400, "stream type %r is not supported here: use type=mjpeg"
                                   % q.get("type"))
            return self._error(req, 404, "no page %s: try / for the list of image topics" % url.path)
        except (BrokenPipeError, ConnectionResetError):
            return None

    @staticmethod
    def _send(req, code, body, content_type="text/html; charset=utf-8", no_cache=False):
        req.send_response(code)
        req.send_header("Content-Type", content_type)
        req.send_header("Content-Length", str(len(body)))
        if no_cache:
            req.send_header("Cache-Control", "no-cache")
        req.end_headers()
        req.wfile.write(body)

    @classmethod
    def _error(cls, req, code, text):
        cls._send(req, code, ("<html><body><h1>%d</h1><p>%s</p></body></html>"
                              % (code, html.escape(text))).encode())

    def _request(self, req, q, page):
        """(topic, (quality, width, height)) of a /stream or /snapshot request, or None once a 400
        naming what is wrong was sent."""
        topic = q.get("topic", "")
        if not topic:
            self._error(req, 400, "give the image topic: /%s?topic=/camera/image" % page)
            return None
        try:
            return topic, (int(q.get("quality", self.default_quality)), int(q.get("width", 0)),
                           int(q.get("height", 0)))
        except ValueError:
            self._error(req, 400, "quality, width and height must be integers")
            return None

    def image_topics(self):
        try:
            topics = rospy.get_published_topics()
        except Exception as err:  # noqa: B902 - the master may be gone; the page says so
            rospy.logwarn("web_video_server: cannot list topics: %s", err)
            return []
        return sorted(t for t, kind in topics if kind == "sensor_msgs/Image")

    def _index(self, req):
        items = []
        for t in self.image_topics():
            qt = quote(t, safe="/")
            items.append('<li><a href="/stream_viewer?topic=%s">%s</a> (<a href="/stream?topic=%s">stream'
                         '</a>, <a href="/snapshot?topic=%s">snapshot</a>)</li>'
                         % (qt, html.escape(t), qt, qt))
        body = ("<html><head><title>ROS Image Topic List</title></head><body>"
                "<h1>Available ROS Image Topics:</h1><ul>%s</ul></body></html>"
                % ("".join(items) or "<li>none yet</li>")).encode()
        self._send(req, 200, body)

    def _viewer(self, req, q):
        topic = q.get("topic", "")
        if not topic:
            return self._error(req, 400, "give the image topic: /stream_viewer?topic=/camera/image")
        qt = quote(topic, safe="/")
        extra = "".join("&%s=%s" % (k, quote(q[k])) for k in ("quality", "width", "height") if k in q)
        body = ('<html><head><title>%s</title></head><body><h1>%s</h1>'
                '<img id="stream" src="/stream?topic=%s%s"></body></html>'
                % (html.escape(topic), html.escape(topic), qt, extra)).encode()
        self._send(req, 200, body)

    def _frame(self, msg, params):
        bgr = to_bgr(msg.width, msg.height, msg.encoding, msg.step, msg.data)
        return jpeg(bgr, *params)

    def _snapshot(self, req, q):
        r = self._request(req, q, "snapshot")
        if r is None:
            return
        topic, params = r
        src = self._acquire(topic)
        try:
            msg, _ = src.next(0, self.image_timeout)
            if msg is None:
                return self._error(req, 404, "no image on %s within %.0f s (is it published?)"
                                   % (topic, self.image_timeout))
            try:
                data = self._frame(msg, params)
            except EncodingError as err:
                return self._error(req, 415, "%s: %s" % (topic, err))
            self._send(req, 200, data, "image/jpeg", no_cache=True)
        finally:
            self._release(src)

    def _stream(self, req, q):
        r = self._request(req, q, "stream")
        if r is None:
            return
        topic, params = r
        src = self._acquire(topic)
        try:
            req.send_response(200)
            req.send_header("Content-Type", "multipart/x-mixed-replace;boundary=%s" % BOUNDARY)
            req.send_header("Cache-Control", "no-cache, no-store, must-revalidate, max-age=0")
            req.send_header("Pragma", "no-cache")
            req.send_header("Connection", "close")
            req.end_headers()
            count = 0
            while not rospy.is_shutdown():
                msg, count = src.next(count, 1.0)
                if msg is None:
                    continue
                try:
                    data = self._frame(msg, params)
                except EncodingError as err:
                    rospy.logwarn_throttle(10.0, "web_video_server: %s: %s" % (topic, err))
                    continue
                head = "--%s\r\nContent-Type: image/jpeg\r\nContent-Length: %d\r\nX-Timestamp: %.6f\r\n\r\n"
                req.wfile.write((head % (BOUNDARY, len(data), msg.header.stamp.to_sec())).encode())
                req.wfile.write(data)
                req.wfile.write(b"\r\n")
                req.wfile.flush()
        except (BrokenPipeError, ConnectionResetError):
            pass
        finally:
            self._release(src)
