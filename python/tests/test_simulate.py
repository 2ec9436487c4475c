"""simulate(): files and dicts through the same loader, the same traces as simulate-axis."""
import csv
import subprocess

import numpy as np
import pytest

import servo_axis_id as sai

from conftest import ROOT

# testdata/generate/x_step_10V.yaml as a dict (the committed testdata CSVs
# were written from that file by simulate-axis).
STEP_10V = {
    "description": "10 V step, X axis, noisy a/tach/i at 1 kHz",
    "model": "../../configs/axes/x_axis.yaml",
    "duration": 2.0,
    "step": 1.0e-5,
    "output_rate": 1000,
    "channels": ["u", "a", "tach", "i", "v"],
    "noise": {"a": 0.02, "tach": 0.005, "i": 0.05},
    "seed": 11,
    "input": {"type": "step", "amplitude": 10, "start": 0.0},
}


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return {name: np.array([float(r[k]) for r in rows[1:]]) for k, name in enumerate(rows[0])}


def assert_same_trace(trace, expected):
    """Equal to the 12 significant digits simulate-axis writes."""
    assert list(trace) == list(expected)
    for name, values in expected.items():
        np.testing.assert_allclose(trace[name], values, rtol=1e-10,
                                   atol=1e-12 * np.max(np.abs(values)), err_msg=name)


def test_path_and_dict_give_the_same_arrays():
    from_path = sai.simulate(ROOT / "testdata/generate/x_step_10V.yaml")
    from_dict = sai.simulate(STEP_10V, base_dir=ROOT / "testdata/generate")
    assert list(from_path) == ["t", "u", "a", "tach", "i", "v"]
    for name in from_path:
        assert from_path[name].dtype == np.float64
        assert from_path[name].shape == (2001,)
        np.testing.assert_array_equal(from_path[name], from_dict[name], err_msg=name)


@pytest.mark.parametrize("noise,csv_name", [(True, "x_step_10V.csv"),
                                            (False, "x_step_10V_clean.csv")])
def test_matches_the_committed_simulate_axis_output(noise, csv_name):
    trace = sai.simulate(str(ROOT / "testdata/generate/x_step_10V.yaml"), noise=noise)
    assert_same_trace(trace, read_csv(ROOT / "testdata" / csv_name))


def test_seed_and_set_as_simulate_axis_options(tmp_path, bin_dir):
    experiment = ROOT / "configs/experiments/x_move_1m.yaml"
    out = tmp_path / "move.csv"
    subprocess.run([str(bin_dir / "simulate-axis"), str(experiment), "--out", str(out),
                    "--seed", "5", "--set", "B_a=250", "--set", "T_p=0.05"], check=True)
    trace = sai.simulate(experiment, seed=5, set={"B_a": 250, "T_p": 0.05})
    assert_same_trace(trace, read_csv(out))
    default = sai.simulate(experiment)
    assert not np.array_equal(default["x"], trace["x"])


def test_channel_choice():
    experiment = dict(STEP_10V, duration=0.05)
    everything = sai.simulate(experiment, base_dir=ROOT / "testdata/generate", channels="all",
                              noise=False)
    assert list(everything) == sai.CHANNELS
    some = sai.simulate(experiment, base_dir=ROOT / "testdata/generate",
                        channels=["tach", "x"], noise=False)
    assert list(some) == ["t", "tach", "x"]
    np.testing.assert_array_equal(some["tach"], everything["tach"])
    with pytest.raises(ValueError, match="channels: expected .*got 'speed'"):
        sai.simulate(experiment, base_dir=ROOT / "testdata/generate", channels=["speed"])
