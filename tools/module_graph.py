#!/usr/bin/env python3
"""Files and lines per module of src/, and the include graph between modules.

    tools/module_graph.py [ROOT]          # ROOT: a source tree (default: this checkout)
    tools/module_graph.py --check         # exit 1 if an include runs against the declared dependencies

A module is a directory of src/; the public headers of include/mesodpd/ count for the module whose
CMakeLists.txt lists them in PUBLIC_HEADERS (or for `include` in a tree without module libraries).
An arrow A -> B means some file of A includes a header of B. With --check, every arrow must be a
dependency that src/<A>/CMakeLists.txt declares (DEPENDS of mesodpd_module, followed transitively):
the build refuses such an include anyway (each module sees only its dependencies' headers); the check
says which one, in words, for a tree that has not been built.
"""
import re
import sys
from collections import defaultdict
from pathlib import Path

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def modules_of(root: Path):
    src = root / "src"
    return sorted(p.name for p in src.iterdir() if p.is_dir())


def declared(root: Path, modules):
    """Module -> (target, DEPENDS targets, PUBLIC_HEADERS) from src/<module>/CMakeLists.txt."""
    out = {}
    for m in modules:
        cm = root / "src" / m / "CMakeLists.txt"
        if not cm.exists():
            continue
        text = cm.read_text()
        call = re.search(r"mesodpd_module\(([^)]*)\)", text, re.S)
        if not call:
            continue
        words = call.group(1).split()
        target, groups, key = words[0], defaultdict(list), None
        for w in words[1:]:
            if w in ("DIR", "SOURCES", "DEPENDS", "PUBLIC_HEADERS"):
                key = w
            elif key:
                groups[key].append(w)
        out[m] = (target, groups["DEPENDS"], groups["PUBLIC_HEADERS"])
    return out


def main(argv):
    check = "--check" in argv
    args = [a for a in argv if not a.startswith("--")]
    root = Path(args[0]) if args else Path(__file__).resolve().parent.parent
    modules = modules_of(root)
    decl = declared(root, modules)
    owner = {}  # public header name -> module
    for m, (_, _, headers) in decl.items():
        for h in headers:
            owner[h] = m

    files = defaultdict(list)
    for m in modules:
        files[m] = [p for p in (root / "src" / m).rglob("*") if p.suffix in (".cpp", ".hpp", ".cu", ".h")]
    for p in sorted((root / "include" / "mesodpd").glob("*.hpp")):
        files[owner.get(p.name, "include")].append(p)

    edges = defaultdict(set)
    for m, paths in files.items():
        for p in paths:
            for inc in INCLUDE.findall(p.read_text(errors="replace")):
                head = inc.split("/")[0]
                if head == "mesodpd":
                    target = owner.get(inc.split("/", 1)[1], "include")
                elif head in modules:
                    target = head
                else:
                    continue
                if target != m:
                    edges[m].add(target)

    total_files = total_lines = 0
    print("| module | files | lines |\n|---|---:|---:|")
    for m in sorted(files, key=lambda k: (k not in modules, k)):
        n = sum(len(p.read_text(errors="replace").splitlines()) for p in files[m])
        total_files += len(files[m])
        total_lines += n
        print(f"| {m} | {len(files[m])} | {n} |")
    print(f"| all | {total_files} | {total_lines} |\n")
    print("Include arrows (A -> modules whose headers A includes):\n")
    for m in sorted(edges):
        print(f"- {m} -> {', '.join(sorted(edges[m]))}")

    if not check:
        return 0
    if not decl:
        print("\nno module libraries declared in this tree: nothing to check")
        return 1
    target_of = {m: t for m, (t, _, _) in decl.items()}
    module_of = {t: m for m, t in target_of.items()}
    deps = {m: {module_of[d] for d in ds if d in module_of} for m, (_, ds, _) in decl.items()}

    def closure(m, seen=None):
        seen = set() if seen is None else seen
        for d in deps.get(m, ()):
            if d not in seen:
                seen.add(d)
                closure(d, seen)
        return seen

    bad = [(m, t) for m in sorted(edges) for t in sorted(edges[m]) if m in deps and t not in closure(m)]
    for m, t in bad:
        print(f"\nsrc/{m} includes a header of src/{t}, which src/{m}/CMakeLists.txt does not depend on")
    if not bad:
        print("\nevery arrow is a declared dependency: none runs back up the layers")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
