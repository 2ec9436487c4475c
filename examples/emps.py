#!/usr/bin/env python3
"""Fits the EMPS benchmark job from Python and plots measured vs simulated.

    PYTHONPATH=build/python python3 examples/emps.py [--job JOB.yaml] [--png emps.png] [--quiet]

The job (default configs/jobs/emps.yaml) fits M and B_a of the EMPS axis
(testdata/emps/README.md) to the estimation run in closed loop, runs the
discovery loop it asks for (`discover:`) and validates on the pulse run; the
same as `fit-params configs/jobs/emps.yaml`, but nothing is written except
the plot (`out=None`). Takes about a minute on two cores. The figure has one
row per experiment and channel (but an input the simulation replays):
measured and simulated position x (m) or controller output u (V) against
time, and the residual.
"""
import argparse
import pathlib
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
try:
    import servo_axis_id as sai
except ImportError:  # not on PYTHONPATH: the module of a build in build/
    sys.path.insert(0, str(ROOT / "build" / "python"))
    import servo_axis_id as sai

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt  # noqa: E402


def plot(result, png):
    """One row per measured channel of every experiment: traces and residual.
    A channel the simulation replays (the open-loop run's input u: residual
    identically 0) is left out."""
    rows = [(e, c) for e in result.experiments for c in e.channels
            if (c.simulated != c.measured).any()]
    fig, axes = plt.subplots(len(rows), 2, figsize=(13, 2.3 * len(rows)), squeeze=False,
                             gridspec_kw={"width_ratios": [3, 2]})
    for (experiment, channel), (left, right) in zip(rows, axes):
        label = f"{experiment.name} ({experiment.role}): {channel.channel} [{channel.unit}]"
        left.plot(experiment.t, channel.measured, lw=0.8, label="measured")
        left.plot(experiment.t, channel.simulated, lw=0.8, label="simulated")
        left.set_title(f"{label}, fit {channel.fit_percent:.2f} %", fontsize=9)
        left.legend(loc="upper right", fontsize=8)
        right.plot(experiment.t, channel.simulated - channel.measured, lw=0.6, color="C3")
        right.set_title(f"residual, RMS {channel.rms:.3g} {channel.unit}", fontsize=9)
        for axis in (left, right):
            axis.tick_params(labelsize=8)
            axis.grid(alpha=0.3)
    for axis in axes[-1]:
        axis.set_xlabel("t [s]")
    fig.suptitle(result.title, fontsize=11)
    fig.tight_layout()
    fig.savefig(png, dpi=90)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--job", default=str(ROOT / "configs/jobs/emps.yaml"))
    parser.add_argument("--png", default="emps.png")
    parser.add_argument("--quiet", action="store_true", help="no progress lines")
    args = parser.parse_args()

    job = sai.load_job(args.job)
    print(job)
    start = time.monotonic()
    result = sai.fit(job, progress=None if args.quiet else print)
    seconds = time.monotonic() - start

    print(f"\nfit: {seconds:.1f} s, cost {result.final_cost:.6g}, "
          f"{'converged' if result.converged else 'NOT converged'}")
    for p in result.parameters:
        if p.free:
            low, high = p.ci95
            print(f"  {p.name:8} = {p.value:.6g} +- {p.std_error:.3g} {p.unit}"
                  f"  95% [{low:.6g}, {high:.6g}]")
    if result.discovery is not None:
        print(f"discovered: {', '.join(result.discovery['selected']) or 'nothing'};"
              f" verdict: {result.discovery['verdict']}")
    for experiment in result.experiments:
        for c in experiment.channels:
            print(f"  {experiment.name:22} {c.channel:3} RMS {c.rms:.4g} {c.unit:4}"
                  f" fit {c.fit_percent:7.2f} %  rel. error {c.relative_error_percent:.4g} %")
    plot(result, args.png)
    print(f"wrote {args.png}")


if __name__ == "__main__":
    main()
