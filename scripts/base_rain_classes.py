"""base_rain_classes.py SPP [WIDTH HEIGHT] | --shape [WIDTH HEIGHT]: the supercell's cloud base and rain shaft seen from the
ground (datasets/scenes/supercell_chaser.json) in the fast renderer's settings against the Monte
Carlo reference with skylight (docs/ACCURACY.md, "Base and rain shaft"). Both draw a black ground
(the reference's), so whole frames compare.

Pixel classes come from the file itself, not from either renderer: each pixel's ray is marched
through the CM1 fields (nearest sample, 125 m steps). The cloud base is the lowest level where cloud
water exceeds 0.1 g/kg in at least a tenth as many cells as on the cloudiest level; *rain* pixels see rain of optical depth >= 0.3 below it
(its extinction 2 pi r^2 N from the mixing ratio and number, r the mean-volume radius) before
their visible surface; *base* pixels look up (ray at least 3 degrees above the horizon), see
cloud (alpha > 0.9) whose visible surface lies within 750 m above the base, and
no such rain. The visible surface and alpha are the fast frame's (opacity-weighted depth along
the ray; the lighting does not move them).
--shape prints, without a reference, what the file gives the shaft: the rain's extent below the
base against the base's height, and the rain pixels' optical depth and opacity along their rays.
Run from the repository's root with PYTHONPATH=build/release/python and /usr/bin/python3."""
import sys

import netCDF4
import numpy as np

import stormlight

SCENE = "datasets/scenes/supercell_chaser.json"
DATA = "../shared/data/cm1/cm1_supercell_t070min.nc"
SETTINGS = {
    "default (diffuse sunlight, skylight, xi 0)": {},
    "no diffuse sunlight, xi 0.05 (the paper's model with the sky)": {"diffuse_sunlight": "off", "xi": 0.05},
    "no diffuse sunlight, no skylight, xi 0.05 (the paper's model)": {"diffuse_sunlight": "off", "skylight": "off",
                                                                      "xi": 0.05},
    "diffuse sunlight, no skylight": {"skylight": "off"},
}


def rays(camera, width, height):
    p, t, up = (np.asarray(camera[k], float) for k in ("position", "target", "up"))
    fwd = (t - p) / np.linalg.norm(t - p)
    right = np.cross(fwd, up)
    right /= np.linalg.norm(right)
    upv = np.cross(right, fwd)
    tan_half = np.tan(np.radians(camera["fov"]) / 2)
    x = (2 * (np.arange(width) + 0.5) / width - 1) * tan_half * width / height
    y = (1 - 2 * (np.arange(height) + 0.5) / height) * tan_half
    d = fwd + x[None, :, None] * right + y[:, None, None] * upv
    return p, d / np.linalg.norm(d, axis=2, keepdims=True), fwd


def fields():
    ds = netCDF4.Dataset(DATA)
    ds.set_auto_mask(False)
    prs, th = ds["prs"][0].astype(float), ds["th"][0].astype(float)
    rho = prs / (287.0 * th * (prs / 1e5) ** (287.0 / 1004.0))
    qc, qr, nr = (ds[v][0].astype(float) for v in ("qc", "qr", "ncr"))
    z = ds["zh"][:].astype(float) * 1000.0
    count = (qc > 1e-4).sum(axis=(1, 2))
    levels = np.where(count >= 0.1 * count.max())[0]
    base = z[levels.min()] if count.max() > 0 else np.inf
    n = np.maximum(nr * rho, 1e-3)
    r = np.cbrt(3 * rho * qr / (4 * np.pi * 1000.0 * n))
    beta_rain = np.where(qr > 1e-6, 2 * np.pi * r ** 2 * n, 0.0)
    return beta_rain, z, base


def rain_depth(p, d, placement, beta_rain, z, base, t_stop):
    """Rain optical depth below the base along each ray up to t_stop (nearest sample, 125 m steps)."""
    origin, spacing = np.asarray(placement["origin"]), np.asarray(placement["spacing"])
    nx, ny, nz = placement["shape"]
    tau = np.zeros(d.shape[:2])
    step = 125.0
    for t in np.arange(step / 2, 150000.0, step):
        x = p + t * d
        i = np.rint((x[..., 0] - origin[0]) / spacing[0]).astype(int)
        j = np.rint((x[..., 1] - origin[1]) / spacing[1]).astype(int)
        k = np.searchsorted(z, x[..., 2])
        inside = (i >= 0) & (i < nx) & (j >= 0) & (j < ny) & (k < nz) & (x[..., 2] < base) & (t < t_stop)
        tau[inside] += step * beta_rain[k[inside], j[inside], i[inside]]
    return tau


def classes(frame, placement, rain, width, height):
    """The pixel classes, and the pixels' rays (origin, directions); rain is fields()'s."""
    beta_rain, z, base = rain
    p, d, fwd = rays(frame.camera, width, height)
    t_surface = np.where(frame.alpha > 0.01, frame.depth / np.maximum(d @ fwd, 1e-6), np.inf)
    tau = rain_depth(p, d, placement, beta_rain, z, base, t_surface)
    height_surface = np.where(np.isfinite(t_surface), p[2] + np.where(np.isfinite(t_surface), t_surface, 0) * d[..., 2],
                              np.inf)
    wet = (tau >= 0.3) & (frame.alpha > 0.3)
    cloud_base = (d[..., 2] > np.sin(np.radians(3))) & (frame.alpha > 0.9) & (height_surface < base + 750) & ~wet
    return {"base": cloud_base, "rain": wet}, (p, d)


def shaft_shape(placement, frame, masks, ray, rain):
    """The shaft's shape in the file: columns whose rain below the base has vertical optical depth
    >= 0.3, their extent against the base's height; the rain pixels' rain optical depth along
    their whole rays and the frame's opacity there."""
    beta_rain, z, base = rain
    tau = rain_depth(*ray, placement, beta_rain, z, base, np.inf)
    dz = np.diff(np.concatenate(([0.0], 0.5 * (z[1:] + z[:-1]), [z[-1]])))
    below = (z < base)[:, None, None]
    column = (beta_rain * dz[:, None, None] * below).sum(axis=0)
    wet = column >= 0.3
    dx, dy = placement["spacing"][0], placement["spacing"][1]
    jj, ii = np.nonzero(wet)
    area = wet.sum() * dx * dy
    print(f"rain below the {base:.0f} m base: {wet.sum()} columns of vertical optical depth >= 0.3 "
          f"(median {np.median(column[wet]):.2f}), {area / 1e6:.0f} km^2, spanning "
          f"{(ii.max() - ii.min() + 1) * dx / 1e3:.1f} km east-west and {(jj.max() - jj.min() + 1) * dy / 1e3:.1f} km "
          f"north-south; width / height of an equal-area disc: {2 * np.sqrt(area / np.pi) / base:.0f}")
    r = masks["rain"]
    q = np.percentile(tau[r], [25, 50, 75])
    a = np.percentile(frame.alpha[r], [25, 50, 75])
    print(f"rain pixels ({r.sum()}): rain optical depth along the whole ray, quartiles {q[0]:.2f} {q[1]:.2f} {q[2]:.2f}; "
          f"the frame's opacity {a[0]:.2f} {a[1]:.2f} {a[2]:.2f}")


def main():
    args = sys.argv[1:]
    if len(args) not in (1, 3):
        sys.exit(__doc__)
    size = {"width": int(args[1]), "height": int(args[2])} if len(args) == 3 else {"width": 96, "height": 60}
    scene = stormlight.Scene.from_json(SCENE, ground_albedo=0, **size)
    frame = scene.render()
    rain = fields()
    base = rain[2]
    masks, ray = classes(frame, scene.placement(), rain, size["width"], size["height"])
    if args[0] == "--shape":
        shaft_shape(scene.placement(), frame, masks, ray, rain)
        return
    spp = int(args[0])
    ref = scene.reference(spp=spp, seed=5, skylight=True)
    print(f"{SCENE} at {size['width']}x{size['height']}, reference {spp} spp with skylight; cloud base "
          f"{base:.0f} m; pixels: base {masks['base'].sum()}, rain {masks['rain'].sum()}")
    for name, cls in masks.items():
        if not cls.any():
            continue
        b = ref.rgb[cls]
        noise = float(np.sqrt((ref.stderr[cls] ** 2).sum()) / b.size / b.mean())
        print(f"  {name}: the reference's mean {b.mean():.4g} (its noise {noise:.3f} of it)")
    for label, options in SETTINGS.items():
        a_frame = stormlight.Scene.from_json(SCENE, ground_albedo=0, **size, **options).render()
        parts = []
        for name, cls in masks.items():
            if cls.any():
                a, b = a_frame.rgb[cls], ref.rgb[cls]
                parts.append(f"{name} bias {(a - b).sum() / b.sum():+.3f}, mean rel. {np.abs(a - b).sum() / b.sum():.3f}, "
                             f"blue/red {a[:, 2].mean() / a[:, 0].mean():.2f} (ref. {b[:, 2].mean() / b[:, 0].mean():.2f})")
        print(f"  {label}: " + "; ".join(parts))


if __name__ == "__main__":
    main()
