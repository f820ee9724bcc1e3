"""The revision diff: ranked by relative change, noise below the answers' own tolerance left out, a unit on every row."""

from __future__ import annotations

import pytest

from api.library.diff import ROUNDING, answer_changes, tolerances

# Two answers of the shape /v1/analysis gives, the second after a 2 % longer crank: the torque moved 10 %, the
# shaking force 2 %, a joint reaction 0.5 %; the two paths to the torque disagree by 1.2e-14 then 1.4e-14 N·m (the
# answer's own check) and the reduced inertia moved by 1e-12 kg·m² (rounding of a 0.05 kg·m² figure).
BEFORE = {"summary": {"rms_driving_torque_Nm": 10.0, "rms_shaking_force_N": 200.0, "max_driving_torque_Nm": 25.0,
                      "mean_reduced_inertia_kgm2": 0.05},
          "joint_reactions_N": {"O": [[100.0, 40.0], [90.0, 30.0]]},
          "checks": {"virtual_power_torque_max_diff_Nm": 1.2e-14}}
AFTER = {"summary": {"rms_driving_torque_Nm": 11.0, "rms_shaking_force_N": 204.0,
                     "max_driving_torque_Nm": 25.0 + 3e-15, "mean_reduced_inertia_kgm2": 0.05 + 1e-12},
         "joint_reactions_N": {"O": [[100.5, 40.0], [90.0, 30.0]]},
         "checks": {"virtual_power_torque_max_diff_Nm": 1.4e-14}}


def test_the_largest_relative_change_comes_first_and_noise_is_left_out() -> None:
    changes, same, quiet = answer_changes(BEFORE, AFTER)
    assert [c.path for c in changes] == ["summary.rms_driving_torque_Nm", "summary.rms_shaking_force_N",
                                         "joint_reactions_N.O.0.0"]
    # relative changes, computed by hand: 1/10, 4/200, 0.5/100
    assert [c.change_rel for c in changes] == pytest.approx([0.1, 0.02, 0.005], rel=1e-12)
    # every row has its unit, the joint reaction's from the name of the map it sits in
    assert [c.unit for c in changes] == ["N·m", "N", "N"]
    # left out: the check itself (2e-15 N·m) and the peak torque's 3e-15 N·m (below the N·m tolerance), and the
    # inertia's 1e-12 kg·m² (below a billionth of 0.05)
    assert quiet == 3
    # equal: the three other components of the reactions
    assert same == 3


def test_the_noise_is_offered_on_request_and_the_order_by_path() -> None:
    changes, _, quiet = answer_changes(BEFORE, AFTER, noise=True, order="path")
    assert quiet == 3 and len(changes) == 6
    # path order: the newer answer's own
    assert [c.path for c in changes][:2] == ["summary.rms_driving_torque_Nm", "summary.rms_shaking_force_N"]
    tol = tolerances(BEFORE, AFTER)
    # the larger of the check's own disagreement and a billionth of the largest torque (25 N·m)
    assert tol["N·m"] == pytest.approx(max(1.4e-14, ROUNDING * 25.0), rel=1e-6)
    # a check that disagrees more than rounding sets the tolerance of its unit
    loose = {**AFTER, "checks": {"virtual_power_torque_max_diff_Nm": 0.5}}
    assert tolerances(BEFORE, loose)["N·m"] == 0.5
    assert [c.path for c in answer_changes(BEFORE, loose)[0]] == ["summary.rms_driving_torque_Nm",
                                                                   "summary.rms_shaking_force_N", "joint_reactions_N.O.0.0"]
    assert tol["kg·m²"] == pytest.approx(ROUNDING * (0.05 + 1e-12), rel=1e-12)


def test_a_figure_that_appears_ranks_first() -> None:
    after = {**AFTER, "summary": {**AFTER["summary"], "max_bearing_force_N": 300.0}}
    changes, _, _ = answer_changes(BEFORE, after)
    assert changes[0].path == "summary.max_bearing_force_N" and changes[0].before is None
