"""fit() and load_job(): the same estimates as fit-params, traces, discovery, progress, GIL."""
import csv
import subprocess
import threading
import time

import numpy as np
import pytest

import servo_axis_id as sai

from conftest import ROOT

# The paper's identification (configs/jobs/x_axis_paper.yaml) cut short: two
# of its five unknowns from the first 0.3 s of the noisy 10 V step
# (testdata/x_step_10V.csv; the truth is V_L = 2.7 V, B_a = 200 N*s/m).
# One Ceres thread: the same floating-point sums in every run.
JOB = {
    "title": "paper job, 0.3 s of the 10 V step",
    "model": "configs/axes/x_axis.yaml",
    "free": {"V_L": {"initial": 3.5, "lower": 0.5, "upper": 20},
             "B_a": {"initial": 150, "lower": 10, "upper": 2000}},
    "experiments": [{
        "name": "step",
        "data": "testdata/x_step_10V.csv",
        "window": [0, 0.3],
        "channels": {"u": "u", "a": "a", "tach": "tach"},
        "input": {"column": "u"},
        "fit": {"a": 0.02, "tach": 0.005},
    }],
    "solver": {"threads": 1},
}
TRUTH = {"V_L": 2.7, "B_a": 200.0}


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


@pytest.fixture(scope="module")
def fitted():
    """The short job loaded, then fitted with a progress callback."""
    job = sai.load_job(JOB, base_dir=ROOT)
    lines, threads = [], set()

    def progress(line):
        lines.append(line)
        threads.add(threading.get_ident())

    return sai.fit(job, progress=progress), lines, threads


def test_load_job_is_inspectable():
    job = sai.load_job(JOB, base_dir=ROOT)
    assert job.title == JOB["title"]
    assert job.path == "<job dict>"
    assert job.free_names == ["V_L", "B_a"]
    assert [(p.name, p.unit, p.initial, p.lower, p.upper) for p in job.free] == [
        ("V_L", "V", 3.5, 0.5, 20.0), ("B_a", "N*s/m", 150.0, 10.0, 2000.0)]
    assert job.experiment_names == ["step"] and job.validate_names == []
    step = job.experiments[0]
    assert step.t.shape == (301,) and step.t[0] == 0.0
    assert sorted(step.measured) == ["a", "tach", "u"]
    assert step.fitted == {"a": 0.02, "tach": 0.005}
    assert job.out_dir == "" and not job.discover
    paper = sai.load_job(ROOT / "configs/jobs/x_axis_paper.yaml")
    assert paper.free_names == ["V_L", "B_a", "b_g", "k_g", "T_p"]
    assert paper.experiment_names == ["step_10V", "step_4V"]
    assert paper.validate_names == ["move_1m"]


def test_recovers_the_truth_within_the_intervals(fitted):
    result = fitted[0]
    assert result.converged
    assert result.free_names == ["V_L", "B_a"]
    for name, truth in TRUTH.items():
        p = result.parameter(name)
        assert p.free and p.unit == {"V_L": "V", "B_a": "N*s/m"}[name]
        low, high = p.ci95
        assert low < truth < high, (name, p.value, p.ci95)
        assert 0 < p.std_error < (high - low)
    assert result.values == {n: result.parameter(n).value for n in TRUTH}
    assert result.parameter("M").free is False and result.parameter("M").std_error is None
    assert result.correlation.shape == (2, 2)


def test_traces_and_statistics(fitted):
    result = fitted[0]
    job = sai.load_job(JOB, base_dir=ROOT)
    step = result.experiment("step")
    assert step.role == "fit"
    np.testing.assert_array_equal(step.t, job.experiments[0].t)
    for name in ("a", "tach"):
        channel = step.channel(name)
        assert channel.fitted and channel.sigma == JOB["experiments"][0]["fit"][name]
        np.testing.assert_array_equal(channel.measured, job.experiments[0].measured[name])
        assert channel.simulated.shape == channel.measured.shape
        rms = np.sqrt(np.mean((channel.simulated - channel.measured) ** 2))
        assert channel.rms == pytest.approx(rms, rel=1e-12)
        assert channel.fit_percent > 90
    report = result.report
    assert [p["name"] for p in report["parameters"][:2]] == ["V_L", "B_a"]
    assert report["experiments"][0]["channels"][1]["rms"] == step.channel("a").rms
    assert result.discovery is None and result.published is None
    assert "V_L" in result.table()


def test_equals_fit_params_on_the_same_job(fitted, tmp_path, bin_dir):
    job = dict(JOB, output={"dir": str(tmp_path / "out")})
    job["model"] = str(ROOT / JOB["model"])
    job["experiments"] = [dict(JOB["experiments"][0], data=str(ROOT / "testdata/x_step_10V.csv"))]
    (tmp_path / "job.yaml").write_text(sai.to_yaml(job))
    subprocess.run([str(bin_dir / "fit-params"), str(tmp_path / "job.yaml")], check=True,
                   stdout=subprocess.DEVNULL)
    result = fitted[0]
    rows = {row["name"]: row for row in read_csv(tmp_path / "out/params.csv")}
    for p in result.parameters:
        assert float(rows[p.name]["value"]) == p.value, p.name
        if p.free:
            assert float(rows[p.name]["std_error"]) == p.std_error
            assert (float(rows[p.name]["ci95_low"]), float(rows[p.name]["ci95_high"])) == p.ci95
    trace = read_csv(tmp_path / "out/fit_step.csv")
    simulated = np.array([float(r["tach_simulated"]) for r in trace])
    np.testing.assert_allclose(simulated, result.experiment("step").channel("tach").simulated,
                               rtol=1e-10)


def test_progress_lines_come_from_the_calling_thread(fitted):
    result, lines, threads = fitted
    assert threads == {threading.get_ident()}
    assert any(line.startswith("start  0  horizon") for line in lines)
    assert any("optimum verified" in line for line in lines)
    assert all("\n" not in line for line in lines)


def test_writes_files_only_when_asked(tmp_path):
    job = dict(JOB, experiments=[dict(JOB["experiments"][0], window=[0, 0.1])],
               output={"dir": str(tmp_path / "from_job")})
    sai.fit(job, base_dir=ROOT)
    assert not (tmp_path / "from_job").exists()
    sai.fit(job, base_dir=ROOT, out=tmp_path / "here")
    names = {p.name for p in (tmp_path / "here").iterdir()}
    assert {"params.csv", "params.md", "report.json", "fit_step.csv"} <= names
    sai.fit(job, base_dir=ROOT, out=True)
    assert (tmp_path / "from_job/params.csv").exists()


def test_callback_exception_is_raised_after_the_fit():
    calls = []

    def progress(line):
        calls.append(line)
        raise KeyError("stop")

    job = dict(JOB, experiments=[dict(JOB["experiments"][0], window=[0, 0.1])])
    with pytest.raises(KeyError, match="stop"):
        sai.fit(job, base_dir=ROOT, progress=progress)
    assert len(calls) == 1


def test_the_gil_is_released_while_fitting():
    """A Python thread ticks every millisecond; holding the GIL for the whole
    fit (about 2 s) would leave it a tick or two."""
    ticks = [0]
    stop = threading.Event()
    started = threading.Event()

    def ticker():
        while not stop.is_set():
            ticks[0] += 1
            started.set()
            time.sleep(0.001)

    thread = threading.Thread(target=ticker)
    thread.start()
    started.wait()
    try:
        before = ticks[0]
        sai.fit(JOB, base_dir=ROOT)
        during = ticks[0] - before
    finally:
        stop.set()
        thread.join()
    assert during >= 20, during


def test_discovery_finds_coulomb_friction():
    """0.3 s of the two steps of the coulomb discovery case
    (configs/jobs/discover/coulomb.yaml; truth F_c = 30 N)."""
    experiments = [{
        "name": name,
        "data": f"testdata/discover/coulomb_{name}.csv",
        "window": [0, 0.3],
        "channels": {"u": "u", "a": "a", "tach": "tach"},
        "input": {"column": "u"},
        "fit": {"a": 0.02, "tach": 0.005},
    } for name in ("step_p4V", "step_m2V")]
    job = {
        "model": "configs/axes/x_axis.yaml",
        "free": {"B_a": {"initial": 200, "lower": 10, "upper": 2000}},
        "experiments": experiments,
        "solver": {"threads": 1},
        "uncertainty": {"method": "gauss_newton"},
        "discover": {"max_effects": 1},
    }
    result = sai.fit(job, base_dir=ROOT, discover=True)
    discovery = result.discovery
    assert discovery["selected"] == ["coulomb"]
    assert discovery["verdict"] == "explained"
    assert discovery["steps"][0]["effect"] == "coulomb" and discovery["steps"][0]["kept"]
    f_c = result.parameter("F_c")
    assert f_c.free and f_c.ci95[0] < 30 < f_c.ci95[1]
    assert "Selected: coulomb" in result.discovery_table
    assert "coulomb:" in result.model_yaml
