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


def test_bad_arguments_name_the_argument_and_the_rule():
    """Issue 46: pybind11's TypeError listed the signature, and set={'M': 'heavy'} raised
    "RuntimeError: Unable to cast Python instance to C++ type"."""
    rule = r"an integer in 0\.\.4611686018427387904 \(the range of the experiment's seed key\)"
    for seed in (-1, 2**62 + 1, 2**70):
        with pytest.raises(ValueError, match=rf"^seed: expected {rule}, got {seed}$"):
            sai.simulate(EXPERIMENT, base_dir=ROOT, seed=seed)
    for seed in (2.5, "3", True):
        with pytest.raises(TypeError, match=rf"^seed: expected None or {rule}, got "):
            sai.simulate(EXPERIMENT, base_dir=ROOT, seed=seed)
    with pytest.raises(ValueError, match=r"^set\['M'\]: expected a number \(the parameter's value "
                                         r"in SI units\), got str 'heavy'$"):
        sai.simulate(EXPERIMENT, base_dir=ROOT, set={"M": "heavy"})
    with pytest.raises(ValueError, match=r"^set\['M'\]: expected a number .*got bool True$"):
        sai.simulate(EXPERIMENT, base_dir=ROOT, set={"M": True})
    with pytest.raises(ValueError, match=r"^set\['M'\]: expected a number .*got float nan$"):
        sai.simulate(EXPERIMENT, base_dir=ROOT, set={"M": float("nan")})
    with pytest.raises(ValueError, match=r"^set\['M'\]: .*'M'.*expected a finite positive number"):
        sai.simulate(EXPERIMENT, base_dir=ROOT, set={"M": -5})
    with pytest.raises(ValueError, match=r"^set: expected str keys \(MODEL\.md parameter names\), "
                                         r"got int 3$"):
        sai.simulate(EXPERIMENT, base_dir=ROOT, set={3: 1.0})
    with pytest.raises(TypeError, match=r"^set: expected None or a dict parameter name -> number, "
                                        r"got list"):
        sai.simulate(EXPERIMENT, base_dir=ROOT, set=[("M", 1.0)])
    with pytest.raises(TypeError, match=r"^noise: expected True or False, got str 'no'$"):
        sai.simulate(EXPERIMENT, base_dir=ROOT, noise="no")
    with pytest.raises(TypeError, match=r"^noise: expected True or False, got NoneType None$"):
        sai.simulate(EXPERIMENT, base_dir=ROOT, noise=None)
    with pytest.raises(TypeError, match=r'^channels: expected None, "all" or a list of channel '
                                        r"names \(.*\), got str 'v'$"):
        sai.simulate(EXPERIMENT, base_dir=ROOT, channels="v")
    with pytest.raises(TypeError, match=r"^channels: expected channel names \(str\), got int 3$"):
        sai.simulate(EXPERIMENT, base_dir=ROOT, channels=["v", 3])
    with pytest.raises(TypeError, match=r"^base_dir: expected a path \(str or os\.PathLike\) or "
                                        r"None, got int$"):
        sai.simulate(EXPERIMENT, base_dir=3)
    with pytest.raises(TypeError, match=r"^discover: expected True or False, got str 'yes'$"):
        sai.fit(JOB, base_dir=ROOT, discover="yes")
    # What still works: NumPy integers and floats, a tuple of channels.
    numpy = pytest.importorskip("numpy")
    trace = sai.simulate(EXPERIMENT, base_dir=ROOT, seed=numpy.int64(3),
                         set={"M": numpy.float64(60.0)}, channels=("v",), noise=numpy.bool_(False))
    assert list(trace) == ["t", "v"]


def test_fit_output_path_is_checked_before_the_fit(tmp_path):
    """Issue 46: out=<a file> failed with RuntimeError after the whole fit."""
    a_file = tmp_path / "a_file"
    a_file.write_text("x\n")
    calls = []
    for out in (a_file, a_file / "sub"):
        with pytest.raises(ValueError, match=re.escape(f"{out}: expected an output directory")):
            sai.fit(JOB, base_dir=ROOT, out=out, progress=calls.append)
    assert calls == []  # the fit never started
    assert a_file.read_text() == "x\n"
    with pytest.raises(ValueError, match=r"^out: expected a folder path \(or True, False or None\), "
                                         r"got ''"):
        sai.fit(JOB, base_dir=ROOT, out="")
    with pytest.raises(TypeError, match=r"^out: expected a path \(str or os\.PathLike\), True, "
                                        r"False or None, got int$"):
        sai.fit(JOB, base_dir=ROOT, out=3)


def test_yaml_documents_merge_keys_and_non_utf8_are_refused(tmp_path):
    """Issue 46: a second document was ignored, a merge key not applied, and a UTF-16 file
    printed raw bytes cut at the first NUL."""
    text = (f"model: {ROOT}/configs/axes/x_axis.yaml\nduration: 0.05\nchannels: [u, x]\n"
            "input: {type: step, amplitude: 1.0}\n")
    path = tmp_path / "two.yaml"
    path.write_text(text + "---\nduration: 5\n")
    with pytest.raises(ValueError, match=re.escape(f"{path}:5: expected one YAML document, got a "
                                                   "second one")):
        sai.simulate(path)
    path = tmp_path / "merge.yaml"
    path.write_text("step: &s {type: step}\n" + text.replace("input: {type: step, amplitude: 1.0}",
                                                             "input:\n  <<: *s\n  amplitude: 1.0"))
    with pytest.raises(ValueError, match=re.escape(f"{path}:6: key 'input.<<': expected no YAML "
                                                   "merge key")):
        sai.simulate(path)
    path = tmp_path / "utf16.yaml"
    path.write_bytes(text.encode("utf-16"))
    with pytest.raises(ValueError, match=re.escape(f"{path}:1: expected UTF-8 text, got byte 0xFF "
                                                   "at byte offset 0 (not UTF-8 text; a UTF-16 "
                                                   "file?")):
        sai.simulate(path)
    with pytest.raises(ValueError, match=r"^<job dict>:\d+: key 'output\.dir': expected a folder "
                                         r"path"):
        sai.load_job(dict(JOB, output={"dir": ""}), base_dir=ROOT)
