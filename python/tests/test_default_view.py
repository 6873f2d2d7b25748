"""The storm chaser's default view (scene/scene_build.c, sl_camera_chaser): the CM1 supercell with no
camera option, drawn as `stormlight render` draws it, fills 20-70 % of the frame with condensate
and puts the horizon in the lower third; a wide deck keeps the orbit from above."""
import numpy as np

import stormlight

SUPERCELL = dict(field="hail=qg", origin=(35.2, -97.4))


def horizon_fraction(frame):
    """Where the sky meets the ground, as a fraction of the height from the top, in the columns the
    volume leaves clear from top to bottom: the first row whose background ray meets the ground."""
    rows = [np.nonzero(np.isfinite(frame.depth[:, x]))[0].min()
            for x in range(frame.width) if (frame.alpha[:, x] < 0.01).all() and np.isfinite(frame.depth[:, x]).any()]
    assert rows, "no column shows the horizon clear of the storm"
    return float(np.median(rows)) / frame.height


def test_supercell_from_the_ground(shared):
    with stormlight.open(shared / "data/cm1/cm1_supercell_t070min.nc", **SUPERCELL) as storm:
        frame = stormlight.Scene(storm, sun_elevation=30, sun_azimuth=225, width=160, height=100).render()
    camera = frame.camera
    assert camera["position"][2] < 10.0, "the camera stands on the ground"
    coverage = float((frame.alpha > 0.5).mean())
    assert 0.2 <= coverage <= 0.7, f"condensate covers {coverage:.2f} of the frame"
    assert horizon_fraction(frame) >= 2.0 / 3.0, "the horizon lies in the lower third"


def test_a_deck_keeps_the_orbit(datasets):
    with stormlight.open(datasets / "stratocumulus.nc") as storm:
        frame = stormlight.Scene(storm, width=64, height=48).render()
    assert frame.camera["position"][2] > 1000.0, "a deck too wide for a ground view is seen from above"
