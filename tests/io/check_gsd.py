# Checks a GSD file written by mesodpd's GsdWriter against expected values, using the reference
# readers of the `gsd` Python package (the C reader behind gsd.hoomd.open and the pure-Python
# gsd.pygsd), so the test proves interoperability rather than agreement with our own reader.
#
# usage: check_gsd.py FILE.gsd EXPECTED.json
# EXPECTED.json: {"frames": [{"step": int, "N": int, "box": [Lx, Ly, Lz],
#                 optional "types": [str], "typeid": [int], "mass": [float],
#                 "position": [[x, y, z]], "velocity": [[...]], "image": [[...]],
#                 "force": [[...]], "id": [int]}]}
# Reals are the double values the writer converts to float32; they must match bit for bit after
# the same conversion. Exit status 0 when everything matches; otherwise a message on stderr.
import json
import sys

import numpy as np
import gsd.hoomd
import gsd.pygsd


def fail(message):
    print("check_gsd: " + message, file=sys.stderr)
    sys.exit(1)


def check_array(label, actual, expected, dtype):
    expected = np.asarray(expected, dtype=dtype)
    actual = np.asarray(actual)
    if actual.dtype != np.dtype(dtype):
        fail(f"{label}: dtype {actual.dtype}, expected {np.dtype(dtype)}")
    if actual.shape != expected.shape:
        fail(f"{label}: shape {actual.shape}, expected {expected.shape}")
    if not np.array_equal(actual, expected):
        bad = np.argwhere(actual != expected)[0]
        fail(f"{label}: first mismatch at {tuple(bad)}: {actual[tuple(bad)]} != {expected[tuple(bad)]}")


def check_trajectory(traj, frames, reader):
    if len(traj) != len(frames):
        fail(f"[{reader}] {len(traj)} frames in file, expected {len(frames)}")
    for k, want in enumerate(frames):
        snap = traj[k]
        where = f"[{reader}] frame {k}"
        if int(snap.configuration.step) != want["step"]:
            fail(f"{where}: step {snap.configuration.step}, expected {want['step']}")
        if int(snap.configuration.dimensions) != 3:
            fail(f"{where}: dimensions {snap.configuration.dimensions}, expected 3")
        check_array(where + " box", snap.configuration.box, list(want["box"]) + [0, 0, 0], np.float32)
        if int(snap.particles.N) != want["N"]:
            fail(f"{where}: N = {snap.particles.N}, expected {want['N']}")
        if snap.particles.N > 0:
            # HOOMD's box convention, checked on every file: -L/2 <= x < L/2 against the float32 box.
            half = np.asarray(snap.configuration.box[:3], dtype=np.float32) / np.float32(2)
            pos = snap.particles.position
            if not (np.all(pos >= -half) and np.all(pos < half)):
                fail(f"{where}: positions outside [-L/2, L/2): min {pos.min(axis=0)}, max {pos.max(axis=0)}, "
                     f"L/2 = {half}")
        if "types" in want and list(snap.particles.types) != want["types"]:
            fail(f"{where}: types {snap.particles.types}, expected {want['types']}")
        for key, dtype in (("typeid", np.uint32), ("mass", np.float32), ("position", np.float32),
                           ("velocity", np.float32), ("image", np.int32)):
            if key in want:
                check_array(f"{where} particles.{key}", getattr(snap.particles, key), want[key], dtype)
        if "force" in want:
            check_array(where + " log/particles/force", snap.log["particles/force"], want["force"], np.float32)
        if "id" in want:
            check_array(where + " log/particles/id", snap.log["particles/id"], want["id"], np.uint32)


def main():
    if len(sys.argv) != 3:
        fail("usage: check_gsd.py FILE.gsd EXPECTED.json")
    path, expected_path = sys.argv[1], sys.argv[2]
    with open(expected_path) as f:
        frames = json.load(f)["frames"]

    with gsd.hoomd.open(name=path, mode="rb") as traj:
        if traj.file.schema != "hoomd" or tuple(traj.file.schema_version) != (1, 4):
            fail(f"schema {traj.file.schema} {traj.file.schema_version}, expected hoomd (1, 4)")
        if tuple(traj.file.gsd_version) != (2, 0):
            fail(f"GSD file version {traj.file.gsd_version}, expected (2, 0)")
        check_trajectory(traj, frames, "gsd.fl")

    with open(path, "rb") as raw, gsd.pygsd.GSDFile(raw) as f:
        check_trajectory(gsd.hoomd.HOOMDTrajectory(f), frames, "gsd.pygsd")

    print(f"check_gsd: {path}: {len(frames)} frames OK")


if __name__ == "__main__":
    main()
