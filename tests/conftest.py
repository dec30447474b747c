import os

# Off-screen rendering for any test that imports pyvista (no X server needed).
os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")

# Property tests draw the same examples on every run (CI must be reproducible);
# HYPOTHESIS_PROFILE=explore draws fresh random examples for a local search.
from hypothesis import settings  # noqa: E402

settings.register_profile("ci", derandomize=True, print_blob=True)
settings.register_profile("explore", derandomize=False, print_blob=True)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))
