"""The particles' optics (render/optics, docs/OPTICS.md): what ``stormlight optics`` tabulates, for
one particle type at one wavelength. Tables are built once (Mie for droplets and drops, ray
tracing for ice) and kept in the on-disk cache."""
from __future__ import annotations

from typing import Any, Dict

import numpy as np

from . import _stormlight

PARTICLES = ("cloud", "rain", "ice", "snow", "graupel", "hail")


def phase(particle: str, wavelength: float, angles: Any, order: int = 1) -> np.ndarray:
    """Riley et al.'s multiple-scattering phase function Ams_order (1/sr) of a particle type at a
    wavelength (nm), at scattering angles in degrees: order 1 is the single-scattering phase
    function P. The forward peak within the truncation cone (half the sun's disk) is a Dirac of
    weight f^order apart from these values (``properties``'s truncated_fraction), so that
    2 pi int Ams_n sin(theta) dtheta = 1 - f^n."""
    theta = np.radians(np.asarray(angles, dtype=np.float64))
    d = _stormlight.optics(particle, float(wavelength), np.ascontiguousarray(theta.ravel()), int(order))
    return np.frombuffer(d["ams"], dtype=np.float64).reshape(theta.shape)


def properties(particle: str, wavelength: float) -> Dict[str, Any]:
    """A particle type's table at a wavelength (nm): sigma_ext (m^2 per representative particle),
    the representative particle's mass (kg; a storm's water over it is the number of particles the
    renderer puts in a cell where the scheme gives no sizes), single-scattering albedo, asymmetry g, truncated forward fraction f, the forward fractions
    F_n of eq. 23 and the last order the table holds."""
    d = _stormlight.optics(particle, float(wavelength), np.zeros(0), 1)
    d.pop("ams")
    return d
