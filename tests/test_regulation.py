"""Speed regulation after a load step: the self-regulating machine's exponential, the PI loop against an
independent linear simulation, Routh's conditions against the poles, and the unstable regulator refused."""

from __future__ import annotations

import math

import numpy as np
import pytest

from api.translate.linkage import linkage_from
from api.translate.foundation import regulator_from
from api.translate.motor import motor_from
from mechsynth_client.client import InfeasibleError, SynthClient
from mechsynth_client.schemas.foundation import RegulationIn
from synth.errors import Infeasible
from synth.flywheel import Motor
from synth.machine.regulation import PIController, closed_loop_poles, regulate, routh_stable, tune_pi
from synth.machine.simulate import MachineCycle

N = 60
PHI = np.arange(N) * 2 * math.pi / N
MOTOR = Motor(1500 * math.pi / 30, 1440 * math.pi / 30, 30.0, gear_ratio=3.0, efficiency=0.95)
J = 4.0
CYCLE = MachineCycle(PHI, np.full(N, J), np.zeros(N), np.full(N, -60.0))
EXAMPLES = RegulationIn.model_json_schema()["examples"]


def test_self_regulation_follows_the_closed_form() -> None:
    r = regulate(CYCLE, 0.0, MOTOR, 25.0, delta=0.005)
    s = MOTOR.reduced().slope
    # linear characteristic, constant inertia and load: w(t) = w_b + (w_a - w_b)·exp(-t/tau), tau = J/s
    assert r.time_constant == pytest.approx(J / s, rel=1e-12)
    assert r.drop == pytest.approx(25.0 / s, rel=1e-6)
    late = r.time >= r.step_time
    exact = r.speed_after + (r.speed_before - r.speed_after) * np.exp(-(r.time[late] - r.step_time) / (J / s))
    assert np.max(np.abs(r.omega[late] - exact)) < 1e-6 * r.speed_before
    assert r.settling_closed_form == pytest.approx(J / s * math.log((25.0 / s) / (0.005 * r.speed_after / 2)))
    # the simulated settling time is read off a grid of the run's points: within one grid step
    assert r.settling_time == pytest.approx(r.settling_closed_form, abs=r.time[1] - r.time[0])


def test_a_tuned_pi_loop_matches_an_independent_linear_simulation() -> None:
    s = MOTOR.reduced().slope
    c = tune_pi(J, s, 0.4, 0.1)
    zeta = -math.log(0.1) / math.sqrt(math.pi**2 + math.log(0.1) ** 2)
    poles = np.sort_complex(closed_loop_poles(J, s, c))
    # the pair sits at the overshoot's damping; its natural frequency is the one the tuning found
    wn = float(abs(poles[0]))
    assert poles == pytest.approx(np.sort_complex(np.roots([1, 2 * zeta * wn, wn * wn])), rel=1e-9)
    r = regulate(CYCLE, 0.0, MOTOR, 25.0, delta=0.005, controller=c)
    # speed change after a load step dM/p: w(p) = -dM / (J p² + s(1 + k_p) p + s k_i), whose inverse for the
    # poles sigma ± i·w_d is -dM·exp(sigma t)·sin(w_d t)/(J w_d)
    late = r.time >= r.step_time
    t = r.time[late] - r.step_time
    sigma, wd = poles[0].real, abs(poles[0].imag)
    dw = -25.0 * np.exp(sigma * t) * np.sin(wd * t) / (J * wd)
    assert np.max(np.abs(r.omega[late] - r.speed_before - dw)) < 1e-5 * np.max(np.abs(dw))
    assert r.settling_time is not None and r.settling_time < 0.4
    # integral action brings the reference back; the run ends 8 decay times after the step (e^-8 of the dip left)
    assert abs(r.omega[-1] - r.speed_before) <= math.exp(-8) * 25.0 / (J * wd) * 1.01


@pytest.mark.parametrize("kp, ki, tf", [(1.0, 50.0, 0.0), (5.0, 400.0, 0.05), (0.5, 900.0, 0.2), (-2.0, 5.0, 0.0),
                                        (3.0, 20.0, 0.01)])
def test_routh_agrees_with_the_poles(kp: float, ki: float, tf: float) -> None:
    c = PIController(kp, ki, tf)
    s = MOTOR.reduced().slope
    assert routh_stable(J, s, c) == bool(np.all(closed_loop_poles(J, s, c).real < 0))


def test_regulation_through_the_service(client: SynthClient) -> None:
    out = client.regulation(RegulationIn.model_validate(EXAMPLES[1]))
    assert out.ki_1_s is not None and out.ki_1_s > 0 and out.poles_real_1_s and max(out.poles_real_1_s) < 0
    # the example stays inside its model: the motor on its linear branch, the targets met
    assert out.validity and all(c.passed for c in out.validity) and not out.warnings
    assert out.settling_time_s is not None and abs(out.smoothed_speed_rpm[-1] - out.speed_before_rpm) < out.band_rpm
    with pytest.raises(InfeasibleError) as err:
        client.regulation(RegulationIn.model_validate({**EXAMPLES[0], "regulator": {"kp": -3, "ki": 1}}))
    assert err.value.problem["constraint"] == "regulator"
    png = client.regulation_png(RegulationIn.model_validate(EXAMPLES[0]))
    assert png[:8] == b"\x89PNG\r\n\x1a\n"


def test_the_record_page_draws_what_it_is_given() -> None:
    import io

    import matplotlib.pyplot as plt

    from synth.machine.foundation_plots import foundation_record_page

    r = regulate(CYCLE, 0.0, MOTOR, 25.0, delta=0.005)
    fig = foundation_record_page(regulation=r)
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png")
    plt.close(fig)
    assert buffer.getvalue()[:8] == b"\x89PNG\r\n\x1a\n" and len(fig.axes) == 2  # the table and the speed


# ---------------------------------------------------------------------------------------------------------------
# Where the model stops: the motor's whole characteristic, the tuning on the real loop, the settling band.

def _example(**changes: object) -> RegulationIn:
    return RegulationIn.model_validate({**EXAMPLES[0], **changes})


def test_a_load_beyond_the_breakdown_torque_is_refused_with_the_torque_it_lacks(client: SynthClient) -> None:
    from synth.analysis import analyse

    body = _example(load_step_Nm=250)
    cycle = analyse(linkage_from(body), body.omega_rad_s, samples=body.samples).reduced
    # the mean load after the step, angle-averaged, against breakdown × ratio × efficiency = 70·3·0.95 at the crank
    mean_load = -float(np.mean(cycle.resisting_torque)) + 250
    top = 70 * 3 * 0.95
    assert mean_load > top
    with pytest.raises(InfeasibleError) as err:
        client.regulation(body)
    problem = err.value.problem
    assert problem["condition"] == "motor_stalls" and problem["constraint"] == "load_step_Nm"
    assert problem["breakdown_torque_at_crank_Nm"] == pytest.approx(top, rel=1e-12)
    assert problem["torque_lacking_Nm"] == pytest.approx(mean_load - top, rel=1e-9)


def test_the_motor_never_gives_more_than_its_breakdown_torque() -> None:
    # the PI loop tuned for 0.05 s on the example asks more torque than the motor has at the peaks of the cycle:
    # the motor pulls out (a warning and a failed check), and no torque in the answer exceeds 70·3·0.95 N·m
    body = RegulationIn.model_validate({**EXAMPLES[0], "regulator": {"settling_time_s": 0.05, "overshoot": 0.05}})
    from synth.machine.regulation import regulate_linkage

    assert body.regulator is not None
    r = regulate_linkage(linkage_from(body), body.omega_rad_s, motor_from(body.motor), body.load_step_Nm,
                         constant_inertia=body.constant_inertia_kgm2, tuning=regulator_from(body.regulator)[1],
                         samples=body.samples)
    top = 70 * 3 * 0.95
    assert r.breakdown_torque == pytest.approx(top, rel=1e-12)
    assert float(r.motor_torque.max()) <= top * (1 + 1e-12)
    check = {c.name: c for c in r.checks}["motor_breakdown"]
    assert not check.passed and "motor_breakdown" in {w.code for w in r.warnings}


def test_tuning_places_the_real_loop_with_its_filter() -> None:
    from scipy.signal import impulse

    from synth.machine.regulation import damping_ratio

    s = MOTOR.reduced().slope
    c = tune_pi(J, s, 0.5, 0.05, 0.02)
    poles = closed_loop_poles(J, s, c)
    # the dominant pair at the damping of 5 % overshoot, -ln 0.05/sqrt(pi² + ln² 0.05) = 0.690
    zeta = -math.log(0.05) / math.sqrt(math.pi**2 + math.log(0.05) ** 2)
    assert damping_ratio(poles) == pytest.approx(zeta, rel=1e-6)
    # an independent linear simulation of the loop with its filter (scipy's impulse response of
    # (T_f p + 1)/(J T_f p³ + (J + s T_f) p² + s(1 + k_p) p + s k_i)) settles within 2 % of its dip in 0.5 s
    t = np.linspace(0, 1.0, 20001)
    _, y = impulse(([0.02, 1.0], [J * 0.02, J + s * 0.02, s * (1 + c.kp), s * c.ki]), T=t)
    outside = np.flatnonzero(np.abs(y) > 0.02 * y.max())
    assert t[outside[-1]] <= 0.5
    # the untuned filter's loop, as the gains tuned without it leave it (the third-order poles), is not
    untuned = PIController(2 * zeta * (4 / (zeta * 0.5)) * J / s - 1, J * (4 / (zeta * 0.5)) ** 2 / s, 0.02)
    assert damping_ratio(closed_loop_poles(J, s, untuned)) < 0.6


def test_the_filtered_example_reports_what_it_achieves_against_what_was_asked() -> None:
    from synth.machine.regulation import damping_ratio, regulate_linkage

    body = _example(regulator={"settling_time_s": 0.05, "overshoot": 0.05, "filter_time_s": 0.02})
    assert body.regulator is not None
    r = regulate_linkage(linkage_from(body), body.omega_rad_s, motor_from(body.motor), body.load_step_Nm,
                         constant_inertia=body.constant_inertia_kgm2, tuning=regulator_from(body.regulator)[1],
                         samples=body.samples)
    assert r.poles is not None and damping_ratio(r.poles) > 0.6  # tuned without the filter: 0.11
    checks = {c.name: c for c in r.checks}
    assert checks["regulator_settling_time"].value == r.settling_time
    assert checks["regulator_overshoot"].value == r.overshoot and checks["regulator_overshoot"].passed
    # every failed check has its warning
    assert {c.name for c in r.checks if not c.passed} <= {w.code for w in r.warnings}


def test_settling_is_judged_in_two_percent_of_the_dip() -> None:
    r = regulate(CYCLE, 0.0, MOTOR, 25.0)
    s = MOTOR.reduced().slope
    # the exponential exp(-t/tau) falls to 2 % of the drop after tau·ln 50 (constant inertia and load)
    assert r.band == pytest.approx(0.02 * r.drop, rel=1e-6)
    assert r.settling_time == pytest.approx(J / s * math.log(50), abs=r.time[1] - r.time[0])
    # a band as wide as the dip is not allowed to say "settled at once"
    wide = regulate(CYCLE, 0.0, MOTOR, 25.0, delta=0.5)
    assert wide.settling_time == pytest.approx(r.settling_time, rel=1e-9)
    assert "settling_band_wide" in {w.code for w in wide.warnings}


def test_a_pi_loop_without_a_filter_settles_after_a_time() -> None:
    s = MOTOR.reduced().slope
    r = regulate(CYCLE, 0.0, MOTOR, 25.0, controller=tune_pi(J, s, 0.4, 0.1), target=(0.4, 0.1))
    # the disturbance response dM·exp(sigma t)·sin(w_d t)/(J w_d) needs time to fall within 2 % of its dip
    assert r.settling_time is not None and r.settling_time > 0.1
    assert all(c.passed for c in r.checks), r.checks


def test_a_barely_damped_loop_is_refused_at_once_with_its_poles() -> None:
    s = MOTOR.reduced().slope
    tf = 0.05
    # k_p = 0 and k_i at 0.999 of Routh's limit (J + s T_f)(1 + k_p)/(J T_f): stable, damping ratio near zero
    c = PIController(0.0, 0.999 * (J + s * tf) / (J * tf), tf)
    assert routh_stable(J, s, c)
    with pytest.raises(Infeasible) as err:
        regulate(CYCLE, 0.0, MOTOR, 25.0, controller=c)
    assert err.value.details["condition"] == "regulator_underdamped"
    expected = np.sort_complex(np.roots([J * tf, J + s * tf, s, s * c.ki]))
    got = np.sort_complex(np.array(err.value.details["poles_real_1_s"])
                          + 1j * np.array(err.value.details["poles_imag_1_s"]))
    assert got == pytest.approx(expected, rel=1e-9)
