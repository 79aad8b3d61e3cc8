#!/usr/bin/env python3
"""tools/module_graph.py --check: this tree's include arrows all follow declared module dependencies,
and a copy of the tree in which core includes an engine header is refused, naming both modules."""
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

root = Path(sys.argv[1])
tool = root / "tools" / "module_graph.py"


def check(tree):
    r = subprocess.run([sys.executable, str(tool), str(tree), "--check"], capture_output=True, text=True)
    return r.returncode, r.stdout + r.stderr


rc, out = check(root)
assert rc == 0 and "none runs back up" in out, out
assert "| core |" in out and "| engine |" in out, out

with tempfile.TemporaryDirectory() as tmp:
    copy = Path(tmp)
    shutil.copytree(root / "src", copy / "src")
    shutil.copytree(root / "include", copy / "include")
    box = copy / "src" / "core" / "box.hpp"
    box.write_text('#include "engine/simulation.hpp"\n' + box.read_text())
    rc, out = check(copy)
    assert rc == 1, out
    assert "src/core includes a header of src/engine" in out, out
print("module graph check: ok")
