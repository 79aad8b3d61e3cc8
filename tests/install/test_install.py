"""cmake --install of the built tree into a temporary prefix, then what a user does with it: build a
separate CMake project against find_package(mesodpd) and run it, run the installed command, import the
installed Python package. Reads the build tree only (it builds nothing there), so it cannot race with a
build; everything it writes is under a temporary directory, removed afterwards (MESODPD_KEEP_TMP=1 keeps it).

Usage: test_install.py BUILD_DIR SOURCE_DIR CXX_COMPILER [LAUNCHER]   (tests/install/CMakeLists.txt)"""
import os
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile

build, source = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
cxx = sys.argv[3]
launcher = sys.argv[4] if len(sys.argv) > 4 and sys.argv[4] else None
here = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(here))
import install_support  # noqa: E402
from install_support import run  # noqa: E402


def cache_value(name):
    return install_support.cache_value(build, name)


tmp = pathlib.Path(tempfile.mkdtemp(prefix="mesodpd-install-"))
try:
    prefix = tmp / "prefix"
    run(["cmake", "--install", build, "--prefix", prefix])

    # The command.
    mesodpd = prefix / "bin" / "mesodpd"
    version = run([mesodpd, "--version"], capture_output=True, text=True).stdout
    assert re.match(r"mesodpd \d+\.\d+\.\d+", version), version
    run([mesodpd, "check", source / "examples" / "fluid" / "fluid.toml"], stdout=subprocess.DEVNULL)

    # The headers: exactly include/mesodpd/*.hpp, each including only the standard library and each other.
    installed = sorted(p.name for p in (prefix / "include" / "mesodpd").iterdir())
    assert installed == sorted(p.name for p in (source / "include" / "mesodpd").glob("*.hpp")), installed
    assert sorted(p.name for p in (prefix / "include").iterdir()) == ["mesodpd"]
    for header in (prefix / "include" / "mesodpd").iterdir():
        for quoted in re.findall(r'#include\s+"([^"]+)"', header.read_text()):
            assert quoted.startswith("mesodpd/") and (prefix / "include" / quoted).is_file(), \
                f"{header.name} includes {quoted}, which is not an installed public header"

    # The library and the package; the exported targets must not point back into the build or source tree.
    # (libmesodpd*.a: one archive today, one per module once the library is split.)
    libs = list(prefix.glob("lib*/libmesodpd*.a")) + list(prefix.glob("lib*/*/libmesodpd*.a"))
    assert libs, "no libmesodpd*.a installed"
    package = list(prefix.glob("lib*/**/cmake/mesodpd"))
    assert len(package) == 1, package
    names = sorted(p.name for p in package[0].iterdir())
    for want in ("mesodpdConfig.cmake", "mesodpdConfigVersion.cmake", "mesodpdTargets.cmake"):
        assert want in names, names
    for f in package[0].glob("mesodpdTargets*.cmake"):
        text = f.read_text()
        for tree in (str(source.resolve()), str(build.resolve())):
            assert tree not in text, f"{f.name} mentions {tree}"

    # A separate project, configured and built in the temporary directory.
    consumer = tmp / "consumer"
    configure = ["cmake", "-S", here / "consumer", "-B", consumer, f"-DCMAKE_PREFIX_PATH={prefix}",
                 f"-DCMAKE_CXX_COMPILER={cxx}", "-DCMAKE_BUILD_TYPE=Release"]
    if launcher:
        configure.append(f"-DCMAKE_CXX_COMPILER_LAUNCHER={launcher}")
    run(configure)
    run(["cmake", "--build", consumer])
    run([consumer / "consumer"], env=dict(os.environ, OMP_NUM_THREADS="1"))

    # The Python package, imported from the prefix alone (the build tree is not on the path).
    pydir = cache_value("MESODPD_PYTHON_INSTALL_DIR")
    python = cache_value("Python3_EXECUTABLE")
    if pydir and python:
        site = pathlib.Path(pydir) if os.path.isabs(pydir) else prefix / pydir
        env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
        env.update(PYTHONPATH=str(site), OMP_NUM_THREADS="1")
        run([python, here / "tiny_run.py", site], env=env, cwd=tmp)
    else:
        print("no Python module in this build: its install is not checked")
    print("test_install: ok")
finally:
    if os.environ.get("MESODPD_KEEP_TMP"):
        print(f"kept {tmp}")
    else:
        shutil.rmtree(tmp, ignore_errors=True)
