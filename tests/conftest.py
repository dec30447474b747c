import os

# Off-screen rendering for any test that imports pyvista (no X server needed).
os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")

# Property tests draw the same examples on every run (CI must be reproducible);
# HYPOTHESIS_PROFILE=explore draws fresh random examples for a local search.
from hypothesis import settings  # noqa: E402

settings.register_profile("ci", derandomize=True, print_blob=True)
settings.register_profile("explore", derandomize=False, print_blob=True)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))


# The test session never writes into the user's cache folder: unless FLEXGEAR_CACHE_DIR names
# a cache to use (e.g. a shared one), meshes and reductions go to a temporary folder made
# for this session (subprocesses inherit it) and removed at its end.
import shutil  # noqa: E402
import tempfile  # noqa: E402

_SESSION_CACHE = None
if not os.environ.get("FLEXGEAR_CACHE_DIR", "").strip():
    _SESSION_CACHE = tempfile.mkdtemp(prefix="flexgear-test-cache-")
    os.environ["FLEXGEAR_CACHE_DIR"] = _SESSION_CACHE


# Run in parallel (pytest-xdist, ``-n``; ``make test`` does), every worker's BLAS and OpenMP
# pools take one thread: two workers on two cores with two BLAS threads each would run four
# threads on two cores. Set in the controller before it starts its workers (they and the
# subprocesses the tests start inherit it), where the environment does not already say.
BLAS_THREAD_VARS = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")


def pytest_configure(config):
    if getattr(config.option, "numprocesses", None) and not os.environ.get("PYTEST_XDIST_WORKER"):
        for name in BLAS_THREAD_VARS:
            os.environ.setdefault(name, "1")


def pytest_unconfigure(config):
    if _SESSION_CACHE is not None:
        shutil.rmtree(_SESSION_CACHE, ignore_errors=True)
