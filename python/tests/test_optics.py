"""stormlight.optics: a particle table's values against what they must integrate to."""
import numpy as np
import pytest

import stormlight

ANGLES = np.linspace(0.0, 180.0, 18001)  # 0.01 degrees: ten points per table step


def integrals(particle, order=1):
    props = stormlight.optics.properties(particle, 550.0)
    ams = stormlight.optics.phase(particle, 550.0, ANGLES, order=order)
    w = np.radians(ANGLES)
    f = props["truncated_fraction"] ** order  # the forward Dirac's weight, at theta = 0
    norm = 2 * np.pi * np.trapz(ams * np.sin(w), w) + f
    mean_cos = 2 * np.pi * np.trapz(ams * np.sin(w) * np.cos(w), w) + f
    return props, ams, norm, mean_cos


@pytest.mark.parametrize("particle", ["cloud", "rain"])
def test_phase_functions_hold_the_energy_and_the_asymmetry(particle):
    props, ams, norm, mean_cos = integrals(particle)
    assert abs(norm - 1.0) < 1e-4  # P with its forward Dirac is normalised
    assert abs(mean_cos - props["asymmetry"]) < 1e-4  # its mean cosine is g
    assert 0.999 < props["albedo"] <= 1.0 and props["max_order"] >= 2
    _, _, norm2, _ = integrals(particle, order=2)
    assert abs(norm2 - 1.0) < 1e-4  # so is Ams_2, with the Dirac's weight f^2
    assert (ams >= 0).all()


def test_rain_shows_the_rainbow_at_descartes_angle():
    # Descartes: the ray of minimum deviation through a sphere of index n = 1.333 (water, 550 nm)
    # leaves at 180 + 2i - 4r with cos i = sqrt((n^2 - 1) / 3), sin r = sin i / n: 137.9 degrees.
    n = 1.333
    i = np.arccos(np.sqrt((n * n - 1.0) / 3.0))
    r = np.arcsin(np.sin(i) / n)
    descartes = np.degrees(np.pi + 2 * i - 4 * r)
    ams = stormlight.optics.phase("rain", 550.0, ANGLES)
    back = ANGLES > 120
    peak = ANGLES[back][np.argmax(ams[back])]
    assert abs(peak - descartes) < 1.0, (peak, descartes)


def test_bad_optics_input():
    with pytest.raises(ValueError, match="unknown particle 'sleet'"):
        stormlight.optics.phase("sleet", 550.0, [0.0])
    with pytest.raises(ValueError, match="outside 200..3000"):
        stormlight.optics.properties("cloud", 55.0)
    with pytest.raises(ValueError, match="last order"):
        stormlight.optics.phase("cloud", 550.0, [0.0], order=1000)


def test_sky_equals_the_command_line_and_beer_lambert(cli):
    import json
    got = stormlight.sky(100, 10, 180, 30, 200, earth="round")
    command = json.loads(cli("sky", "--eye-height", 100, "--view-elevation", 10, "--view-azimuth", 180,
                             "--sun-elevation", 30, "--sun-azimuth", 200, "--earth", "round", "--json"))
    for key in ("radiance", "transparency", "sunlight_at_eye", "wavelengths_nm"):
        assert np.allclose(got[key], command[key], rtol=1e-14, atol=0), key  # JSON keeps 15 digits
    # A horizontal ray at 2 km over 20 km of air of scale height H: exp(-beta_sl e^(-h/H) d).
    level = stormlight.sky(2000, 0, 90, 30, 200, distance=20000)
    for beta, t in zip(level["beta_sea_level"], level["transparency"]):
        expected = np.exp(-beta * np.exp(-2000 / level["scale_height_m"]) * 20000)
        assert abs(t - expected) < 1e-9 * expected
    assert stormlight.sky(0, 10, 0, -5, 0)["night"]
    with pytest.raises(ValueError):
        stormlight.sky(0, 95, 0, 30, 0)
