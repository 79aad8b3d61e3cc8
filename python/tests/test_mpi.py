"""Python under mpirun with mpi4py: the files of a run do not depend on the rank count."""
import filecmp
import os
import shutil
import subprocess
import sys

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))


def _mpirun():
    exe = os.environ.get("MESODPD_MPIEXEC") or shutil.which("mpirun")
    if not exe:
        pytest.skip("no mpirun")
    pytest.importorskip("mpi4py")
    import mesodpd
    if not mesodpd._core.has_mpi:
        pytest.skip("mesodpd built without MPI")
    return exe


def test_one_and_two_ranks_write_the_same_files(small_toml, tmp_path):
    mpirun = _mpirun()
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_mpi_yield_when_idle="1", OMPI_MCA_rmaps_base_oversubscribe="1", OMP_NUM_THREADS="1")
    outs = {}
    for n in (1, 2):
        out = tmp_path / f"np{n}"
        r = subprocess.run([mpirun, "--oversubscribe", "-np", str(n), sys.executable, os.path.join(HERE, "mpi_run.py"),
                            str(small_toml), str(out)], env=env, capture_output=True, text=True, timeout=300)
        assert r.returncode == 0, r.stdout + r.stderr
        assert f"ok {n}" in r.stdout
        outs[n] = out
    names = sorted(os.listdir(outs[1]))
    assert names == sorted(os.listdir(outs[2])) and "checkpoint.mdpd" in names
    _, mismatch, errors = filecmp.cmpfiles(outs[1], outs[2], names, shallow=False)
    assert mismatch == [] and errors == []
