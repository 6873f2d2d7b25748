"""Where the tests find the command, the bundled storms and ../shared (set by CMake's python_tests)."""
import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def datasets() -> pathlib.Path:
    return pathlib.Path(os.environ.get("SL_DATASETS_DIR", ROOT / "datasets"))


@pytest.fixture(scope="session")
def shared() -> pathlib.Path:
    path = pathlib.Path(os.environ.get("SL_SHARED_DIR", ROOT.parent / "shared"))
    if not (path / "data").is_dir():
        pytest.fail(f"{path}/data is absent: these tests read the real storms from ../shared/data")
    return path


@pytest.fixture(scope="session")
def cli():
    """Runs `stormlight ARGS...` (the build's executable) and fails the test on a non-zero exit."""
    exe = os.environ.get("SL_STORMLIGHT", str(ROOT / "build/release/app/stormlight"))

    def run(*args):
        r = subprocess.run([exe, *map(str, args)], capture_output=True, text=True)
        assert r.returncode == 0, f"stormlight {' '.join(map(str, args))}: {r.stderr.strip()}"
        return r.stdout

    return run
