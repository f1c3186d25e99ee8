"""The Python examples run at small sizes."""
import os
import pathlib
import subprocess
import sys

import mgelastic
from conftest import SOURCE_DIR

EXAMPLES = SOURCE_DIR / "examples" / "python"


def run(script, *args, cwd):
    # The module this suite imports, whatever PYTHONPATH (maybe relative) found it.
    env = dict(os.environ, PYTHONPATH=str(pathlib.Path(mgelastic.__file__).parent))
    return subprocess.run([sys.executable, str(EXAMPLES / script), *args], cwd=cwd, check=True,
                          capture_output=True, text=True, env=env)


def test_cantilever_sweep_writes_a_png(tmp_path):
    png = tmp_path / "sweep.png"
    result = run("cantilever_sweep.py", "--resolution", "16", "--threads", "1", "--output",
                 str(png), cwd=tmp_path)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert result.stdout.count("tip deflection") == 7


def test_keyframed_arm_follows_the_script(tmp_path):
    result = run("keyframed_arm.py", "--resolution", "16", "--frames", "4", "--threads", "1",
                 cwd=tmp_path)
    lines = [line for line in result.stdout.splitlines() if line.startswith("frame")]
    assert len(lines) == 4
