"""Stormlight for Python: render storm simulations (WRF, CM1, CF-NetCDF) with physically based light.

    import stormlight
    scene = stormlight.Scene("wrfout_d02.nc", time=2, width=640, height=360,
                             sun_elevation=8, sun_azimuth=250)
    frame = scene.render()          # linear HDR, numpy arrays
    frame.to_png("storm.png")

The keywords of ``Scene`` are the scene file's keys (docs/SCENES.md) with hyphens as
underscores; ``stormlight.options()`` lists them with their help. docs/PYTHON.md walks through it.
"""
from ._stormlight import version as _version
from . import optics
from .frame import Frame
from .numbers import compare, sky, sun_position
from .scene import Scene, options
from .storm import Storm, open  # noqa: A004

__version__ = _version()
__all__ = ["optics", "Frame", "Scene", "Storm", "compare", "open", "options", "sky", "sun_position", "__version__"]
