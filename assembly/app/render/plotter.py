"""The off-screen pyvista plotter of the images: pyvista loaded for off-screen rendering
(EGL when there is no X server), one plotter kept for many images, and its image written
as a PNG. pyvista is imported only when :func:`load_pyvista` is called (never at import of
this module)."""
from __future__ import annotations

import os


def load_pyvista():
    """Import pyvista for off-screen rendering (EGL when no X server)."""
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    import pyvista as pv

    pv.OFF_SCREEN = True
    return pv


#: zlib level of the PNG files: 3 writes in half the time of PIL's default 6, files ~15 % larger.
PNG_COMPRESS_LEVEL = 3


def save_png(pl, path) -> None:
    """The plotter's current image as a PNG file (PNG_COMPRESS_LEVEL)."""
    from PIL import Image
    Image.fromarray(pl.screenshot(None, return_img=True)).save(str(path), format="PNG",
                                                               compress_level=PNG_COMPRESS_LEVEL)


def kept_plotter(pv, window_size):
    """An off-screen plotter whose ``close()`` clears it for the next image; ``release()``
    closes it."""
    class KeptPlotter(pv.Plotter):
        def close(self, *args, **kwargs):
            self.clear()

        def release(self):
            pv.Plotter.close(self)

        def __del__(self):
            if getattr(self, "_initialized", False) and not self._closed:
                self.release()
            super().__del__()

    return KeptPlotter(off_screen=True, window_size=list(window_size))
