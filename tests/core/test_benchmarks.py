"""The shadow benchmarks run and report what they claim (tiny sizes: numbers, not speed)."""
import os
import sys

import numpy as np
import pytest

from conftest import REPO

sys.path.insert(0, os.path.join(REPO, "benchmarks"))

import overhead_lights  # noqa: E402
import shadow_quality  # noqa: E402


@pytest.fixture
def one_run(monkeypatch):
    monkeypatch.setattr(shadow_quality, "RUNS", 1)


def test_shadow_quality_rows(one_run):
    rows = shadow_quality.measure(64)
    assert len(rows) == 4 * len(shadow_quality.CASES)
    for label, level, sec, ratio, err, settings, worst, goal in rows:
        assert sec > 0 and np.isfinite(ratio) and 0 <= err < 0.05, (label, level, err)
        assert worst >= ratio
        if level == "baseline":
            assert ratio == 1.0 and settings == "K = 64 march at 64×64"
        # a goal beside every preview and final row, met or not
        assert (goal != "") == (level in ("preview", "final")), (label, level, goal)
        assert goal.endswith(": met") or goal.endswith(": not met") or goal == ""
    # final stays close to the reference even at 64² (where it marches, K = 64, below 512 px)
    finals = [r for r in rows if r[1] == "final"]
    assert all(r[4] < 3e-3 for r in finals)


def test_overhead_lights_prints_a_ratio_per_case(one_run, capsys):
    worst = overhead_lights.main(["--size", "64", "--levels", "draft"])
    out = capsys.readouterr().out
    assert np.isfinite(worst) and out.count("| draft |") == 8 and "goal ≤ 1.2×" in out
