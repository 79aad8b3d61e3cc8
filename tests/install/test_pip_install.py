"""pip install --no-build-isolation --no-index of the source tree into a fresh virtual environment (with
the system's site-packages, for numpy, setuptools and wheel), then the installed package is imported from
the venv and runs a tiny simulation. Builds the library again from scratch in a temporary directory
(minutes on two cores, less with a warm ccache); writes nothing into the source tree, which it checks.

Usage: test_pip_install.py BUILD_DIR SOURCE_DIR  (the interpreter is the build's Python3_EXECUTABLE; exit 77,
skipped, when the build has no Python module)"""
import os
import pathlib
import shutil
import sys
import tempfile

build, source = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2]).resolve()
here = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(here))
import install_support  # noqa: E402
from install_support import run  # noqa: E402


def cache_value(name):
    return install_support.cache_value(build, name)


python = cache_value("Python3_EXECUTABLE")
if not python or not list((build / "python" / "mesodpd").glob("_core*.so")):
    print("this build has no Python module (pybind11-dev, python3-dev missing?): skipped")
    sys.exit(77)


def tree_state():
    # What a setuptools build leaves when it is not redirected: build/, *.egg-info, files in python/.
    names = set()
    for d in (source, source / "python", source / "python" / "mesodpd"):
        names |= {str(p.relative_to(source)) for p in d.iterdir()}
    return names


before = tree_state()
tmp = pathlib.Path(tempfile.mkdtemp(prefix="mesodpd-pip-"))
try:
    venv = tmp / "venv"
    run([python, "-m", "venv", "--system-site-packages", venv])
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PIP_INDEX_URL", "PIP_FIND_LINKS")}
    env.update(MESODPD_PIP_BUILD_DIR=str(tmp / "pip-build"), PIP_DISABLE_PIP_VERSION_CHECK="1")
    env.setdefault("CMAKE_BUILD_PARALLEL_LEVEL", "2")
    run([venv / "bin" / "pip", "install", "--no-build-isolation", "--no-index", "--no-cache-dir", source],
        env=env, cwd=tmp)
    run([venv / "bin" / "python", here / "tiny_run.py", venv], env=dict(env, OMP_NUM_THREADS="1"), cwd=tmp)

    after = tree_state()
    assert after == before, f"pip left {sorted(after - before)} in the source tree"
    print("test_pip_install: ok")
finally:
    if os.environ.get("MESODPD_KEEP_TMP"):
        print(f"kept {tmp}")
    else:
        shutil.rmtree(tmp, ignore_errors=True)
