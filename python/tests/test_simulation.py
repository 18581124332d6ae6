"""drape.Simulation: scenes from files and dicts, the state as NumPy views, stepping, stats,
the hand, errors, threads and Ctrl-C."""
import os
import pathlib
import signal
import threading

import numpy as np
import pytest

import drape
from conftest import (PHYSICAL_KEYS, TIMING_KEYS, command_error, command_stats, scene_path)


def test_a_scene_file_by_path_or_pathlike_and_a_dict_with_its_keys_give_the_same_cloth():
    by_str = drape.Simulation(scene_path("hang"))
    by_path = drape.Simulation(pathlib.Path(scene_path("hang")))
    by_dict = drape.Simulation({"name": "hang", "cloth": {"pins": ["top-left", "top-right"]}})
    for sim in (by_str, by_path, by_dict):
        assert sim.positions.shape == (1024, 3)
        assert sim.frame == 0 and sim.time == 0.0
    # The shipped hang scene is the defaults: the same start, bit for bit.
    assert np.array_equal(by_str.positions, by_dict.positions)
    assert by_dict.stats()["scene"] == "hang"
    assert drape.Simulation({}).stats()["scene"] == "untitled"


def test_positions_velocities_and_triangles_are_read_only_views_of_the_right_shape_and_type():
    sim = drape.Simulation(scene_path("hang"))
    for array, shape, dtype in ((sim.positions, (1024, 3), np.float64),
                                (sim.velocities, (1024, 3), np.float64),
                                (sim.triangles, (2 * 31 * 31, 3), np.int32)):
        assert array.shape == shape
        assert array.dtype == dtype
        assert not array.flags.writeable
        assert not array.flags.owndata  # a view on the simulation's memory
        with pytest.raises(ValueError):
            array[0, 0] = 1
    assert sim.triangles.min() == 0 and sim.triangles.max() == 1023

    # No copy per call: each access views the same memory, and a view taken before a step shows
    # the state after it.
    before = sim.positions
    kept = sim.positions.copy()
    assert sim.positions.__array_interface__["data"][0] == before.__array_interface__["data"][0]
    assert np.shares_memory(before, sim.positions)
    assert sim.step(5)
    assert not np.array_equal(before, kept)
    assert np.array_equal(before, sim.positions)
    assert np.abs(sim.velocities).max() > 0


def test_a_view_keeps_its_simulation_alive():
    positions = drape.Simulation(scene_path("hang")).positions
    assert positions.base is not None
    assert np.isfinite(positions).all() and positions.shape == (1024, 3)


def test_step_counts_frames_and_time():
    sim = drape.Simulation(scene_path("hang"))
    assert sim.step() is True
    assert sim.step(4) is True
    assert sim.step(0) is True
    assert sim.frame == 5
    assert sim.time == pytest.approx(5 * 0.016666667, rel=1e-15)
    with pytest.raises(ValueError, match="frames: must be >= 0"):
        sim.step(-1)


def test_free_fall_matches_the_closed_form_within_the_methods_first_order_error(free_fall):
    # Semi-implicit Euler at substep h falls exactly 1/2 g t^2 + 1/2 g h t.
    sim = drape.Simulation(free_fall)
    start = sim.positions.copy()
    assert sim.step(30)
    stats = sim.stats()
    g, t = 9.81, sim.time
    h = stats["dt"] / stats["substeps_per_frame"]
    fell = start[:, 1] - sim.positions[:, 1]
    closed_form = 0.5 * g * t * t
    assert np.allclose(fell, closed_form + 0.5 * g * h * t, rtol=1e-12, atol=0)
    assert np.all(np.abs(fell - closed_form) <= 0.5 * g * h * t * (1 + 1e-9))
    # Nothing moves sideways (but for the springs' round-off), and every particle falls at g t.
    assert np.abs(sim.positions[:, [0, 2]] - start[:, [0, 2]]).max() < 1e-12
    assert np.allclose(sim.velocities[:, 1], -g * t, rtol=1e-12)


def test_stats_have_the_stats_files_keys_and_the_commands_values(tmp_path):
    sim = drape.Simulation(scene_path("sphere"))
    assert sim.step(30)
    stats = sim.stats()
    assert sorted(stats) == sorted(PHYSICAL_KEYS + TIMING_KEYS)
    command = command_stats(tmp_path, scene_path("sphere"), "--seconds", "0.5")
    assert command["frames"] == 30
    for key in PHYSICAL_KEYS:
        assert stats[key] == command[key], key  # the same code, the same bits
    assert stats["ms_per_frame"] > 0 and stats["wall_seconds"] > 0 and stats["setup_ms"] > 0


def test_step_returns_false_once_diverged_and_stats_say_why():
    sim = drape.Simulation({"cloth": {"springs": {"structural": {"stiffness": 1e9}}},
                            "solver": {"method": "symplectic", "substeps": 1}})
    assert sim.step(10) is False
    assert sim.frame == 1
    assert sim.step() is False and sim.frame == 1  # later calls do nothing
    stats = sim.stats()
    assert stats["status"] == "diverged"
    assert stats["diverged_frame"] == 1
    assert "symplectic method" in stats["message"]


def test_grab_move_grab_and_release_move_a_particle_by_hand():
    sim = drape.Simulation(scene_path("hang"))
    corner = 1023  # bottom-right
    sim.grab(corner)
    target = [1.5, 0.5, 0.7]
    sim.move_grab(target)
    assert sim.positions[corner].tolist() == target
    assert sim.step(3)
    assert sim.positions[corner].tolist() == target  # held still
    assert sim.velocities[corner].tolist() == [0.0, 0.0, 0.0]
    sim.release()
    assert sim.step(3)
    assert sim.positions[corner].tolist() != target  # let go, it swings
    sim.release()  # nothing held: nothing happens


def test_the_hand_refuses_what_it_cannot_do():
    sim = drape.Simulation(scene_path("hang"))
    with pytest.raises(RuntimeError, match="nothing is held"):
        sim.move_grab([0, 0, 0])
    for bad in (-1, 1024):
        with pytest.raises(IndexError, match="out of range: the cloth has 1024 particles"):
            sim.grab(bad)
    sim.grab(5)
    with pytest.raises(ValueError, match="expected a position"):
        sim.move_grab([1.0, 2.0])
    with pytest.raises(ValueError, match="finite"):
        sim.move_grab([float("nan"), 0, 0])


def test_bad_scenes_raise_input_error_a_value_error_with_the_commands_message(tmp_path):
    assert issubclass(drape.InputError, ValueError)
    bad = tmp_path / "bad.json"
    bad.write_text('{"cloth": {"mass": -1}}')
    with pytest.raises(drape.InputError) as error:
        drape.Simulation(str(bad))
    assert str(error.value) == command_error(str(bad))
    assert str(error.value) == f"{bad}: cloth.mass: is -1, must be in (0, 1e+06]"

    typo = tmp_path / "typo.json"
    typo.write_text('{"cloth": {"masss": 2}}')
    with pytest.raises(drape.InputError) as error:
        drape.Simulation(str(typo))
    assert str(error.value) == command_error(str(typo))

    missing = str(tmp_path / "missing.json")
    with pytest.raises(drape.InputError, match="missing.json: no such file"):
        drape.Simulation(missing)


def test_a_dict_scene_is_checked_like_a_file_and_named_scene_in_messages():
    cases = [
        ({"cloth": {"mass": -1}}, "scene: cloth.mass: is -1, must be in (0, 1e+06]"),
        ({"cloth": {"masss": 2}}, 'scene: cloth.masss: unknown key; did you mean "mass"?'),
        ({"solver": {"method": "rk4"}}, 'scene: solver.method: unknown value "rk4"'),
        ({"cloth": {"resolution": [2, "x"]}}, "scene: cloth.resolution[1]: expected a number"),
        ({"cloth": {"mass": float("inf")}}, "scene: cloth.mass: must be a finite number"),
        ({"cloth": {"mass": object()}}, "scene: cloth.mass: expected a dict, list, str, number"),
        ({"cloth": {1: 2}}, "scene: cloth: keys must be strings"),
    ]
    for scene, message in cases:
        with pytest.raises(drape.InputError) as error:
            drape.Simulation(scene)
        assert str(error.value).startswith(message), (scene, str(error.value))
    with pytest.raises(TypeError, match="a scene file's path or a dict"):
        drape.Simulation(42)


def test_numpy_values_in_a_scene_dict_are_taken_as_numbers():
    sim = drape.Simulation({"cloth": {"resolution": np.array([6, 5]), "mass": np.float32(2.0),
                                      "long_range": np.bool_(False)}})
    assert sim.positions.shape == (30, 3)


def test_stepping_releases_the_gil_and_refuses_a_second_thread_meanwhile():
    sim = drape.Simulation(scene_path("hang"))
    done = threading.Event()
    refused = []

    def step():
        sim.step(40)
        done.set()

    worker = threading.Thread(target=step)
    worker.start()
    counted = 0
    while not done.is_set():  # runs only while the worker has let go of the GIL
        counted += 1
        if 0 < sim.frame < 20 and not refused:  # well before the end of the step
            for call in (sim.step, sim.stats, sim.release):
                try:
                    call()
                except RuntimeError as error:
                    refused.append(str(error))
    worker.join()
    assert counted > 1000
    assert refused == ["the simulation is stepping in another thread"] * 3
    assert sim.frame == 40


def test_ctrl_c_interrupts_a_long_step_at_the_end_of_a_frame():
    sim = drape.Simulation(scene_path("hang"))
    timer = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        sim.step(1_000_000)
    timer.join()
    assert 0 < sim.frame < 1_000_000
    assert sim.step()  # still usable
