"""What the command line's number-computing subcommands give, for Python: frame metrics (``stormlight
compare``) and the sun's position (``stormlight sun``)."""
from __future__ import annotations

import datetime as _dt
from typing import Any, Dict, Union

import numpy as np

from . import _stormlight
from .frame import Frame


def compare(a: Frame, b: Frame) -> Dict[str, Any]:
    """The metrics of ``stormlight compare a.exr b.exr`` with b the reference: relative RMSE over
    R, G, B, the largest absolute difference, PSNR (dB, peak = b's largest value) and the pixels
    where either is NaN or infinite."""
    if a.rgba.shape != b.rgba.shape:
        raise ValueError(f"compare: the frames are {a.width}x{a.height} and {b.width}x{b.height}")
    return _stormlight.compare(a.width, a.height, np.ascontiguousarray(a.rgba, dtype=np.float32),
                               np.ascontiguousarray(b.rgba, dtype=np.float32))


def sun_position(date: Union[str, _dt.datetime], lat: float, lon: float) -> Dict[str, Any]:
    """The sun's apparent position at a UTC date (ISO 8601 text or a datetime; a naive datetime is
    UTC) over (lat, lon) degrees, as ``stormlight sun`` and render's placement compute it (Meeus,
    with refraction): elevation, azimuth (compass, clockwise from north), zenith, the true
    elevation, declination, hour angle, Julian day, the unit vector toward the sun (east, north,
    up) and whether it is night."""
    if isinstance(date, _dt.datetime):
        if date.tzinfo is not None:
            date = date.astimezone(_dt.timezone.utc).replace(tzinfo=None)
        date = date.isoformat() + "Z"
    return _stormlight.sun_position(date, float(lat), float(lon))


def sky(eye_height: float, view_elevation: float, view_azimuth: float, sun_elevation: float,
        sun_azimuth: float, distance: float = float("inf"), earth: str = "flat",
        wavelengths: str = "rgb") -> Dict[str, Any]:
    """As ``stormlight sky --json``: the single-scattered sky radiance gathered along a view ray
    from an eye at eye_height (m) toward (elevation, compass azimuth) degrees, to ``distance`` m
    or the top of the air, and the ray's transparency, per wavelength (``rgb``: 650, 515, 440 nm;
    ``spectral``: 16), with the sunlight reaching the eye, all for a top-of-atmosphere sun of
    irradiance 1 (Riley et al. 2004 eqs. 9-15, docs/SKY.md). ``earth`` "flat" is the paper's air
    mass, "round" the Chapman function's."""
    if earth not in ("flat", "round"):
        raise ValueError("earth must be flat or round")
    if wavelengths not in ("rgb", "spectral"):
        raise ValueError("wavelengths must be rgb or spectral")
    return _stormlight.sky(float(eye_height), float(view_elevation), float(view_azimuth), float(sun_elevation),
                           float(sun_azimuth), float(distance), earth == "round", wavelengths == "spectral")
