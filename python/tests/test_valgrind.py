"""Particle arrays kept across steps never read freed memory: kept_arrays.py under valgrind on two MPI
ranks (a rank's arrays are reallocated), with no invalid read or write reported."""
import glob
import os
import re
import shutil
import subprocess
import sys

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))


def test_arrays_kept_across_steps_read_no_freed_memory(tmp_path):
    valgrind = shutil.which("valgrind")
    mpirun = os.environ.get("MESODPD_MPIEXEC") or shutil.which("mpirun")
    if not valgrind or not mpirun:
        pytest.skip("needs valgrind and mpirun")
    pytest.importorskip("mpi4py")
    import mesodpd
    if not mesodpd._core.has_mpi:
        pytest.skip("mesodpd built without MPI")
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_mpi_yield_when_idle="1", OMPI_MCA_rmaps_base_oversubscribe="1", OMP_NUM_THREADS="1",
               PYTHONMALLOC="malloc")  # Python's own allocator hides nothing from valgrind then
    log = str(tmp_path / "valgrind.%p.log")
    r = subprocess.run([mpirun, "--oversubscribe", "-np", "2", valgrind, "--log-file=" + log, "--leak-check=no",
                        "--track-origins=no", sys.executable, os.path.join(HERE, "kept_arrays.py")],
                       env=env, capture_output=True, text=True, timeout=600, cwd=tmp_path)
    logs = sorted(glob.glob(str(tmp_path / "valgrind.*.log")))
    text = "".join(open(f).read() for f in logs)
    # OpenMPI's own start-up makes valgrind report uninitialised bytes in system calls; those are not
    # about our memory. Invalid reads and writes (freed or unallocated memory) are what this test is for.
    invalid = re.findall(r"Invalid (?:read|write) of size \d+", text)
    print(r.stdout, r.stderr[-3000:])
    assert len(logs) == 2, r.stdout + r.stderr
    assert not invalid, f"{len(invalid)} invalid accesses:\n" + text[text.find("Invalid"):][:6000]
    assert r.returncode == 0, r.stdout + r.stderr
    assert "ok 0" in r.stdout and "ok 1" in r.stdout, r.stdout
