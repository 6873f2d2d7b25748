"""A rendered scene: a storm file and the options of ``stormlight render`` (docs/SCENES.md).

The keywords are the scene file's keys with hyphens as underscores; their names, types, ranges
and help come from the one option table of the C library (``scene/sl_settings.h``), which also
checks every value, so a Scene accepts exactly what a scene file and the command line accept.
"""
from __future__ import annotations

import datetime as _dt
import json
import os
import sys
import time as _time
from typing import Any, Dict, Iterator, Mapping, Optional, Sequence, Union

import numpy as np

from . import _stormlight
from .frame import Frame

PathLike = Union[str, "os.PathLike[str]"]

_TABLE = {o["name"]: o for o in _stormlight.options()}


def options() -> Dict[str, Dict[str, Any]]:
    """The scene options by key (hyphenated, as in scene files): type, default, help, range."""
    return {name: dict(o) for name, o in _TABLE.items()}


def _key(name: str) -> str:
    key = name.replace("_", "-")
    if key not in _TABLE or key == "out":
        raise ValueError(f"unknown scene key '{key}'")
    return key


def _number(value: Any) -> str:
    if isinstance(value, bool):
        raise TypeError("a number, not a bool")
    value = float(value) if not isinstance(value, int) else value
    return repr(value)


def _text(key: str, value: Any) -> Optional[str]:
    """The option's value as the command line writes it; None for a flag that is off."""
    kind = _TABLE[key]["type"]
    if kind == "flag":
        if not isinstance(value, bool):
            raise ValueError(f"--{key} is a flag: give True or False")
        return "" if value else None
    if key == "date" and isinstance(value, _dt.datetime):
        if value.tzinfo is not None:
            value = value.astimezone(_dt.timezone.utc).replace(tzinfo=None)
        return value.isoformat() + "Z"
    if isinstance(value, str):
        return value
    if kind == "list" or isinstance(value, (list, tuple)):
        return ",".join(_number(v) for v in value)
    if isinstance(value, Mapping):  # field = {"hail": "QHAIL", "snow": None}
        return ",".join(f"{k}={'none' if v is None else v}" for k, v in value.items())
    return _number(value)


def _arguments(data: str, options: Mapping[str, Any]) -> list:
    """A storm file and options (hyphenated keys) as render's command-line arguments."""
    args = [data]
    for key, value in options.items():
        text = _text(key, value)
        if text is None:
            continue
        args.append("--" + key)
        if _TABLE[key]["type"] != "flag":
            args.append(text)
    return args


class Scene:
    """A storm and the options of ``stormlight render``, built once and rendered many times.

    ``Scene("wrfout.nc", width=640, height=360, sun_elevation=8, sun_azimuth=250)`` checks every
    option at once (``ValueError`` with the command line's one-line message). A Storm from
    ``stormlight.open``, ``Storm.from_xarray`` or ``Storm.from_arrays`` may stand in place of the
    path; its load options come with it. The storm is loaded, and the air and the particle tables
    built, on the first ``render()``, and kept for the next ones. ``close()`` (or a ``with``
    block) frees them at once.
    """

    def __init__(self, data: "PathLike | Storm", **options: Any) -> None:
        self._storm = None
        if hasattr(data, "load_options") and hasattr(data, "path"):  # a Storm: its file and load options
            self._storm = data  # kept: a Storm from arrays owns its file while the scene reads it
            options = {**{k.replace("-", "_"): v for k, v in data.load_options.items()}, **options}
            data = data.path
        self._data = os.fspath(data)
        self._options: Dict[str, Any] = {}
        for name, value in options.items():
            key = _key(name)
            if value is not None:
                self._options[key] = value
        self._renderer = _stormlight.Renderer(self._arguments())

    def _arguments(self) -> list:
        return _arguments(self._data, self._options)

    @property
    def data(self) -> str:
        """The storm file."""
        return self._data

    @property
    def options(self) -> Dict[str, Any]:
        """The options given (hyphenated keys), without the defaults."""
        return dict(self._options)

    @classmethod
    def from_json(cls, path: PathLike, **overrides: Any) -> "Scene":
        """A scene file (docs/SCENES.md), read by the C reader every front end uses (``data``
        relative to the file's folder); keywords override its keys."""
        path = os.fspath(path)
        args = _stormlight.scene_args(path)
        data = None
        options: Dict[str, Any] = {}
        i = 0
        while i < len(args):
            if not args[i].startswith("--"):
                data = args[i]
                i += 1
                continue
            key = args[i][2:]
            if _TABLE[key]["type"] == "flag":
                options[key.replace("-", "_")] = True
                i += 1
            else:
                options[key.replace("-", "_")] = args[i + 1]
                i += 2
        options.pop("out", None)
        options.update(overrides)
        data = options.pop("data", data)
        if data is None:
            raise ValueError(f"{path}: the scene names no \"data\" file")
        try:
            return cls(data, **options)
        except ValueError as e:
            raise ValueError(f"{path}: {e}") from None

    def to_json(self) -> str:
        """The scene as a scene file's JSON (``stormlight render --scene`` reads it)."""
        doc: Dict[str, Any] = {"data": self._data}
        for key, value in self._options.items():
            if isinstance(value, _dt.datetime):
                value = _text(key, value)
            elif isinstance(value, tuple):
                value = list(value)
            doc[key] = value
        return json.dumps(doc, indent=2)

    def render(self, threads: int = 0) -> Frame:
        """One frame, as ``stormlight render --cpu-composite`` draws it. Releases the GIL.

        threads: OpenMP threads for this render (0: the scene's ``threads`` or the default).
        """
        return Frame._from_render(self._call(self._renderer.render, threads=threads), self._exposure())

    def reference(self, spp: int = 16, seed: int = 1, skylight: bool = False, threads: int = 0) -> Frame:
        """The same frame by the Monte Carlo reference (docs/REFERENCE.md): ``spp`` samples per
        pixel and wavelength from ``seed``; ``skylight`` lets scattered paths that leave the
        storm collect the sky. ``frame.stderr`` holds each channel's standard error (height x
        width x 3). The same storm, sun, air, camera and round ground as ``render()``, so
        ``stormlight.compare(scene.render(), scene.reference())`` is the fast model's error."""
        d = self._call(self._renderer.reference, spp, seed=seed, skylight=skylight, threads=threads)
        frame = Frame._from_render(d, self._exposure())
        frame.stderr = np.frombuffer(d["stderr"], dtype=np.float32).reshape(frame.height, frame.width, 3)
        return frame

    def series(self, times: Optional[Sequence[int]] = None, files: Optional[Sequence[PathLike]] = None,
               threads: int = 0, progress: bool = False) -> Iterator[Frame]:
        """Frames of this scene at other times: ``times`` (indices into the storm file; all of
        them by default), or ``files`` (one file per time, as CM1 writes them), each with this
        scene's options. Each time loads its storm; the particle tables come from the on-disk cache
        after the first (docs/OPTICS.md), and each time's storm is freed before the next. With
        ``progress`` a line per frame goes to stderr."""
        if files is not None and times is not None:
            raise ValueError("series: give times or files, not both")
        if files is not None:
            steps = [(os.fspath(f), self._options.get("time")) for f in files]
        else:
            if times is None:
                times = range(max(_stormlight.storm_info(self._data)["ntimes"], 1))
            steps = [(self._data, int(t)) for t in times]
        for i, (data, t) in enumerate(steps):
            options = dict(self._options)
            if t is None:
                options.pop("time", None)
            else:
                options["time"] = t
            start = _time.perf_counter()
            with Scene(data, **{k.replace("-", "_"): v for k, v in options.items()}) as scene:
                frame = scene.render(threads=threads)
            if progress:
                print(f"series: frame {i + 1}/{len(steps)} ({os.path.basename(data)}, time {t if t is not None else 0}) "
                      f"in {_time.perf_counter() - start:.2f} s", file=sys.stderr, flush=True)
            yield frame

    def build(self) -> "Scene":
        """Loads the storm and builds the air, the tables and the renderer now (else on first render)."""
        self._call(self._renderer.build)
        return self

    def placement(self) -> Dict[str, Any]:
        """The grid (shape, origin and spacing in metres) and the sun (elevation, compass azimuth)."""
        return self._call(self._renderer.placement)

    def _call(self, fn, *args, **kwargs):
        """fn's errors about a Storm's temporary file name what it was made from instead."""
        try:
            return fn(*args, **kwargs)
        except (ValueError, OSError) as e:
            label = getattr(self._storm, "label", None)
            if label and self._data in str(e):
                raise type(e)(str(e).replace(self._data, label)) from None
            raise

    def _exposure(self) -> float:
        value = self._options.get("exposure")
        return float(value) if value is not None else float(_TABLE["exposure"]["default"])

    def close(self) -> None:
        """Frees the loaded storm, tables and renderer now (they are built again on use)."""
        self._renderer.close()

    def __enter__(self) -> "Scene":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    def __repr__(self) -> str:
        given = ", ".join(f"{k.replace('-', '_')}={v!r}" for k, v in self._options.items())
        return f"Scene({self._data!r}{', ' if given else ''}{given})"
