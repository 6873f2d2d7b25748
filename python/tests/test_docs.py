"""Every python snippet of docs/PYTHON.md runs, in order, in one namespace, from the repository's root."""
import os
import pathlib
import re

ROOT = pathlib.Path(__file__).resolve().parents[2]


def test_python_md_snippets_run(capsys):
    text = (ROOT / "docs/PYTHON.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert len(blocks) >= 3
    here = os.getcwd()
    os.chdir(ROOT)
    try:
        (ROOT / "out").mkdir(exist_ok=True)
        namespace = {}
        for i, code in enumerate(blocks):
            exec(compile(code, f"docs/PYTHON.md snippet {i + 1}", "exec"), namespace)
    finally:
        os.chdir(here)
    printed = capsys.readouterr().out
    assert "(300, 480, 3) float32" in printed and "unknown scene key 'colour'" in printed
    assert (ROOT / "out/python_supercell.png").stat().st_size > 1000
    assert "\n0.0\n" in printed  # the xarray cut and the file give one frame
    assert (ROOT / "out/python_bubble.png").stat().st_size > 1000
    assert (ROOT / "out/python_katrina.mp4").stat().st_size > 1000
    assert (ROOT / "out/python_notebook.png").stat().st_size > 1000
