"""The README's Python example (tools/python/examples/cloth_ball.py) runs as written."""
import os
import pathlib
import subprocess
import sys

import mccd
from conftest import SOURCE_DIR


def test_readme_example(cloth_ball_frames, tmp_path):
    # the module these tests import, wherever the example runs from
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=str(pathlib.Path(mccd.__file__).resolve().parents[1]))
    r = subprocess.run([sys.executable, str(SOURCE_DIR / "tools" / "python" / "examples" / "cloth_ball.py"),
                        str(cloth_ball_frames)], cwd=tmp_path, env=env, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert lines[0].startswith("113854 contacts, the earliest at t = ")
    assert "'steps': 44" in r.stdout
    assert (tmp_path / "contacts_per_step.png").read_bytes()[:4] == b"\x89PNG"
    assert (tmp_path / "drape.csv").read_text().startswith("frame,substep,kind")
