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
    rows, spread = shadow_quality.measure(64, repeat=2)
    assert len(rows) == 4 * len(shadow_quality.CASES)
    # each case's final × baseline in each run, the first run's in the rows
    finals = {r[0]: r[3] for r in rows if r[1] == "final"}
    assert list(spread) == [c[0] for c in shadow_quality.CASES]
    assert all(len(v) == 2 and v[0] == finals[k] and v[1] > 0 for k, v in spread.items())
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


def test_shadow_quality_cases_print_the_spread_only(one_run, capsys):
    shadow_quality.main(["--size", "64", "--cases", "height map, sun 35", "--repeat", "2"])
    out = capsys.readouterr().out
    assert out.count("| final:") == 2          # one case, two runs
    spread = [line for line in out.splitlines() if line.startswith("| height map, sun 35°")]
    assert len(spread) == 1 and spread[0].count(" · ") == 1 and "≤ 0.1×" in spread[0]


def test_shadow_quality_large_final_reports_times_and_memory():
    sec, march_sec, gap, peak, inputs = shadow_quality.large_final(96)
    assert sec > 0 and march_sec > 0 and peak > 0 and inputs == 96 * 96 * 4 * 4
    assert 0 <= gap < 0.05          # 96 px: final marches too (K = 64), the same march


def test_overhead_lights_prints_a_ratio_per_case(one_run, capsys):
    worst = overhead_lights.main(["--size", "64", "--levels", "draft"])
    out = capsys.readouterr().out
    assert np.isfinite(worst) and out.count("| draft |") == 8 and "goal ≤ 1.2×" in out


def test_suite_speed_reads_pytests_count_and_refuses_a_run_without_one():
    """benchmarks/suite_speed.py (issue 62) keeps each run's count of tests from pytest's
    last line, and a run that printed none (it failed before testing) is not a number."""
    import suite_speed
    assert suite_speed.pytest_summary("694 passed in 45.13s")[0] == 694
    assert suite_speed.pytest_summary("== 1380 passed, 2 skipped, 1 warning in 841.2s ==") == \
        (1380, 841.2)
    with pytest.raises(RuntimeError, match="no pytest summary"):
        suite_speed.pytest_summary("ERROR: file or directory not found: tests/x")
