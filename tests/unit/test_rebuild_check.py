"""The rebuild check's interval (parallel/halo.py steps_to_next_check): between two checks no
element can cross half the skin while its speed and acceleration at most double."""

from __future__ import annotations

import math

import pytest

from pice.parallel.halo import CHECK_INTERVAL_CAP, GROWTH_SAFETY, steps_to_next_check


def _travel(n, speed, accel, dt):
    """Distance [m] of the leapfrog drifts over n steps from half-step speed ``speed`` [m/s] at
    constant acceleration ``accel`` [m/s^2] (the step's kick-drift sequence)."""
    v, x = speed, 0.0
    for _ in range(n):
        v += accel * dt
        x += v * dt
    return x


@pytest.mark.parametrize("speed,accel", [(1.0, 0.0), (5.0, 0.0), (0.0, 50.0), (3.0, 200.0), (40.0, 1e4)])
def test_no_element_crosses_the_budget_before_the_next_check(speed, accel):
    dt, budget = 3e-4, 0.15
    n = steps_to_next_check(budget, speed, accel, dt)
    assert 1 <= n <= CHECK_INTERVAL_CAP
    # the n - 1 steps without a check, with speed and acceleration grown by the safety factor
    assert _travel(n - 1, GROWTH_SAFETY * speed, GROWTH_SAFETY * accel, dt) <= budget


def test_limits():
    dt = 3e-4
    assert steps_to_next_check(0.15, 0.0, 0.0, dt) == CHECK_INTERVAL_CAP  # at rest
    assert steps_to_next_check(0.15, 0.01, 0.0, dt) == CHECK_INTERVAL_CAP  # slow: capped
    assert steps_to_next_check(0.15, 0.0, 0.0, dt, cap=1) == 1  # the check on every step
    assert steps_to_next_check(1e-6, 1.0, 0.0, dt) == 1  # near half the skin: every step
    assert steps_to_next_check(-0.01, 1.0, 0.0, dt) == 1
    assert steps_to_next_check(0.15, math.nan, 0.0, dt) == 1  # NaN: the health check reports it
    # constant speed: 1 + floor((budget / 2) / (v dt)) steps
    assert steps_to_next_check(0.15, 10.0, 0.0, dt) == 1 + math.floor(0.075 / (10.0 * dt))
