"""The native libraries are the build of the sources next to their loaders: each carries the
SHA-256 of the source it was built from, and a library built from another source (a pull or rebase
without `make build`) is refused with a message that names the files and says to build, instead of
the World falling back to the pure-Python physics unnoticed. MODROB_PHYSICS_NATIVE=0 still selects
the pure-Python physics on purpose."""
import ctypes

import pytest

from modrob_sim.errors import SimulationError
from modrob_sim.physics import World
from modrob_sim.physics import native
from modrob_sim.sensors import native as ray_native
from modrob_sim.sensors import raycast


def built(library):
    try:
        return native.find_library(library)
    except FileNotFoundError:
        return None


needs_build = pytest.mark.skipif(built(native.LIBRARY) is None, reason="the native libraries are not built")


@pytest.fixture
def reload_after():
    """Load the libraries again, as the environment and sources are, after the test changed them."""
    mp = pytest.MonkeyPatch()
    yield mp
    mp.undo()
    native.load()
    ray_native.load()


@needs_build
def test_the_built_libraries_are_those_of_the_sources():
    assert not native.STALE and native.LIB is not None, native.REASON
    assert not ray_native.STALE and ray_native.LIB is not None, ray_native.REASON
    for library, source in ((native.LIBRARY, native.SOURCE), (ray_native.LIBRARY, ray_native.SOURCE)):
        path = built(library)
        assert native.source_mismatch(ctypes.CDLL(path), path, source) is None


@needs_build
def test_a_library_built_from_another_source_is_refused(tmp_path, reload_after):
    changed = tmp_path / "modrob_ode_native.c"
    with open(native.SOURCE) as f:
        changed.write_text(f.read() + "/* changed after the build */\n")
    reload_after.setattr(native, "SOURCE", str(changed))
    native.load()
    assert native.STALE and native.LIB is None and not native.DISABLED
    for text in (built(native.LIBRARY), str(changed), "out of date", "`make build`",
                 "MODROB_PHYSICS_NATIVE=0"):
        assert text in native.REASON
    with pytest.raises(SimulationError, match="out of date.*make build"):
        World()
    with pytest.raises(SimulationError, match="out of date"):
        World(native=True)
    assert not World(native=False).native              # the pure-Python path, asked for


def test_a_library_without_a_checksum_is_out_of_date():
    text = native.source_mismatch(ctypes.CDLL(None), "/x/libmodrob_ode_native.so", native.SOURCE)
    assert "/x/libmodrob_ode_native.so is out of date" in text and "no checksum" in text
    assert native.source_mismatch(ctypes.CDLL(None), "/x/lib.so", "/no/such/source.c") is None


@needs_build
def test_the_pure_python_physics_on_purpose_does_not_look_at_the_library(tmp_path, reload_after):
    changed = tmp_path / "modrob_ode_native.c"
    changed.write_text("/* another source */\n")
    reload_after.setattr(native, "SOURCE", str(changed))
    reload_after.setenv("MODROB_PHYSICS_NATIVE", "0")
    native.load()
    assert native.DISABLED and not native.STALE and native.LIB is None
    assert not World().native


@needs_build
def test_ray_sensors_refuse_a_stale_ray_caster(tmp_path, reload_after):
    changed = tmp_path / "modrob_raycast.c"
    changed.write_text("/* another source */\n")
    reload_after.setattr(ray_native, "SOURCE", str(changed))
    ray_native.load()
    assert ray_native.STALE and ray_native.LIB is None
    with pytest.raises(RuntimeError, match="libmodrob_raycast.so is out of date.*make build"):
        raycast.make_caster(World())
    assert raycast.make_caster(World(), kind="numpy").name == "numpy"
