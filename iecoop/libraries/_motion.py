"""The set-point generator of the simulated Tc2_MC2 axis: trapezoidal velocity profiles as data.

A profile is a list of segments of constant acceleration, ``(duration_s,
acceleration)``, that starts from a position and a velocity; it ends at rest
on a target (a point-to-point move, a stop) or runs on at its last velocity
(a velocity move). ``evaluate`` gives position, velocity and acceleration at
any time since the start, in closed form, so the value at a cycle does not
depend on how often it was asked for, and a finished point-to-point move
stands exactly on its target.

The rules, as PLCopen Motion Control Part 1 describes a move and Beckhoff's
NC PTP executes one without jerk limitation:

* accelerate with ``acc`` up to the commanded velocity, cruise, brake with
  ``dec`` so that the velocity reaches 0 on the target (a trapezoid); when
  the distance is too short to reach the velocity the cruise drops out and
  the peak is where the two ramps meet (a triangle);
* a move started while the axis travels the other way, or too fast to stop
  before the target, first brakes to standstill with ``dec`` and then moves
  back (the reversal PLCopen's MC_Aborting asks for);
* a velocity above the commanded one is first braked down with ``dec``.

Jerk is not limited (a jerk input is accepted and ignored).
"""

from __future__ import annotations

import math
from typing import NamedTuple

__all__ = ["Profile", "Sample", "evaluate", "plan_move", "plan_stop", "plan_velocity"]

#: Distances below this (in position units) count as zero: the move is already there.
EPSILON = 1e-9
#: A segment counts as ended this close to its end (1 ns, the clock's resolution), so that float
#: rounding of the durations does not push a move's end one cycle later.
_TIME_EPSILON = 1e-9


class Sample(NamedTuple):
    """Set position, set velocity and set acceleration at one instant."""

    position: float
    velocity: float
    acceleration: float


class Profile(NamedTuple):
    """Segments of constant acceleration from ``(start, velocity)``.

    ``endless``: after the last segment the axis runs on at the reached
    velocity; otherwise it stands still on ``target``.
    """

    start: float
    velocity: float
    segments: tuple[tuple[float, float], ...]
    target: float
    endless: bool

    @property
    def duration(self) -> float:
        """Seconds until the last segment ends (the move's end, or reaching the velocity)."""
        return sum(duration for duration, _ in self.segments)


def _ramp(segments: list[tuple[float, float]], duration: float, acceleration: float) -> None:
    if duration > 0.0:
        segments.append((duration, acceleration))


def plan_move(start: float, velocity: float, target: float, vmax: float, acc: float, dec: float) -> Profile:
    """A point-to-point move from ``start`` at ``velocity`` to rest on ``target``.

    ``vmax``, ``acc`` and ``dec`` are positive.
    """
    segments: list[tuple[float, float]] = []
    position, speed = start, velocity
    distance = target - position
    if abs(distance) <= EPSILON and abs(speed) <= EPSILON:
        return Profile(start, velocity, (), target, False)
    direction = 1.0 if distance > 0 or (distance == 0 and speed >= 0) else -1.0
    along = speed * direction  # velocity towards the target (negative: moving away)
    if along < 0.0 or along * along / (2.0 * dec) > abs(distance) + EPSILON:
        # Moving away, or too fast to stop in time: brake to standstill first, then move from there.
        brake = abs(speed) / dec
        braking_acc = -dec if speed > 0 else dec
        _ramp(segments, brake, braking_acc)
        position += speed * brake + 0.5 * braking_acc * brake * brake
        rest = plan_move(position, 0.0, target, vmax, acc, dec)
        return Profile(start, velocity, tuple(segments) + rest.segments, target, False)
    remaining = abs(distance)
    if along > vmax:
        slow = (along - vmax) / dec
        _ramp(segments, slow, -direction * dec)
        remaining -= (along * along - vmax * vmax) / (2.0 * dec)
        along = vmax
    peak = min(vmax, math.sqrt(max(0.0, (2.0 * acc * dec * remaining + dec * along * along) / (acc + dec))))
    peak = max(peak, along)
    accelerate = (peak - along) / acc
    brake = peak / dec
    cruise_distance = remaining - (peak * peak - along * along) / (2.0 * acc) - peak * peak / (2.0 * dec)
    cruise = max(0.0, cruise_distance) / peak if peak > 0.0 else 0.0
    _ramp(segments, accelerate, direction * acc)
    _ramp(segments, cruise, 0.0)
    _ramp(segments, brake, -direction * dec)
    return Profile(start, velocity, tuple(segments), target, False)


def plan_velocity(start: float, velocity: float, commanded: float, acc: float, dec: float) -> Profile:
    """Reach the signed velocity ``commanded`` from ``velocity`` and run on at it."""
    segments: list[tuple[float, float]] = []
    speed = velocity
    if speed * commanded < 0.0:  # reversing: brake to standstill first
        _ramp(segments, abs(speed) / dec, -dec if speed > 0 else dec)
        speed = 0.0
    change = commanded - speed
    faster = abs(commanded) > abs(speed)
    rate = acc if faster else dec
    _ramp(segments, abs(change) / rate, math.copysign(rate, change))
    return Profile(start, velocity, tuple(segments), math.nan, True)


def plan_stop(start: float, velocity: float, dec: float) -> Profile:
    """Brake from ``velocity`` to standstill with ``dec``; the target is where the axis comes to rest."""
    brake = abs(velocity) / dec
    acceleration = -dec if velocity > 0 else dec
    target = start + velocity * brake + 0.5 * acceleration * brake * brake
    segments = ((brake, acceleration),) if brake > 0.0 else ()
    return Profile(start, velocity, segments, target, False)


def evaluate(profile: Profile, elapsed: float) -> tuple[Sample, bool]:
    """The set point ``elapsed`` seconds after the profile's start, and whether its last segment has ended."""
    position, speed = profile.start, profile.velocity
    remaining = max(0.0, elapsed)
    for duration, acceleration in profile.segments:
        if remaining < duration - _TIME_EPSILON:
            return (
                Sample(position + speed * remaining + 0.5 * acceleration * remaining * remaining,
                       speed + acceleration * remaining, acceleration),
                False,
            )
        position += speed * duration + 0.5 * acceleration * duration * duration
        speed += acceleration * duration
        remaining -= duration
    if profile.endless:
        return Sample(position + speed * remaining, speed, 0.0), True
    return Sample(profile.target, 0.0, 0.0), True
