"""examples/sweep.py on a LocalCluster of two workers: every task's stats arrive, a bad scene
reports its error without stopping the others, and the table is what running the same scenes one
by one gives."""
import csv
import itertools
import os
import subprocess
import sys

import drape
from conftest import PHYSICAL_KEYS, SOURCE, TIMING_KEYS, scene_path

SWEEP = os.path.join(SOURCE, "examples", "sweep.py")


def test_a_sweep_on_two_local_workers_gives_the_table_of_the_runs_one_by_one(tmp_path):
    stiffness, masses, methods = [500, 4000], [1, -1], ["symplectic", "xpbd"]
    table, picture = tmp_path / "sweep.csv", tmp_path / "sweep.png"
    run = subprocess.run(
        [sys.executable, SWEEP, scene_path("hang"), "--seconds", "0.25",
         "--set", "cloth.resolution=[8,8]",
         "--vary", "cloth.springs.structural.stiffness", *map(str, stiffness),
         "--vary", "cloth.mass", *map(str, masses),
         "--vary", "solver.method", *methods,
         "--workers", "2", "--csv", str(table), "--plot", str(picture), "--y", "max_strain"],
        capture_output=True, text=True, check=False, timeout=300)
    # A bad task fails the sweep's exit code, after every other task ran.
    assert run.returncode == 1, run.stdout + run.stderr
    assert "sweep: 4 of 8 runs done" in run.stdout
    assert "100%" in run.stderr  # the progress bar reached its end

    with open(table, newline="") as f:
        rows = list(csv.DictReader(f))
    combinations = list(itertools.product(stiffness, masses, methods))
    assert len(rows) == len(combinations)
    for row, (k, mass, method) in zip(rows, combinations):
        assert (row["cloth.springs.structural.stiffness"], row["cloth.mass"],
                row["solver.method"]) == (str(k), str(mass), method)
        if mass < 0:
            assert row["error"] == "scene: cloth.mass: is -1, must be in (0, 1e+06]"
            assert all(row[key] == "" for key in PHYSICAL_KEYS + TIMING_KEYS)
            continue
        assert row["error"] == ""
        # The same scene run here, one by one: the same figures, to the bit.
        alone = drape.run(
            scene_path("hang"), seconds=0.25,
            overrides={"cloth.resolution": [8, 8], "cloth.springs.structural.stiffness": k,
                       "cloth.mass": mass, "solver.method": method})
        for key in PHYSICAL_KEYS:
            expected = "" if alone[key] is None else str(alone[key])
            assert row[key] == expected, (key, row[key], alone[key])
        for key in TIMING_KEYS:
            assert float(row[key]) > 0, key
    assert picture.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_sweep_refuses_what_it_cannot_run(tmp_path):
    def sweep(*args):
        return subprocess.run([sys.executable, SWEEP, *args], capture_output=True, text=True,
                              check=False, cwd=tmp_path, timeout=60)

    missing = sweep(str(tmp_path / "missing.json"), "--vary", "cloth.mass", "1")
    assert missing.returncode == 2 and "missing.json" in missing.stderr
    twice = sweep(scene_path("hang"), "--vary", "cloth.mass", "1", "--vary", "cloth.mass", "2")
    assert twice.returncode == 2 and "each key may be varied once" in twice.stderr
    bad_x = sweep(scene_path("hang"), "--vary", "cloth.mass", "1", "--x", "duration")
    assert bad_x.returncode == 2 and "not one of the varied keys" in bad_x.stderr
