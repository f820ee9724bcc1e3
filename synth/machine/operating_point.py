"""Where a motor runs under a machine's mean load: the speed on its characteristic the train ratio is taken from.

An induction motor's static characteristic is linear from zero torque at synchronous speed w_s through the rated
point (rated torque T_r at rated speed w_r): T(w) = k·(w_s - w), k = T_r/(w_s - w_r). A machine whose crank
takes the mean power P at its working speed draws P/eta from the motor (eta the train's efficiency), so the
motor settles where k·(w_s - w)·w = P/eta. Of the two roots, the upper one lies on the stable branch (torque
falling with speed, above the breakdown speed): w = (w_s + sqrt(w_s² - 4·P/(eta·k)))/2. A lightly loaded
motor runs near w_s, not at w_r; a train ratio taken from w_r turns the crank too fast by up to (w_s - w_r)/w_r.

The linear characteristic makes this exact for the angle-average crank speed of the steady motion (zero net work
over the cycle, whatever the flywheel); the simulated mean (over time) differs from it by the order of delta².
"""

from __future__ import annotations

import math

from ..errors import Infeasible
from ..gearing import CatalogueMotor


def operating_speed(motor: CatalogueMotor, power: float) -> float:
    """Speed [rad/s] at which ``motor`` gives the mean ``power`` [W] on its linear characteristic (stable branch).

    Raises Infeasible (constraint ``drive.motor``) when the power exceeds the most the characteristic gives,
    k·w_s²/4 at half the synchronous speed.
    """
    k = motor.rated_torque / (motor.synchronous_speed - motor.rated_speed)
    disc = motor.synchronous_speed**2 - 4.0 * power / k
    if disc < 0:
        raise Infeasible(f"motor {motor.name} cannot give the machine's mean {power:.4g} W on its characteristic "
                         f"(at most {k * motor.synchronous_speed**2 / 4:.4g} W): name a larger motor",
                         constraint="drive.motor", required_power_W=power)
    return 0.5 * (motor.synchronous_speed + math.sqrt(disc))


class MotorLoad:
    """The motor speed function a drive takes its ratio from: each motor at its operating point for ``power``
    [W] on the motor shaft. A plain callable object, so the drive design can call it for every candidate.

    A motor too small for the power (only when the reserve factor is below 1) is given half its synchronous
    speed, where its characteristic gives the most power: the simulated machine then shows it overloaded and
    the chain steps up to the next size, as it does for any motor the cycle overloads.
    """

    __slots__ = ("power",)

    def __init__(self, power: float) -> None:
        self.power = power

    def __call__(self, motor: CatalogueMotor) -> float:
        """Operating speed of ``motor`` [rad/s] (see :func:`operating_speed`)."""
        try:
            return operating_speed(motor, self.power)
        except Infeasible:
            return 0.5 * motor.synchronous_speed
