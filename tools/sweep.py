"""Helpers shared by the examples' parameter sweeps (examples/interface/run.py, examples/wetting/run.py):
the common command-line options, one run of mesodpd on a config text in its own folder, and a set of
runs a few at a time."""
import concurrent.futures
import os
import subprocess


def add_run_args(ap, root, out_name):
    """--mesodpd, --out, --jobs and --analyse-only."""
    ap.add_argument("--mesodpd", default=os.path.join(root, "build", "mesodpd"))
    ap.add_argument("--out", default=os.path.join(root, "out", out_name))
    ap.add_argument("--jobs", type=int, default=1, help="runs at the same time (each on one thread)")
    ap.add_argument("--analyse-only", action="store_true", help="only analyse the runs already in --out")


def run_config(mesodpd, text, folder, name):
    """Writes `text` to folder/name and runs it there on one thread at the lowest priority (log.txt)."""
    os.makedirs(folder, exist_ok=True)
    cfg = os.path.join(folder, name)
    with open(cfg, "w") as f:
        f.write(text)
    with open(os.path.join(folder, "log.txt"), "w") as log:
        subprocess.run(["nice", "-n", "19", mesodpd, "run", cfg, "--out", folder, "--threads", "1"],
                       check=True, stdout=log, stderr=subprocess.STDOUT)


def run_all(run_one, values, jobs):
    """run_one(v) for every value, `jobs` at a time."""
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as ex:
        list(ex.map(run_one, values))
