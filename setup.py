"""pip install --no-build-isolation .  builds the Python module with CMake and installs it (docs/install.md).

Only Debian 12's own packages are needed (python3-setuptools, python3-wheel, python3-pip, plus the C++
build dependencies of scripts/install-deps): setuptools' build_ext step configures the CMake project
without tests and benchmarks, builds only the Python targets, and copies the compiled _core next to the
.py files of python/mesodpd/.

Environment:
  MESODPD_PIP_BUILD_DIR       where the CMake tree and setuptools' build files go (default: build-pip/
                              in the source tree; kept, so a second install rebuilds only what changed)
  MESODPD_CMAKE_ARGS          extra CMake configure arguments, split like a shell command line
  CMAKE_BUILD_PARALLEL_LEVEL  parallel build jobs (default: every core)
ccache is used as the compiler launcher when it is on PATH.
"""
import os
import pathlib
import re
import shlex
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent
# Every file setuptools writes (build/, *.egg-info) goes here instead of the source tree.
BUILD_DIR = pathlib.Path(os.environ.get("MESODPD_PIP_BUILD_DIR") or ROOT / "build-pip").resolve()


def project_version():
    # One version, the one in CMakeLists.txt's project() line.
    text = (ROOT / "CMakeLists.txt").read_text()
    match = re.search(r"project\(\s*mesodpd\s+VERSION\s+([0-9.]+)", text)
    if not match:
        raise RuntimeError("setup.py: no project(mesodpd VERSION ...) in CMakeLists.txt")
    return match.group(1)


class CMakeExtension(Extension):
    """The compiled module, built by CMake's target `target` rather than by setuptools' compiler."""

    def __init__(self, name, target):
        super().__init__(name, sources=[])
        self.target = target


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        if not isinstance(ext, CMakeExtension):
            return super().build_extension(ext)
        tree = pathlib.Path(self.build_temp).resolve() / "cmake"
        tree.mkdir(parents=True, exist_ok=True)
        configure = [
            "cmake", "-S", str(ROOT), "-B", str(tree),
            "-DCMAKE_BUILD_TYPE=Release",
            "-DMESODPD_TESTS=OFF", "-DMESODPD_BENCH=OFF", "-DMESODPD_CUDA_CHECK=OFF",
            "-DMESODPD_PYTHON=ON",
            # The interpreter running pip: the module must match its ABI (a venv's python3 included).
            f"-DPython3_EXECUTABLE={sys.executable}",
        ]
        extra = shlex.split(os.environ.get("MESODPD_CMAKE_ARGS", ""))
        if shutil.which("ccache") and not any(a.startswith("-DCMAKE_CXX_COMPILER_LAUNCHER") for a in extra):
            configure.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
        configure += extra
        build = ["cmake", "--build", str(tree), "--target", ext.target]
        # cmake --build reads CMAKE_BUILD_PARALLEL_LEVEL itself; without it, Makefiles build serially.
        if self.parallel:
            build += ["--parallel", str(self.parallel)]
        elif not os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL"):
            build += ["--parallel", str(os.cpu_count() or 1)]
        for cmd in (configure, build):
            print("setup.py:", shlex.join(cmd), flush=True)
            try:
                subprocess.run(cmd, check=True)
            except subprocess.CalledProcessError as e:
                raise RuntimeError(
                    f"setup.py: `{shlex.join(cmd)}` failed (exit {e.returncode}); the C++ dependencies "
                    "(pybind11-dev, python3-dev, ...) come from scripts/install-deps") from None
        # pybind11 names the module with this interpreter's suffix, the same one setuptools expects.
        built = sorted((tree / "python" / "mesodpd").glob("_core*.so"))
        if len(built) != 1:
            raise RuntimeError(f"setup.py: expected one _core*.so in {tree / 'python' / 'mesodpd'}, "
                               f"found {[p.name for p in built]} (is the Python module ON in the CMake output?)")
        dest = pathlib.Path(self.get_ext_fullpath(ext.name))
        dest.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built[0], dest)


BUILD_DIR.mkdir(parents=True, exist_ok=True)
setup(
    name="mesodpd",
    version=project_version(),
    description="Dissipative particle dynamics engine (C++20) with a Python interface",
    long_description=(ROOT / "docs" / "python.md").read_text(),
    long_description_content_type="text/markdown",
    python_requires=">=3.9",
    install_requires=["numpy"],
    extras_require={"plot": ["matplotlib"]},
    packages=["mesodpd"],
    package_dir={"": "python"},
    ext_modules=[CMakeExtension("mesodpd._core", target="mesodpd_python")],
    cmdclass={"build_ext": CMakeBuild},
    zip_safe=False,
    options={
        "build": {"build_base": str(BUILD_DIR / "setuptools")},
        "egg_info": {"egg_base": str(BUILD_DIR)},
    },
)
