"""Counterweight balancing on the linear map (four-bar static and full, optimal for every family); rotors;
slider-crank Lanchester balancing."""

from ..counter_rotors import CounterRotor
from .batch import StaticCase, balance_static_batch
from .fourbar import (
    BalanceResult,
    Weights,
    balance_full,
    balance_optimal,
    balance_static,
    counter_rotor_loads,
    exact_static_counterweights,
    least_squares_crank_counterweight,
    objective_value,
    pendulum_inertia,
    relative_weights,
    tradeoff,
)
from .fixed_points import fixed_point_counterweights
from .program import CounterweightSpec
from .rotors import Correction, RotorBalance, RotorMass, balance_rotor_dynamic, balance_rotor_static
from .slider_crank import LanchesterPair, SliderCrankBalance, balance_slider_crank

__all__ = [
    "BalanceResult", "Correction", "CounterRotor", "CounterweightSpec", "LanchesterPair", "RotorBalance",
    "RotorMass", "SliderCrankBalance", "Weights", "balance_full", "balance_optimal", "balance_rotor_dynamic",
    "balance_rotor_static", "balance_slider_crank", "balance_static", "counter_rotor_loads",
    "exact_static_counterweights", "least_squares_crank_counterweight", "objective_value", "pendulum_inertia",
    "relative_weights", "tradeoff", "fixed_point_counterweights", "StaticCase", "balance_static_batch",
]
