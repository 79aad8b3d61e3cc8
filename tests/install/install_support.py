"""What the install tests share (test_install.py, test_pip_install.py): running a command with its echo,
and reading a value of the build's CMake cache."""
import pathlib
import subprocess


def run(cmd, **kwargs):
    print("+", " ".join(str(c) for c in cmd), flush=True)
    return subprocess.run([str(c) for c in cmd], check=True, **kwargs)


def cache_value(build, name):
    for line in (pathlib.Path(build) / "CMakeCache.txt").read_text().splitlines():
        if line.startswith(name + ":"):
            return line.split("=", 1)[1]
    return None
