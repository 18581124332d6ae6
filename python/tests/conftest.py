"""Shared helpers for the Python module's tests: the source tree, the drape command, scenes."""
import json
import os
import subprocess

import pytest

SOURCE = os.environ.get("DRAPE_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
DRAPE = os.environ.get("DRAPE_EXE", os.path.join(SOURCE, "build", "drape"))

# The --stats keys whose values do not depend on the machine's speed.
PHYSICAL_KEYS = [
    "scene", "status", "diverged_frame", "message", "method", "particles", "springs", "frames",
    "substeps_per_frame", "dt", "sim_seconds", "state_bytes", "model_bytes", "workspace_bytes",
    "bytes_per_particle", "kinetic_energy", "max_strain", "mean_strain", "max_penetration",
    "pinned_drift", "finite", "auto", "self_intersections",
]
TIMING_KEYS = ["wall_seconds", "setup_ms", "ms_per_frame"]


def scene_path(name):
    return os.path.join(SOURCE, "scenes", name + ".json")


def drape_command(*args):
    """Runs the drape command; returns (exit code, stdout and stderr)."""
    r = subprocess.run([DRAPE, *args], capture_output=True, text=True, check=False)
    return r.returncode, r.stdout + r.stderr


def command_stats(tmp_path, *args):
    """`drape run ARGS --stats FILE`'s stats."""
    stats = tmp_path / "stats.json"
    code, output = drape_command("run", *args, "--quiet", "--stats", str(stats))
    assert code == 0, output
    return json.loads(stats.read_text())


def command_error(*args):
    """The message `drape run ARGS` prints for bad input (exit 2), without its prefix."""
    code, output = drape_command("run", *args)
    assert code == 2, output
    prefix = "drape: error: "
    assert output.startswith(prefix), output
    return output[len(prefix):].strip()


@pytest.fixture
def free_fall():
    """A scene dict of a cloth in free fall: no pins, exactly flat, no drag, the seed's method."""
    return {
        "cloth": {"resolution": [8, 8], "pins": [], "perturbation": 0.0},
        "forces": {"air_drag": 0.0},
        "solver": {"method": "symplectic"},
    }
