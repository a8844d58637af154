"""The one place a pyvista plotter is made: off-screen, with its settings passed in, no global state.

Nothing here sets ``pv.OFF_SCREEN`` or leaves the environment changed. VTK chooses its window class when
the window is constructed, from ``VTK_DEFAULT_OPENGL_WINDOW``; without an X display it first tries X and
logs "bad X server connection" on every plotter. So, headless and only while the window is constructed,
that variable names the EGL window, and the previous environment is restored right after.
"""
from __future__ import annotations

import os
from contextlib import contextmanager
from dataclasses import dataclass

__all__ = ["RenderSettings", "off_screen_plotter"]

_WINDOW_VARIABLE = "VTK_DEFAULT_OPENGL_WINDOW"


@dataclass(frozen=True)
class RenderSettings:
    window_px: tuple[int, int] = (1000, 750)
    background: str = "white"
    shape: tuple[int, int] = (1, 1)

    def __post_init__(self):
        if len(self.window_px) != 2 or min(self.window_px) < 16:
            raise ValueError(f"window_px must be two sizes >= 16 px, got {self.window_px}")
        if len(self.shape) != 2 or min(self.shape) < 1:
            raise ValueError(f"shape must be (rows, columns) >= 1, got {self.shape}")


@contextmanager
def _headless_window_class():
    if os.environ.get("DISPLAY") or _WINDOW_VARIABLE in os.environ:
        yield  # a display (or the user's explicit choice): VTK's own choice stands
        return
    os.environ[_WINDOW_VARIABLE] = "vtkEGLRenderWindow"
    try:
        yield
    finally:
        os.environ.pop(_WINDOW_VARIABLE, None)


def off_screen_plotter(settings: RenderSettings = RenderSettings()):
    """A new off-screen ``pyvista.Plotter`` with ``settings`` applied to every subplot."""
    import pyvista as pv

    with _headless_window_class():
        plotter = pv.Plotter(off_screen=True, window_size=list(settings.window_px), shape=settings.shape)
    for row in range(settings.shape[0]):
        for col in range(settings.shape[1]):
            plotter.subplot(row, col)
            plotter.set_background(settings.background)
    plotter.subplot(0, 0)
    return plotter
