"""skylight_share.py SCENE.json SPP [SCENE.json SPP ...]: the skylight's term in the fast renderer
against the Monte Carlo reference's (docs/ACCURACY.md, "Skylight"). Each scene is drawn by both with
skylight on and off; the reference takes the same seed both times, so its paths are the same and
the difference is the sky's term with little noise. Prints, over the pixels the volume covers by
more than half, the mean sky term of each, their ratio, and the reference's whole radiance.
Run from the repository's root with the package importable (PYTHONPATH=build/release/python) and
Debian's /usr/bin/python3."""
import sys

import stormlight


def share(path, spp):
    frames = {}
    for sky in ("off", "on"):
        scene = stormlight.Scene.from_json(path, skylight=sky)
        fast = scene.render()
        frames["fast", sky], frames["ref", sky] = fast.rgb, scene.reference(spp=spp, seed=3, skylight=sky == "on").rgb
        covered = fast.alpha > 0.5
    fast_sky = float((frames["fast", "on"] - frames["fast", "off"])[covered].mean())
    ref_sky = float((frames["ref", "on"] - frames["ref", "off"])[covered].mean())
    whole = float(frames["ref", "on"][covered].mean())
    print(f"{path}: {spp} spp; sky term fast {fast_sky:.4g}, reference {ref_sky:.4g} (ratio {fast_sky / ref_sky:.2f}); "
          f"the reference's radiance {whole:.4g} (the sky {100 * ref_sky / whole:.1f} %)")


if __name__ == "__main__":
    args = sys.argv[1:]
    if not args or len(args) % 2:
        sys.exit(__doc__)
    for i in range(0, len(args), 2):
        share(args[i], int(args[i + 1]))
