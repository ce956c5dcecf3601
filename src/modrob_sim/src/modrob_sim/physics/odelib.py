"""Direct access to the libode that PyODE itself uses (the same shared library, so the same global
state), for the few calls PyODE does not wrap: the SOR relaxation factor and ODE's global random
seed (quickStep reorders constraints randomly; saving and restoring the seed per World makes
each World deterministic however worlds are interleaved in one process).

Raw pointers of PyODE objects (``World``, ``Body``, ``JointGroup``) are read from the Cython
object layout (the pointer is the first field after PyObject_HEAD) and VERIFIED once against
values PyODE reports; if the check fails, :data:`AVAILABLE` is False and callers fall back.
"""
import ctypes
import ctypes.util
import logging
import struct

import ode

LOG = logging.getLogger("modrob_sim.physics")

_HEAD = struct.calcsize("P") * 2  # ob_refcnt + ob_type


def _load():
    name = ctypes.util.find_library("ode") or "libode.so.8"
    try:
        lib = ctypes.CDLL(name)
    except OSError as e:
        LOG.warning("libode not loadable through ctypes (%s): SOR and per-world seeds are off", e)
        return None
    vp = ctypes.c_void_p
    lib.dRandGetSeed.restype = ctypes.c_ulong
    lib.dRandGetSeed.argtypes = []
    lib.dRandSetSeed.restype = None
    lib.dRandSetSeed.argtypes = [ctypes.c_ulong]
    lib.dWorldSetQuickStepW.restype = None
    lib.dWorldSetQuickStepW.argtypes = [vp, ctypes.c_double]
    lib.dWorldGetQuickStepW.restype = ctypes.c_double
    lib.dWorldGetQuickStepW.argtypes = [vp]
    lib.dWorldGetCFM.restype = ctypes.c_double
    lib.dWorldGetCFM.argtypes = [vp]
    lib.dBodyGetPosition.restype = ctypes.POINTER(ctypes.c_double)
    lib.dBodyGetPosition.argtypes = [vp]
    lib.dGeomGetBody.restype = vp
    lib.dGeomGetBody.argtypes = [vp]
    lib.dBodyGetWorld.restype = vp
    lib.dBodyGetWorld.argtypes = [vp]
    lib.dBodySetAutoDisableFlag.restype = None
    lib.dBodySetAutoDisableFlag.argtypes = [vp, ctypes.c_int]
    for fn in ("dBodySetKinematic", "dBodySetDynamic"):  # ODE >= 0.13: infinite mass, moves by its velocity
        getattr(lib, fn).restype = None
        getattr(lib, fn).argtypes = [vp]
    lib.dBodyIsKinematic.restype = ctypes.c_int
    lib.dBodyIsKinematic.argtypes = [vp]
    return lib


LIB = _load()


def raw_pointer(obj):
    """The C pointer stored first in a PyODE World/Body/JointGroup object."""
    return ctypes.c_void_p.from_address(id(obj) + _HEAD).value


def _verify():
    if LIB is None:
        return False
    try:
        w = ode.World()
        w.setCFM(1.25e-7)
        wp = raw_pointer(w)
        if abs(LIB.dWorldGetCFM(wp) - 1.25e-7) > 1e-15:
            return False
        b = ode.Body(w)
        b.setPosition((1.5, -2.5, 3.5))
        bp = raw_pointer(b)
        p = LIB.dBodyGetPosition(bp)
        if (p[0], p[1], p[2]) != (1.5, -2.5, 3.5):
            return False
        g = ode.GeomSphere(None, 0.1)
        g.setBody(b)
        if LIB.dGeomGetBody(g._id()) != bp or LIB.dBodyGetWorld(bp) != wp:
            return False
        del g, b, w
        return True
    except Exception as e:  # noqa: B902 - any failure here only disables the fast path
        LOG.warning("PyODE object layout check failed (%s): raw ODE access disabled", e)
        return False


AVAILABLE = _verify()


def _param_layout():
    """Joint parameter numbers of the libode in use. PyODE's ode.ParamFMax etc. were compiled
    against an older ODE: ODE 0.16 inserted dParamLoVel/dParamHiVel after dParamVel, so
    ode.ParamFMax (3) is really dParamLoVel there and setting it does nothing. Detect the layout
    from the defaults (FudgeFactor 1, StopERP = world ERP 0.2)."""
    w = ode.World()
    b = ode.Body(w)
    h = ode.HingeJoint(w)
    h.attach(b, None)
    new = h.getParam(6) == 1.0 and abs(h.getParam(9) - 0.2) < 1e-12
    del h, b, w
    if new:
        return dict(LoStop=0, HiStop=1, Vel=2, FMax=5, FudgeFactor=6, Bounce=7, CFM=8, StopERP=9,
                    StopCFM=10)
    return dict(LoStop=ode.ParamLoStop, HiStop=ode.ParamHiStop, Vel=ode.ParamVel, FMax=ode.ParamFMax,
                FudgeFactor=ode.ParamFudgeFactor, Bounce=ode.ParamBounce, CFM=ode.ParamCFM,
                StopERP=ode.ParamStopERP, StopCFM=ode.ParamStopCFM)


_P = _param_layout()
PARAM_LO_STOP = _P["LoStop"]
PARAM_HI_STOP = _P["HiStop"]
PARAM_VEL = _P["Vel"]
PARAM_FMAX = _P["FMax"]
PARAM_CFM = _P["CFM"]
PARAM_STOP_ERP = _P["StopERP"]
PARAM_STOP_CFM = _P["StopCFM"]
if LIB is not None and not AVAILABLE:
    LOG.warning("PyODE object layout not as expected: SOR parameter and native collision disabled")


def get_seed():
    return LIB.dRandGetSeed() if LIB is not None else 0


def set_seed(seed):
    if LIB is not None:
        LIB.dRandSetSeed(seed & 0xFFFFFFFF)
