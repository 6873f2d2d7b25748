"""stormlight.open, Storm.from_xarray and Storm.from_arrays: the same storm the same frame, by
every way in; the readers' rules and errors; an analytic sphere."""
import numpy as np
import pytest
import xarray as xr

import stormlight
from test_scene import SMALL, assert_same_frame, cli_frame, flags

KATRINA = "data/wrf/wrf_katrina2005_d02_mercator_wsm3_4t.nc"
SUPERCELL = "data/cm1/cm1_supercell_t070min.nc"


def test_open_reads_what_the_file_holds(shared, datasets):
    wrf = stormlight.open(shared / KATRINA, time=2)
    info = wrf.info()
    assert info["format"] == "WRF" and wrf.grid["shape"] == (48, 48, 14) and info["projection"]["map_proj"] == 3
    assert wrf.times == ["2005-08-28T12:00:00", "2005-08-28T15:00:00", "2005-08-28T18:00:00", "2005-08-28T21:00:00"]
    assert [s["variable"] for s in wrf.species] == ["QCLOUD", "QRAIN"] and wrf.load_options["time"] == 2
    cm1 = stormlight.open(shared / SUPERCELL)
    assert cm1.info()["format"] == "CM1" and cm1.times == ["+4200s"]
    with pytest.raises(ValueError, match="out of range"):
        stormlight.open(shared / KATRINA, time=4)
    with pytest.raises(ValueError, match="scene option"):
        stormlight.open(shared / KATRINA, width=64)
    with pytest.raises(OSError):
        stormlight.open(datasets / "no-such-storm.nc")


def test_info_is_the_command_lines(cli, shared):
    import json
    storm = stormlight.open(shared / KATRINA, time=1, field="cloud=QCLOUD,rain=none", stride=2)
    got = storm.info()
    command = json.loads(cli("info", "--json", shared / KATRINA, "--time", 1, "--field", "cloud=QCLOUD,rain=none",
                             "--stride", 2))
    for d in (got, command):
        del d["memory"]["available_bytes"]  # what the machine has free now
    assert got == command
    assert got["uniform_grid"]["nx"] == 24 and got["time_index"] == 1  # the stride and time reached the load


def three_ways(cli, tmp_path, path, time, ds, **options):
    """The frames of one storm through open(), from_xarray() and the command line."""
    opened = stormlight.Scene(stormlight.open(path, time=time), **options).render()
    with stormlight.Storm.from_xarray(ds) as storm:
        through_xarray = stormlight.Scene(storm, **options).render()
    command = cli_frame(cli, tmp_path, path, "--time", time, *flags(options))
    assert_same_frame(opened, command)
    assert_same_frame(through_xarray, command)
    return command


def test_wrf_three_ways(cli, shared, tmp_path):
    path = shared / KATRINA
    frame = three_ways(cli, tmp_path, path, 2, xr.open_dataset(path).isel(Time=[2]), max_fields=4,
                       view_elevation=25, fov=30, **SMALL)
    assert frame.alpha.max() > 0.5


def test_cm1_three_ways(cli, shared, tmp_path):
    path = shared / SUPERCELL
    frame = three_ways(cli, tmp_path, path, 0, xr.open_dataset(path), field="hail=qg", **SMALL)
    assert frame.alpha.max() > 0.5


def write_cf_storm(path):
    """A CF-NetCDF file as another model's post-processing writes one: latitudes from the north,
    heights in km, cloud water in g/kg on a latitude-longitude grid, density given."""
    import netCDF4
    with netCDF4.Dataset(path, "w") as f:
        f.Conventions = "CF-1.8"
        for name, n in (("time", 1), ("height", 12), ("lat", 20), ("lon", 24)):
            f.createDimension(name, n)
        t = f.createVariable("time", "f8", ("time",))
        t.units, t.calendar = "hours since 2024-06-21 00:00:00", "standard"
        t[:] = [18.0]
        h = f.createVariable("height", "f4", ("height",))
        h.units, h.standard_name, h.positive = "km", "height", "up"
        h[:] = 0.5 + 0.5 * np.arange(12)
        lat = f.createVariable("lat", "f8", ("lat",))
        lat.units, lat.standard_name = "degrees_north", "latitude"
        lat[:] = 35.5 - 0.01 * np.arange(20)
        lon = f.createVariable("lon", "f8", ("lon",))
        lon.units, lon.standard_name = "degrees_east", "longitude"
        lon[:] = -97.6 + 0.01 * np.arange(24)
        z, y, x = np.meshgrid(np.arange(12), np.arange(20), np.arange(24), indexing="ij")
        blob = np.exp(-((x - 11.5) ** 2 + (y - 9.5) ** 2) / 30.0 - (z - 5.0) ** 2 / 6.0)
        q = f.createVariable("clw", "f4", ("time", "height", "lat", "lon"))
        q.units, q.standard_name = "g kg-1", "mass_fraction_of_cloud_liquid_water_in_air"
        q[0] = 0.8 * blob
        rho = f.createVariable("rho", "f4", ("time", "height", "lat", "lon"))
        rho.units, rho.standard_name = "kg m-3", "air_density"
        rho[0] = 1.2 * np.exp(-(0.5 + 0.5 * z) / 8.0)


def test_cf_three_ways(cli, tmp_path):
    path = tmp_path / "cf_storm.nc"
    write_cf_storm(path)
    frame = three_ways(cli, tmp_path, path, 0, xr.open_dataset(path), view_elevation=10, **SMALL)
    assert frame.alpha.max() > 0.1


def sphere_cells(q0, n=40, cell=100.0, radius=1500.0):
    """A homogeneous sphere of cloud water q0 (kg/kg): the cells whose centres lie within 1.5 km of
    (0, 0, 2.5 km), in air of density 1 kg m-3."""
    x = (np.arange(n) - n / 2 + 0.5) * cell
    z = 500.0 + cell * np.arange(n)
    zz, yy, xx = np.meshgrid(z, x, x, indexing="ij")
    inside = xx ** 2 + yy ** 2 + (zz - 2500.0) ** 2 <= radius ** 2
    return np.where(inside, q0, 0.0).astype(np.float32), x, z


def sphere(q0):
    q, x, z = sphere_cells(q0)
    return stormlight.Storm.from_arrays(cloud=q, x=x, y=x, z=z, density=np.ones_like(q))


def test_sphere_from_arrays():
    # Seen from 60 km along +y, no air: each pixel's transparency is exp(-tau) along its ray.
    view = dict(width=65, height=65, no_atmosphere=True, camera_position=(0, -60000, 2500),
                camera_target=(0, 0, 2500), fov=4, sun_elevation=40, sun_azimuth=180)
    tau = {}
    for q0 in (1e-6, 2e-6):
        with sphere(q0) as storm:
            t = stormlight.Scene(storm, **view).render().transparency
            tau[q0] = -np.log(t.astype(np.float64))
    centre = tau[1e-6][32, 32]
    assert 0.05 < centre < 1.0
    # The known optical depth: the representative droplets (no sizes in a CF file) number rho q / m
    # per m^3, each of the tables' extinction cross-section averaged over the three wavelengths
    # (extinction is grey), along the centre line's chord of 30 cells (its samples at x = -50 and
    # +50 m both hold 30 inside the sphere; the trilinear field integrates to one cell per sample).
    # The light volume's march steps half a cell from the box's face, so each step lies between
    # two samples and its midpoint value is exact.
    sigma = np.mean([stormlight.optics.properties("cloud", nm)["sigma_ext"] for nm in (650.0, 515.0, 440.0)])
    mass = stormlight.optics.properties("cloud", 550.0)["particle_mass"]
    known = 1.0 * 1e-6 / mass * sigma * 30 * 100.0
    with sphere(1e-6) as storm:
        marched = stormlight.Scene(storm, light_volume=True, **view).render().transparency[32, 32]
    print(f"sphere: tau through the centre {-np.log(marched):.7f} against {known:.7f} known; slicer {centre:.7f}")
    assert abs(-np.log(marched) / known - 1.0) < 1e-4, (-np.log(marched), known)
    assert abs(centre / known - 1.0) < 1e-4, (centre, known)  # the slicer, too
    # Optical depth is linear in the water: twice the water, exp(-2 tau) through the centre.
    assert abs(tau[2e-6][32, 32] / centre - 2.0) < 1e-4
    # Outside the sphere the air is empty.
    assert tau[1e-6][32, 0] < 1e-6 and tau[1e-6][0, 32] < 1e-6
    # The image integral of tau is beta times the sphere's volume; tau at the centre is beta
    # times its chord. The grid's field is trilinear between cell centres, whose hat functions each
    # integrate to one cell's volume (cell^3) and, along a line through a row of centres, to one
    # cell: volume / chord = (cells inside) cell^2 / (centres inside on the central rows). The
    # central ray runs at z = 2.5 km (a row of centres) between the rows at x = -50 and +50 m.
    q, x, z = sphere_cells(1.0)
    k = int(np.argmin(np.abs(z - 2500.0)))
    chord_cells = 0.5 * (q[k, :, 19].sum() + q[k, :, 20].sum())
    expected = q.sum() * 100.0 ** 2 / chord_cells
    pixel = 2.0 * 60000.0 * np.tan(np.radians(2.0)) / 65  # metres per pixel at the sphere's centre
    measured = tau[1e-6].sum() * pixel ** 2 / centre
    print(f"sphere: volume / chord {measured:.1f} m2 against {expected:.1f} m2 from the cells")
    assert abs(measured / expected - 1.0) < 0.005, (measured, expected)


def test_arrays_bad_input_raises_one_line(tmp_path):
    good = sphere(1e-6)
    x = np.arange(40) * 100.0
    z = 500.0 + 100.0 * np.arange(40)
    q = np.zeros((40, 40, 40), np.float32)
    q[20, 20, 20] = 1e-3
    rho = np.ones_like(q)
    view = dict(width=16, height=16, sun_elevation=40, sun_azimuth=180)

    def raises(kind, says, **arrays):
        with pytest.raises(kind) as e:
            stormlight.Scene(stormlight.Storm.from_arrays(**{"x": x, "y": x, "z": z, "density": rho, **arrays}),
                             **view).render()
        assert says in str(e.value) and "\n" not in str(e.value), str(e.value)
        assert "stormlight-" not in str(e.value)  # no temporary file's name: what it was made from

    nan = q.copy()
    nan[3, 4, 5] = np.nan
    raises(ValueError, "'cloud' has NaN", cloud=nan)
    negative = q.copy()
    negative[3, 4, 5] = -0.5
    raises(ValueError, "not a physical mixing ratio", cloud=negative)
    raises(ValueError, "furlongs", cloud=xr.DataArray(q, attrs={"units": "furlongs"}))
    raises(ValueError, "'rain' has shape (40, 40, 39)", cloud=q, rain=q[:, :, :39])
    raises(ValueError, "'x' must be 1-D of length 40", cloud=q, x=x[:30])
    raises(ValueError, "give density, or pressure and temperature", cloud=q, density=None)
    # g/kg with its units reads as kg/kg / 1000: the same frame as the same water in kg/kg.
    a = stormlight.Scene(stormlight.Storm.from_arrays(cloud=q, x=x, y=x, z=z, density=rho), **view).render()
    b = stormlight.Scene(stormlight.Storm.from_arrays(cloud=xr.DataArray(q * 1000.0, attrs={"units": "g kg-1"}),
                                                      x=x, y=x, z=z, density=rho), **view).render()
    assert np.allclose(a.rgba, b.rgba, rtol=1e-5, atol=1e-7)
    path = good.path
    good.close()
    import os
    assert not os.path.exists(path)


def test_series_equals_each_time_alone(shared, capsys):
    view = dict(max_fields=4, view_elevation=25, fov=30, **SMALL)
    scene = stormlight.Scene(shared / KATRINA, **view)
    frames = list(scene.series(times=[0, 3], progress=True))
    assert "series: frame 2/2" in capsys.readouterr().err
    for t, frame in zip((0, 3), frames):
        alone = stormlight.Scene(shared / KATRINA, time=t, **view).render()
        assert np.array_equal(frame.rgba, alone.rgba)
    assert not np.array_equal(frames[0].rgba, frames[1].rgba)  # the storm moved
    assert len(list(stormlight.Scene(shared / KATRINA, width=16, height=12, **{k: SMALL[k] for k in
                                                                           ("sun_elevation", "sun_azimuth")}).series())) == 4
    files = [shared / "data/cm1/cm1_supercell_t060min.nc", shared / "data/cm1/cm1_supercell_t070min.nc"]
    cm1 = list(stormlight.Scene(files[0], **SMALL).series(files=files))
    assert np.array_equal(cm1[1].rgba, stormlight.Scene(files[1], **SMALL).render().rgba)


def test_arrays_in_another_dimension_order():
    q, x, z = sphere_cells(1e-6)
    view = dict(width=24, height=24, no_atmosphere=True, sun_elevation=40, sun_azimuth=180)
    plain = stormlight.Scene(stormlight.Storm.from_arrays(cloud=q, x=x, y=x, z=z, density=np.ones_like(q)),
                             **view).render()
    # (x, z, y) by name, with a coordinate that says its axis, and by dims given.
    cube = xr.DataArray(q, dims=("height", "south_north", "west_east")).transpose("west_east", "height", "south_north")
    rho = xr.DataArray(np.ones_like(q), dims=("height", "south_north", "west_east"))
    named = stormlight.Scene(stormlight.Storm.from_arrays(cloud=cube, x=x, y=x, z=z, density=rho), **view).render()
    assert np.array_equal(named.rgba, plain.rgba)
    odd = xr.DataArray(q, dims=("k", "j", "i")).transpose("i", "k", "j")
    given = stormlight.Scene(stormlight.Storm.from_arrays(cloud=odd, x=x, y=x, z=z, density=np.ones_like(q),
                                                          dims=("k", "j", "i")), **view).render()
    assert np.array_equal(given.rgba, plain.rgba)
    with pytest.raises(ValueError, match="has dimensions"):
        stormlight.Storm.from_arrays(cloud=odd, x=x, y=x, z=z, density=np.ones_like(q), dims=("z", "y", "x"))


def test_arrays_with_number_concentrations():
    q, x, z = sphere_cells(2e-7)
    view = dict(width=24, height=24, no_atmosphere=True, sun_elevation=40, sun_azimuth=180)
    rho = np.ones_like(q)

    def transparency(**number):
        storm = stormlight.Storm.from_arrays(cloud=q, x=x, y=x, z=z, density=rho, number=number or None)
        sized = [s["sized"] for s in storm.species]
        return stormlight.Scene(storm, **view).render().transparency[12, 12], sized

    t_rep, sized = transparency()
    assert sized == [False]
    t_few, sized = transparency(cloud=np.full_like(q, 5e7))
    assert sized == [True]
    t_many, _ = transparency(cloud=np.full_like(q, 5e8))
    # Ten times the droplets of the same water: smaller, and more light taken out.
    assert t_many < t_few and -np.log(t_many) / -np.log(t_few) > 1.5
    with pytest.raises(ValueError, match="not a number per kg"):
        transparency(cloud=xr.DataArray(np.full_like(q, 5e7), attrs={"units": "m-3"}))
    with pytest.raises(ValueError, match="without rain"):
        transparency(rain=np.full_like(q, 5e7))
