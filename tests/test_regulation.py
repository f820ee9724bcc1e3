"""Speed regulation after a load step: the self-regulating machine's exponential, the PI loop against an
independent linear simulation, Routh's conditions against the poles, and the unstable regulator refused."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mechsynth_client.client import InfeasibleError, SynthClient
from mechsynth_client.schemas.foundation import RegulationIn
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
    wn = 4 / (zeta * 0.4)
    poles = np.sort_complex(closed_loop_poles(J, s, c))
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
    assert out.kp is not None and out.kp > 0 and out.poles_real_1_s and max(out.poles_real_1_s) < 0
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
