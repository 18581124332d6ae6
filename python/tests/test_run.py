"""drape.run: a headless run returning the --stats dict, with seconds and overrides."""
import os
import signal
import threading

import numpy as np
import pytest

import drape
from conftest import PHYSICAL_KEYS, TIMING_KEYS, command_error, command_stats, scene_path


def test_run_returns_the_commands_stats_for_the_same_run(tmp_path):
    stats = drape.run(scene_path("wind"), seconds=0.25)
    assert sorted(stats) == sorted(PHYSICAL_KEYS + TIMING_KEYS)
    command = command_stats(tmp_path, scene_path("wind"), "--seconds", "0.25")
    for key in PHYSICAL_KEYS:
        assert stats[key] == command[key], key
    assert stats["status"] == "ok" and stats["frames"] == 15


def test_seconds_default_to_the_scenes_duration():
    assert drape.run({"cloth": {"resolution": [4, 4]}, "duration": 0.1})["frames"] == 6


def test_overrides_set_any_key_as_set_does(tmp_path):
    overrides = {"cloth.resolution": [8, 6], "solver.substeps": 7, "name": "small",
                 "colliders": [{"type": "sphere", "center": [0, -1, 0]}], "colliders.0.radius": 0.25}
    stats = drape.run(scene_path("hang"), seconds=0.05, overrides=overrides)
    assert "duration" not in overrides  # the caller's dict is left as it was
    assert stats["particles"] == 48
    assert stats["substeps_per_frame"] == 7
    assert stats["scene"] == "small"
    # Overrides on a dict scene too, and NumPy values.
    stats = drape.run({"duration": 0.05}, overrides={"cloth.resolution": np.array([5, 4]),
                                                     "cloth.mass": np.float64(3.0)})
    assert stats["particles"] == 20


def test_bad_overrides_raise_input_error_with_the_commands_message():
    with pytest.raises(drape.InputError) as error:
        drape.run(scene_path("hang"), overrides={"cloth.masss": 2})
    assert str(error.value) == command_error(scene_path("hang"), "--set", "cloth.masss=2")
    with pytest.raises(drape.InputError) as error:
        drape.run(scene_path("hang"), seconds=-1)
    # The command refuses --seconds -1 as an option; the same duration as a key is the same message.
    assert str(error.value) == command_error(scene_path("hang"), "--set", "duration=-1")
    with pytest.raises(drape.InputError, match="override colliders.x: colliders is an array"):
        drape.run({"colliders": []}, overrides={"colliders.x": 1})
    with pytest.raises(drape.InputError, match='a key cannot contain "="'):
        drape.run({}, overrides={"cloth.mass=2": 1})


def test_a_diverging_run_returns_its_stats_with_the_reason():
    stats = drape.run(scene_path("hang"), overrides={"cloth.springs.structural.stiffness": 1e9,
                                                     "solver.substeps": 1})
    assert stats["status"] == "diverged"
    assert stats["diverged_frame"] == 1 and stats["frames"] == 1
    assert "smaller solver.dt" in stats["message"]


def test_ctrl_c_interrupts_a_long_run():
    timer = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        drape.run(scene_path("hang"), seconds=1e5)
    timer.join()
