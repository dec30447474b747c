import os

# Off-screen rendering for any test that imports pyvista (no X server needed).
os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
