"""A debug switch of the /gazebo node for finding memory that grows: with the environment variable
``MODROB_SIM_MEMDEBUG`` set the node offers the service ``~debug/memory`` (std_srvs/Trigger).
Each call answers, in ``message``, the resident set size, glibc's malloc statistics (bytes in use
vs. held free: a C-level leak grows the first, fragmentation the second), the gc object counts by
type that changed since the last call and, with ``MODROB_SIM_MEMDEBUG=N`` (N frames per
allocation; ``gc`` = without), the 25 source lines whose Python allocations grew most since the
last call. scripts/bench/spawn_delete_memory.py calls it between spawn/delete cycles. Off by
default: tracemalloc slows every allocation."""
import collections
import ctypes
import ctypes.util
import gc
import os
import tracemalloc

ENV = "MODROB_SIM_MEMDEBUG"


def enabled():
    return os.environ.get(ENV, "") not in ("", "0")


def rss_kib(pid="self"):
    with open("/proc/%s/status" % pid) as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    return 0


def type_counts():
    gc.collect()
    return collections.Counter(type(o).__module__ + "." + type(o).__qualname__ for o in gc.get_objects())


class _MallInfo2(ctypes.Structure):
    _fields_ = [(n, ctypes.c_size_t) for n in ("arena", "ordblks", "smblks", "hblks", "hblkhd", "usmblks",
                                               "fsmblks", "uordblks", "fordblks", "keepcost")]


def malloc_kib():
    """(in use, held free, mmapped) KiB of glibc's malloc, or None."""
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c"))
        f = libc.mallinfo2
    except (OSError, AttributeError):
        return None
    f.restype = _MallInfo2
    m = f()
    return m.uordblks // 1024, m.fordblks // 1024, m.hblkhd // 1024


def _describe(o):
    if isinstance(o, dict):
        return "dict(%s)" % ", ".join(sorted(str(k) for k in list(o)[:6]))
    if type(o).__name__ == "frame":
        return "frame %s:%d" % (o.f_code.co_filename, o.f_lineno)
    if type(o).__name__ == "cell":
        return "cell"
    return type(o).__module__ + "." + type(o).__qualname__


def removed_models_held():
    """What holds physics Models that were deleted from their World but are still alive (nothing
    should: a deleted model keeps its plugins' publishers and services alive)."""
    gc.collect()
    held = [o for o in gc.get_objects() if type(o).__name__ == "Model" and getattr(o, "_removed", False)]
    out = []
    skip = {id(held)}
    for m in held[:2]:
        for r in gc.get_referrers(m):
            if id(r) in skip or type(r).__name__ == "frame":
                continue
            up = [_describe(u) for u in gc.get_referrers(r) if id(u) not in skip and u is not held
                  and type(u).__name__ != "frame"][:4]
            out.append("deleted model '%s' held by %s <- %s" % (m.name, _describe(r), "; ".join(up)))
    return out


_LIBC = []


def trim_heap():
    """Give the heap's free pages back to the system (glibc malloc_trim): a model's spawn and
    delete free a few MB of many small blocks across malloc's per-thread arenas, and the holes
    stayed resident. Returns True when glibc did release something. No-op elsewhere."""
    if not _LIBC:
        try:
            libc = ctypes.CDLL(ctypes.util.find_library("c"))
            libc.malloc_trim.argtypes = [ctypes.c_size_t]
            libc.malloc_trim.restype = ctypes.c_int
            _LIBC.append(libc)
        except (OSError, AttributeError):
            _LIBC.append(None)
    return bool(_LIBC[0] is not None and _LIBC[0].malloc_trim(0))


class MemoryProbe(object):
    """Snapshots diffed call to call (pure: no rospy). ``frames`` 0: no tracemalloc."""

    def __init__(self, frames=8):
        self._trace = frames > 0
        if self._trace and not tracemalloc.is_tracing():
            tracemalloc.start(frames)
        self._snap = tracemalloc.take_snapshot() if self._trace else None
        self._types = type_counts()

    def report(self, top=25):
        types = type_counts()
        grown = sorted(((n - self._types.get(k, 0), k) for k, n in types.items()
                        if n != self._types.get(k, 0)), reverse=True)
        self._types = types
        lines = ["rss_kib %d malloc_in_use/free/mmapped_kib %s objects %d"
                 % (rss_kib(), "/".join(str(v) for v in (malloc_kib() or ())), sum(types.values()))]
        lines += ["objects %+d %s" % (d, k) for d, k in grown[:25] if d]
        lines += removed_models_held()
        if not self._trace:
            return "\n".join(lines)
        snap = tracemalloc.take_snapshot().filter_traces(
            (tracemalloc.Filter(False, tracemalloc.__file__), tracemalloc.Filter(False, "<frozen *>")))
        diff = snap.compare_to(self._snap, "lineno")
        self._snap = snap
        lines.append("traced_kib %d" % (tracemalloc.get_traced_memory()[0] // 1024))
        for st in diff[:top]:
            if st.size_diff:
                fr = st.traceback[0]
                lines.append("alloc %+d B %+d blocks %s:%d"
                             % (st.size_diff, st.count_diff, fr.filename, fr.lineno))
        return "\n".join(lines)


def advertise(node_name):
    """The ``~debug/memory`` service when the switch is on (else None)."""
    if not enabled():
        return None
    import rospy
    from std_srvs.srv import Trigger, TriggerResponse
    value = os.environ[ENV]
    try:
        frames = 0 if value == "gc" else max(1, int(value))
    except ValueError:
        frames = 8
    probe = MemoryProbe(frames)
    slower = " (tracemalloc on: slower)" if frames else ""
    rospy.logwarn("%s: %s=%s: ~debug/memory reports growth%s" % (node_name, ENV, value, slower))
    return rospy.Service("~debug/memory", Trigger, lambda _req: TriggerResponse(True, probe.report()))
