"""A storm: a file the readers know (WRF, CM1, CF-NetCDF), an xarray Dataset laid out as one, or
numpy arrays.

Every storm is read by the C readers (io/, docs/DATA.md) with their rules and their one-line
errors. A Dataset or arrays are written once to a temporary NetCDF file, which the same reader
then reads. That write is the one copy of the data the package makes; the file is removed by
``close()`` or when the Storm is collected.
"""
from __future__ import annotations

import datetime as _dt
import json
import os
import tempfile
from typing import Any, Dict, List, Mapping, Optional, Sequence, Union

import numpy as np

from . import _stormlight
from .scene import _arguments, _key

PathLike = Union[str, "os.PathLike[str]"]

# The options that choose what is loaded (the rest are the scene's: sun, camera, lighting, ...).
LOAD_OPTIONS = ("time", "dz", "field", "particles", "max-fields", "droplet-number", "region", "levels",
                "stride", "max-memory", "earth", "curvature", "origin")

# The CF standard names the reader takes each particle type by (io/species.c).
_STANDARD_NAMES = {
    "cloud": "mass_fraction_of_cloud_liquid_water_in_air",
    "rain": "mass_fraction_of_rain_in_air",
    "ice": "mass_fraction_of_cloud_ice_in_air",
    "snow": "mass_fraction_of_snow_in_air",
    "graupel": "mass_fraction_of_graupel_in_air",
    "hail": "mass_fraction_of_hail_in_air",
}


class Storm:
    """A storm file and the options it is loaded with (``stormlight.open``)."""

    def __init__(self, path: PathLike, time: Optional[int] = None, _owned: bool = False, **load_options: Any):
        self._owned = False
        self.path = os.fspath(path)
        self._owned = _owned
        self.label = None  # what errors name instead of a temporary file
        self._info = _stormlight.storm_info(self.path)  # OSError / ValueError naming the file
        self.load_options: Dict[str, Any] = {}
        for name, value in load_options.items():
            key = _key(name)
            if key not in LOAD_OPTIONS:
                raise ValueError(f"'{key}' is a scene option, not a load option: give it to Scene")
            if value is not None:
                self.load_options[key] = value
        if time is not None:
            if not 0 <= int(time) < max(self._info["ntimes"], 1):
                raise ValueError(f"{self.path}: time {time} is out of range (the file holds "
                                 f"{self._info['ntimes']})")
            self.load_options["time"] = int(time)

    def info(self) -> Dict[str, Any]:
        """``stormlight info --json`` of this storm at its time with its load options, as a dict:
        the file's grid and the loaded uniform grid, extent, terrain, placement and projection,
        scheme, species with where their sizes come from, size tables, field statistics, memory,
        times. Loads the storm (the properties below do not)."""
        return json.loads(_stormlight.info_json(_arguments(self.path, self.load_options)))

    @property
    def times(self) -> List[str]:
        """The file's times as ISO 8601 in its calendar; CM1's seconds since the run's start as "+Ns"."""
        if self._info["times"]:
            return [t.replace("_", "T") for t in self._info["times"]]
        return [f"+{s:g}s" for s in self._info["elapsed_seconds"]]

    @property
    def grid(self) -> Dict[str, Any]:
        """Mass points (nx, ny, nz), horizontal spacing (m), projection and vertical coordinate."""
        i = self._info
        return {"shape": i["shape"], "spacing": i["spacing"], "map_proj": i["map_proj"], "vertical": i["vertical"]}

    @property
    def species(self) -> List[Dict[str, Any]]:
        """The hydrometeor variables found and the particle types they feed."""
        return [dict(s) for s in self._info["species"]]

    def scene(self, **options: Any):
        """A Scene of this storm (``Scene(storm, **options)``)."""
        from .scene import Scene
        return Scene(self, **options)

    @classmethod
    def from_xarray(cls, ds: Any, time: Optional[int] = None, **load_options: Any) -> "Storm":
        """A Dataset laid out as a file the readers know (WRF, CM1, CF), for example a WRF file
        opened with xarray and cut with ``.isel(Time=[2])``: written to a temporary NetCDF file
        and read by the same reader, with the same rules and errors as the file."""
        path = _temporary_path()
        try:
            ds.to_netcdf(path)
            storm = cls(path, time=time, _owned=True, **load_options)
            storm.label = "Storm.from_xarray"
            return storm
        except BaseException:
            _remove(path)
            raise

    @classmethod
    def from_arrays(cls, cloud: Any = None, rain: Any = None, ice: Any = None, snow: Any = None,
                    graupel: Any = None, hail: Any = None, *, x: Any = None, y: Any = None, z: Any = None,
                    heights: Any = None, density: Any = None, pressure: Any = None, temperature: Any = None,
                    lat: Any = None, lon: Any = None, time: Optional[_dt.datetime] = None,
                    number: Optional[Mapping[str, Any]] = None, dims: Optional[Sequence[str]] = None,
                    **load_options: Any) -> "Storm":
        """A storm from arrays of shape (z, y, x): hydrometeor mass fractions (kg/kg, or with a CF
        ``units`` attribute such as ``g kg-1``), on x/y in metres (or lat/lon in degrees) and
        heights z (1-D, m) or ``heights`` (3-D, m), with the air's ``density`` (kg m-3) or its
        ``pressure`` (Pa) and ``temperature`` (K). Written as a CF-NetCDF file (docs/DATA.md)
        that the CF reader reads: the same unit conversions, checks and one-line errors (NaN,
        negative values beyond the clamping rule, unknown units) as a file. ``number`` maps a
        hydrometeor to its number concentration per kg of air (two-moment schemes' number mixing
        ratio, kg-1), linked to it as a CF ancillary variable: its sizes then follow from (q, N)
        (docs/DATA.md, "Sizes"). DataArrays are put in
        (z, y, x) order by their dimensions' names: ``dims`` names them in that order, else each
        dimension's coordinate (its CF ``axis`` or ``standard_name``) or its name (``height``,
        ``lat``, ``west_east``, ...) says which axis it is."""
        fields = {k: v for k, v in dict(cloud=cloud, rain=rain, ice=ice, snow=snow, graupel=graupel,
                                         hail=hail).items() if v is not None}
        path = _temporary_path()
        try:
            _write_cf(path, fields, x, y, z, heights, density, pressure, temperature, lat, lon, time, dims,
                      number or {})
            storm = cls(path, _owned=True, **load_options)
            storm.label = "Storm.from_arrays"
            taken = {s["variable"] for s in storm.species if s["number_variable"]}
            for k, n in (number or {}).items():
                if k not in taken:
                    units = getattr(n, "attrs", {}).get("units")
                    raise ValueError(f"from_arrays: number['{k}'] in '{units}' is not a number per kg of air "
                                     "(give kg-1: a number per m3 over the air's density)")
            return storm
        except BaseException:
            _remove(path)
            raise

    def close(self) -> None:
        """Removes the temporary file of a Storm made from a Dataset or arrays."""
        if self._owned:
            _remove(self.path)
            self._owned = False

    def __enter__(self) -> "Storm":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    def __del__(self) -> None:
        self.close()

    def __repr__(self) -> str:
        i = self._info
        return f"<stormlight.Storm {i['kind']} {i['shape']} x {i['ntimes']} times: {self.path}>"


def open(path: PathLike, time: Optional[int] = None, **load_options: Any) -> Storm:  # noqa: A001
    """A storm file (WRF, CM1, CF-NetCDF) at a time index, with the load options of docs/SCENES.md
    (field, particles, region, levels, stride, dz, origin, curvature, ...)."""
    return Storm(path, time=time, **load_options)


def _temporary_path() -> str:
    fd, path = tempfile.mkstemp(prefix="stormlight-", suffix=".nc")
    os.close(fd)
    return path


def _remove(path: str) -> None:
    try:
        os.remove(path)
    except FileNotFoundError:
        pass


def _values(name: str, a: Any) -> "tuple[np.ndarray, Optional[str]]":
    """An array's values (float, as given) and its CF units attribute, if it has one."""
    units = None
    attrs = getattr(a, "attrs", None)
    if isinstance(attrs, Mapping):
        units = attrs.get("units")
    values = np.asarray(a)
    if values.dtype.kind not in "fiu":
        raise ValueError(f"from_arrays: '{name}' is not numeric ({values.dtype})")
    return values.astype(np.float64 if values.dtype == np.float64 else np.float32), units


# Dimension names that say which axis they are, where no coordinate or CF attribute says it.
_AXIS_NAMES = {
    "z": ("z", "height", "level", "lev", "bottom_top", "zh", "altitude", "model_level_number"),
    "y": ("y", "lat", "latitude", "south_north", "yh", "rlat"),
    "x": ("x", "lon", "longitude", "west_east", "xh", "rlon"),
}


def _axis_of(a: Any, dim: str) -> Optional[str]:
    """Which axis (z, y, x) a DataArray's dimension is: its coordinate's CF ``axis`` or
    ``standard_name``, else its name."""
    coord = getattr(a, "coords", {}).get(dim) if hasattr(a, "coords") else None
    attrs = getattr(coord, "attrs", {}) if coord is not None else {}
    axis = str(attrs.get("axis", "")).lower()
    if axis in ("x", "y", "z"):
        return axis
    std = attrs.get("standard_name", "")
    for name, axis in (("latitude", "y"), ("longitude", "x"), ("projection_y_coordinate", "y"),
                       ("projection_x_coordinate", "x"), ("height", "z"), ("altitude", "z")):
        if std == name:
            return axis
    for axis, names in _AXIS_NAMES.items():
        if dim.lower() in names:
            return axis
    return None


def _ordered(name: str, a: Any, dims: Optional[Sequence[str]]) -> Any:
    """A 3-D DataArray transposed to (z, y, x) by its dimensions' names: the given ``dims`` (in
    z, y, x order), else what its coordinates or names say. Plain arrays are (z, y, x) already."""
    if not hasattr(a, "dims") or not hasattr(a, "transpose") or len(a.dims) != 3:
        return a
    if dims is not None:
        if set(dims) != set(a.dims):
            raise ValueError(f"from_arrays: '{name}' has dimensions {tuple(a.dims)}, not {tuple(dims)}")
        return a.transpose(*dims)
    axes = {_axis_of(a, d): d for d in a.dims}
    if set(axes) != {"z", "y", "x"}:
        return a  # nothing says otherwise: taken as (z, y, x)
    return a.transpose(axes["z"], axes["y"], axes["x"])


def _write_cf(path, fields, x, y, z, heights, density, pressure, temperature, lat, lon, time, dims=None,
              number=None) -> None:
    import netCDF4

    if not fields:
        raise ValueError("from_arrays: give at least one of cloud, rain, ice, snow, graupel, hail")
    number = {k: _ordered(f"number['{k}']", v, dims) for k, v in (number or {}).items()}
    for k in number:
        if k not in fields:
            raise ValueError(f"from_arrays: number['{k}'] without {k}")
    fields = {k: _ordered(k, v, dims) for k, v in fields.items()}
    heights, density = _ordered("heights", heights, dims), _ordered("density", density, dims)
    pressure, temperature = _ordered("pressure", pressure, dims), _ordered("temperature", temperature, dims)
    data = {k: _values(k, v) for k, v in fields.items()}
    shape = next(iter(data.values()))[0].shape
    if len(shape) != 3:
        raise ValueError(f"from_arrays: the fields are (z, y, x); '{next(iter(data))}' has shape {shape}")
    for k, (v, _) in data.items():
        if v.shape != shape:
            raise ValueError(f"from_arrays: '{k}' has shape {v.shape}, the first field {shape}")
    nz, ny, nx = shape
    horizontal = (("x", x), ("y", y)) if lat is None and lon is None else (("lon", lon), ("lat", lat))
    for (name, a), n in zip(horizontal, (nx, ny)):
        if a is None:
            raise ValueError("from_arrays: give x and y (m) or lat and lon (degrees)")
        if np.ndim(a) != 1 or np.size(a) != n:
            raise ValueError(f"from_arrays: '{name}' must be 1-D of length {n}, it has shape {np.shape(a)}")
    if (z is None) == (heights is None):
        raise ValueError("from_arrays: give z (1-D heights of the levels) or heights (3-D), not both")
    if z is not None and (np.ndim(z) != 1 or np.size(z) != nz):
        raise ValueError(f"from_arrays: 'z' must be 1-D of length {nz}, it has shape {np.shape(z)}")
    if heights is not None and np.shape(heights) != shape:
        raise ValueError(f"from_arrays: 'heights' has shape {np.shape(heights)}, the fields {shape}")
    if density is None and (pressure is None or temperature is None):
        raise ValueError("from_arrays: give density, or pressure and temperature")
    air = {"air_density": density} if density is not None else {"air_pressure": pressure,
                                                                "air_temperature": temperature}
    for name, a in air.items():
        if np.shape(a) != shape:
            raise ValueError(f"from_arrays: '{name}' has shape {np.shape(a)}, the fields {shape}")

    with netCDF4.Dataset(path, "w", format="NETCDF4_CLASSIC") as f:
        f.Conventions = "CF-1.8"
        f.source = "stormlight.Storm.from_arrays"
        dims = ("z", "y", "x")
        if time is not None:
            f.createDimension("time", 1)
            dims = ("time",) + dims
            t = f.createVariable("time", "f8", ("time",))
            t.units, t.calendar, t.standard_name = "seconds since 1970-01-01 00:00:00", "standard", "time"
            if time.tzinfo is not None:
                time = time.astimezone(_dt.timezone.utc).replace(tzinfo=None)
            t[:] = (time - _dt.datetime(1970, 1, 1)).total_seconds()
        for name, n in zip(("z", "y", "x"), shape):
            f.createDimension(name, n)

        def put(name, a, dimensions, units, **attrs):
            values, given_units = _values(name, a)
            v = f.createVariable(name, "f8" if values.dtype == np.float64 else "f4", dimensions)
            units = given_units if given_units is not None else units
            if units is not None:
                v.units = units
            for k, value in attrs.items():
                setattr(v, k, value)
            v[:] = values.reshape(v.shape)

        if lat is None:
            put("x", x, ("x",), "m", standard_name="projection_x_coordinate", axis="X")
            put("y", y, ("y",), "m", standard_name="projection_y_coordinate", axis="Y")
        else:
            put("lon", lon, ("x",), "degrees_east", standard_name="longitude", axis="X")
            put("lat", lat, ("y",), "degrees_north", standard_name="latitude", axis="Y")
        if z is not None:
            put("z", z, ("z",), "m", standard_name="height", axis="Z", positive="up")
        else:
            level = f.createVariable("z", "i4", ("z",))
            level.standard_name, level.axis, level.positive = "model_level_number", "Z", "up"
            level[:] = np.arange(nz)
            put("altitude", heights, dims, "m", standard_name="altitude")
        for name, a in air.items():
            put(name, a, dims, {"air_density": "kg m-3", "air_pressure": "Pa", "air_temperature": "K"}[name],
                standard_name=name)
        for k, (values, units) in data.items():
            v = f.createVariable(k, "f8" if values.dtype == np.float64 else "f4", dims)
            v.standard_name = _STANDARD_NAMES[k]
            v.units = units if units is not None else "kg kg-1"
            v[:] = values.reshape(v.shape)
            if k in number:
                if np.shape(number[k]) != shape:
                    raise ValueError(f"from_arrays: number['{k}'] has shape {np.shape(number[k])}, the fields {shape}")
                put(f"number_{k}", number[k], dims, "kg-1")
                v.ancillary_variables = f"number_{k}"
