#!/usr/bin/python3
# tools/plot_fields.py on the files of a short mesodpd run: a 2-D map, a 1-D profile with a slab fit and a
# 3-D grid each give their PNGs; a CSV that is not a fields file is refused with exit code 1.
# usage: test_plot_fields.py MESODPD_BINARY SOURCE_DIR
import contextlib
import importlib.util
import io
import os
import shutil
import subprocess
import sys
import tempfile

binary, source = sys.argv[1], sys.argv[2]
tool = os.path.join(source, "tools", "plot_fields.py")
work = tempfile.mkdtemp(prefix="mesodpd_plot_fields_")
config = """
[system]
box = [6.0, 4.0, 8.0]
seed = 3

[[species]]
name = "A"
density = 3.0

[run]
steps = 60

[output]
thermo_every = 20
progress = false

[[analysis.fields]]
name = "map"
bins = [6, 1, 8]
every = 5

[[analysis.fields]]
name = "profile"
bins = [1, 1, 16]
every = 5
centre = "z"
fit = "slab"

[[analysis.fields]]
name = "cube"
bins = [3, 2, 4]
every = 5
"""
with open(os.path.join(work, "c.toml"), "w") as f:
    f.write(config)
run = subprocess.run([binary, "run", "c.toml", "--out", "out"], cwd=work, capture_output=True, text=True)
assert run.returncode == 0, run.stdout + run.stderr
out = os.path.join(work, "out")


# The tool runs in this process (matplotlib is imported once, which keeps the test short).
spec = importlib.util.spec_from_file_location("plot_fields", tool)
plot_fields = importlib.util.module_from_spec(spec)
spec.loader.exec_module(plot_fields)


class Result:
    def __init__(self, returncode, stderr):
        self.returncode, self.stderr = returncode, stderr


def plot(*args):
    err = io.StringIO()
    try:
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
            code = plot_fields.main(list(args))
    except SystemExit as e:
        code = e.code
    return Result(code, err.getvalue())


def is_png(path):
    with open(path, "rb") as f:
        return f.read(8) == b"\x89PNG\r\n\x1a\n"


r = plot(os.path.join(out, "map.csv"))
assert r.returncode == 0, r.stderr
for name in ("density", "vx", "vy", "vz", "speed", "temperature"):
    path = os.path.join(out, f"map_{name}.png")
    assert os.path.isfile(path) and is_png(path), path
r = plot(os.path.join(out, "map.csv"), "--min-density", "2", "--prefix", "masked")
assert r.returncode == 0, r.stderr
assert is_png(os.path.join(out, "masked_speed.png"))
r = plot(os.path.join(out, "profile.csv"), "--out-dir", os.path.join(work, "pics"), "--prefix", "p")
assert r.returncode == 0, r.stderr
assert is_png(os.path.join(work, "pics", "p_profile.png"))
r = plot(os.path.join(out, "cube.csv"), "--average-axis", "y")
assert r.returncode == 0, r.stderr
assert is_png(os.path.join(out, "cube_speed.png"))
# Not a fields CSV: a clear error, exit code 1.
r = plot(os.path.join(out, "thermo.csv"))
assert r.returncode == 1 and "lacks column" in r.stderr, (r.returncode, r.stderr)
shutil.rmtree(work)
print("plot_fields.py: maps, profile and 3-D average drawn; bad input refused")
