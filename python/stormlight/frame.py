"""A rendered frame: linear HDR RGBA as numpy arrays, its camera and its sun."""
from __future__ import annotations

import os
import tempfile
from typing import Any, Dict, Optional, Tuple

import numpy as np

from . import _stormlight


class Frame:
    """One frame of a Scene (or an EXR read back).

    ``rgba`` is premultiplied linear radiance relative to a top-of-atmosphere sun of irradiance 1
    per channel, the volume over the sky (float32, height x width x 4, rows from the top); ``rgb``
    is its colour, ``alpha`` the volume's coverage. ``transparency`` is the volume's exp(-tau)
    toward the eye (kept apart from alpha, which cannot hold one below float's epsilon),
    ``depth`` the distance along the view axis to what each pixel shows (+inf: sky). The arrays
    are read-only views of the one buffer the renderer returned, not copies; ``.copy()`` one to
    change it.
    """

    def __init__(self, rgba: np.ndarray, depth: np.ndarray, transparency: np.ndarray,
                 camera: Optional[Dict[str, Any]] = None,
                 sun_direction: Optional[Tuple[float, float, float]] = None,
                 exposure: float = 12.0, seconds: float = 0.0) -> None:
        self.rgba = rgba
        self.depth = depth
        self.transparency = transparency
        self.camera = camera
        self.sun_direction = sun_direction
        self.exposure = exposure
        self.seconds = seconds

    @classmethod
    def _from_render(cls, d: Dict[str, Any], exposure: float) -> "Frame":
        h, w = d["height"], d["width"]
        return cls(np.frombuffer(d["rgba"], dtype=np.float32).reshape(h, w, 4),
                   np.frombuffer(d["depth"], dtype=np.float32).reshape(h, w),
                   np.frombuffer(d["transparency"], dtype=np.float32).reshape(h, w),
                   camera=d["camera"], sun_direction=d["sun_direction"], exposure=exposure,
                   seconds=d["seconds"])

    @classmethod
    def read_exr(cls, path: "os.PathLike[str] | str", exposure: float = 12.0) -> "Frame":
        """An EXR that ``stormlight render`` (or ``save_exr``) wrote; transparency is 1 - A there."""
        d = _stormlight.read_exr(os.fspath(path))
        h, w = d["height"], d["width"]
        rgba = np.frombuffer(d["rgba"], dtype=np.float32).reshape(h, w, 4)
        return cls(rgba, np.frombuffer(d["depth"], dtype=np.float32).reshape(h, w), 1.0 - rgba[..., 3],
                   exposure=exposure)

    @property
    def width(self) -> int:
        return self.rgba.shape[1]

    @property
    def height(self) -> int:
        return self.rgba.shape[0]

    @property
    def rgb(self) -> np.ndarray:
        """Linear HDR colour (height x width x 3, a view of rgba)."""
        return self.rgba[..., :3]

    @property
    def alpha(self) -> np.ndarray:
        """The volume's coverage, 1 - its transparency (a view of rgba)."""
        return self.rgba[..., 3]

    def srgb(self, exposure: Optional[float] = None) -> np.ndarray:
        """The frame tone-mapped to 8-bit sRGB at ``exposure`` (the scene's by default), height x
        width x 3 uint8, exactly as ``to_png`` writes it: for matplotlib's ``imshow``."""
        data = _stormlight.srgb8(self.width, self.height, np.ascontiguousarray(self.rgba),
                                 self.exposure if exposure is None else float(exposure))
        return np.frombuffer(data, dtype=np.uint8).reshape(self.height, self.width, 3)

    def save_exr(self, path: "os.PathLike[str] | str", float32: bool = False) -> None:
        """Linear HDR RGBA plus Z, half floats unless float32 (as ``stormlight render``)."""
        _stormlight.write_exr(os.fspath(path), self.width, self.height, np.ascontiguousarray(self.rgba),
                              np.ascontiguousarray(self.depth), float32)

    def to_png(self, path: "os.PathLike[str] | str", exposure: Optional[float] = None) -> None:
        """Tone-mapped sRGB at ``exposure`` (the scene's by default), as ``stormlight render``."""
        _stormlight.write_png(os.fspath(path), self.width, self.height, np.ascontiguousarray(self.rgba),
                              self.exposure if exposure is None else float(exposure))

    def _repr_png_(self) -> bytes:
        """The tone-mapped frame, for notebooks."""
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "frame.png")
            self.to_png(path)
            with open(path, "rb") as f:
                return f.read()

    def __repr__(self) -> str:
        return f"<stormlight.Frame {self.width}x{self.height}>"
