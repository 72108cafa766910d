"""The kinematics bench compares like with like: its references and pylinkage solve the same joints."""

from __future__ import annotations

import math

import numpy as np
import pytest

from linkstress.kinematics import FourBar, solve_fourbar
from linkstress.validation.bench import kinematics as bench


@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_reference_loops_give_linkstress_joints_a_and_b_within_1e_15_of_the_loop_size(branch):
    # Norton's four-bar moved off the origin and tilted: ground 6, crank 8, coupler 8, output 9 cm
    linkage = FourBar((0.3, -0.2), (0.3 + 0.06 * math.cos(0.4), -0.2 + 0.06 * math.sin(0.4)), 0.08, 0.08, 0.09,
                      branch)
    theta2 = np.linspace(0.0, 2 * math.pi, 361)
    motion = solve_fourbar(linkage, theta2)
    expected = np.hstack([motion.joints["A"].position, motion.joints["B"].position])
    assert np.abs(bench.numpy_positions(linkage, theta2) - expected).max() <= 1e-15
    assert np.abs(np.array(bench.python_positions(linkage, theta2.tolist())) - expected).max() <= 1e-15


def test_bench_prints_every_sweep_and_says_how_to_install_pylinkage_when_it_is_missing(monkeypatch, capsys):
    monkeypatch.setattr(bench, "pylinkage_status", lambda: "pylinkage not installed: pip install 'pylinkage[numba]'")
    bench.main(["--positions", "2000", "--python-positions", "200", "--repeat", "1"])
    out = capsys.readouterr().out
    assert "linkstress solve_fourbar" in out and "2,000" in out
    assert "pip install 'pylinkage[numba]'" in out
    assert "plain Python loop" in out and "200" in out
    assert "one plain numpy pass" in out
    assert "machine of 4 chained loops" in out and "3600 of 3600 feasible" in out


def test_pylinkage_sweeps_the_same_four_bar_on_the_same_branch():
    if bench.pylinkage_status():
        pytest.skip(bench.pylinkage_status())
    # 1,000 steps of 0.36 deg; pylinkage follows the root nearest its last position, linkstress a sign
    joints = bench.pylinkage_sweep(bench.TEXTBOOK, 1000)()
    assert joints.shape == (1000, 4, 2)
    assert bench.pylinkage_agreement(bench.TEXTBOOK, joints) <= 1e-12
