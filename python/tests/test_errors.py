"""Bad input raises ValueError with the C++ loaders' "<file>:<line>: key ..." message."""
import re

import pytest

import servo_axis_id as sai

from conftest import ROOT

EXPERIMENT = {
    "model": "configs/axes/x_axis.yaml",
    "duration": 0.05,
    "channels": ["u", "x"],
    "input": {"type": "step", "amplitude": 1.0},
}

JOB = {
    "title": "short step",
    "model": "configs/axes/x_axis.yaml",
    "free": {"B_a": {"initial": 150, "lower": 10, "upper": 2000}},
    "experiments": [{
        "name": "step",
        "data": "testdata/x_step_10V.csv",
        "window": [0, 0.1],
        "channels": {"u": "u", "tach": "tach"},
        "input": {"column": "u"},
        "fit": {"tach": 0.005},
    }],
}


def line_of(document, needle):
    """1-based line of `needle` in to_yaml(document): what the messages name."""
    for number, line in enumerate(sai.to_yaml(document).splitlines(), start=1):
        if needle in line:
            return number
    raise AssertionError(f"{needle!r} not in {sai.to_yaml(document)}")


def test_unknown_key_in_an_experiment_dict():
    bad = dict(EXPERIMENT, input={"type": "step", "amplitude": 1.0, "bogus": 2})
    with pytest.raises(ValueError) as error:
        sai.simulate(bad, base_dir=ROOT)
    line = line_of(bad, "bogus:")
    assert str(error.value) == (
        f"<experiment dict>:{line}: key 'input.bogus': expected one of the known keys "
        "(amplitude, offset, start, type), got unknown key 'bogus'")


def test_unknown_key_in_a_job_dict():
    bad = {**JOB, "experiments": [dict(JOB["experiments"][0], colour="red")]}
    for call in (sai.load_job, sai.fit):
        with pytest.raises(ValueError,
                           match=r"^<job dict>:\d+: key 'experiments\[0\]\.colour': "
                                 r"expected one of the known keys .*got unknown key 'colour'"):
            call(bad, base_dir=ROOT)


def test_bad_value_in_a_file_names_file_line_and_key(tmp_path):
    path = tmp_path / "e.yaml"
    path.write_text(f"model: {ROOT}/configs/axes/x_axis.yaml\n"
                    "duration: -1\n"
                    "channels: [x]\n"
                    "input: {type: zero}\n")
    with pytest.raises(ValueError, match=re.escape(f"{path}:2: key 'duration': expected")):
        sai.simulate(path)


def test_bad_path():
    with pytest.raises(ValueError, match=r"^no/such/job\.yaml: cannot read"):
        sai.load_job("no/such/job.yaml")
    with pytest.raises(ValueError, match=r"^no/such/experiment\.yaml: cannot read"):
        sai.simulate("no/such/experiment.yaml")


def test_relative_paths_of_a_dict_resolve_against_base_dir(tmp_path):
    with pytest.raises(ValueError, match=re.escape(f"{tmp_path}/configs/axes/x_axis.yaml")):
        sai.simulate(EXPERIMENT, base_dir=tmp_path)
    job = sai.load_job(JOB, base_dir=ROOT)
    assert job.experiments[0].data_path == f"{ROOT}/testdata/x_step_10V.csv"


def test_values_yaml_cannot_hold():
    with pytest.raises(ValueError, match=r"key 'set': expected a str key, got 3"):
        sai.simulate(dict(EXPERIMENT, set={3: 1.0}), base_dir=ROOT)
    with pytest.raises(ValueError, match=r"key 'input.amplitude': expected a dict, list, str, "
                                         r"number, bool or None, got object"):
        sai.simulate(dict(EXPERIMENT, input={"type": "step", "amplitude": object()}),
                     base_dir=ROOT)


def test_wrong_argument_types():
    with pytest.raises(TypeError, match="experiment: expected a path"):
        sai.simulate(42)
    with pytest.raises(TypeError, match="progress: expected a callable"):
        sai.fit(JOB, base_dir=ROOT, progress="print")
    with pytest.raises(ValueError, match="base_dir: expected no base_dir with a file path"):
        sai.simulate(ROOT / "configs/experiments/x_move_1m.yaml", base_dir=ROOT)


def test_bad_set_and_nan():
    with pytest.raises(ValueError, match="expected a parameter name of the model"):
        sai.simulate(EXPERIMENT, base_dir=ROOT, set={"not_a_parameter": 1.0})
    with pytest.raises(ValueError, match=r"key 'duration': expected"):
        sai.simulate(dict(EXPERIMENT, duration=float("nan")), base_dir=ROOT)
