"""Scenario options of the plants ([plant] and [lqg] sections of a scenario file)."""
from __future__ import annotations

import math
from dataclasses import dataclass

from hil.scenario.cdrw_params import DEFAULT_PARAMS, CdrwParams
from hil.scenario.schema import spec

#: Multisine of the default CDRW excitation: frequencies (Hz) with Schroeder phases, each
#: component of amplitude excitation/len, so the peak never exceeds `excitation_deg`.
EXCITATION_HZ = (0.5, 0.9, 1.4, 2.2, 3.0)


@dataclass(frozen=True, kw_only=True)
class CdrwManeuver:
    """The pilot's elevator input, relative to trim (the paper's Fig. 5 flight).

    A cosine-ramped pull (trailing edge up, i.e. negative elevator) of ``pull_deg`` starting
    at ``pull_start``, held, then released back to trim; plus a small multisine so that the
    moving-window regression has excitation besides the slow manoeuvre (real flight data
    always has some: pilot, turbulence).
    """

    pull_deg: float = spec(5.5, ge=0.0, le=20.0)
    pull_start: float = spec(2.0, ge=0.0)
    pull_ramp: float = spec(1.0, gt=0.0)
    hold: float = spec(0.8, ge=0.0)
    release_ramp: float = spec(0.8, gt=0.0)
    excitation_deg: float = spec(0.5, ge=0.0, le=5.0)

    def offset(self, t: float) -> float:
        """Elevator relative to trim at time t (rad)."""
        t1 = self.pull_start + self.pull_ramp
        t2 = t1 + self.hold
        t3 = t2 + self.release_ramp
        shape = _ramp(t, self.pull_start, t1) - _ramp(t, t2, t3)
        de = -math.radians(self.pull_deg) * shape
        if self.excitation_deg > 0.0:
            k = len(EXCITATION_HZ)
            amp = math.radians(self.excitation_deg) / k
            for i, fr in enumerate(EXCITATION_HZ, start=1):
                de += amp * math.sin(2.0 * math.pi * fr * t - math.pi * i * (i - 1) / k)
        return de


def _ramp(t: float, t0: float, t1: float) -> float:
    if t <= t0:
        return 0.0
    if t >= t1:
        return 1.0
    return 0.5 - 0.5 * math.cos(math.pi * (t - t0) / (t1 - t0))


@dataclass(frozen=True, kw_only=True)
class CdrwPlantOptions:
    """[plant] of a CDRW scenario.

    process_noise: bound of the per-step disturbance v_k on (alpha, q), uniform in the box
    |v| <= bound (the paper's model x_{k+1} = A x_k + B de_k + v_k, v_k in <0, E>, E = 0.004 I);
    it is applied as a rate v_k/dt held over the step.
    """

    dt: float = spec(0.02, ge=0.001, le=0.1)        # s, frame period (seed 1: 50 Hz)
    substep: float = spec(0.002, ge=1e-5, le=0.02)  # s, RK4 sub-step
    process_noise: tuple[float, float] = spec((0.004, 0.004), ge=0.0)
    q0: float = spec(0.0)                           # rad/s, initial pitch rate
    maneuver: CdrwManeuver = spec(default_factory=CdrwManeuver)
    params: CdrwParams = spec(default_factory=lambda: DEFAULT_PARAMS)  # [plant.params] overrides


@dataclass(frozen=True, kw_only=True)
class MissilePlantOptions:
    """[plant] of a missile scenario."""

    q0: float = spec(0.1)            # rad/s (seed 2)
    alpha0: float = spec(0.0)        # rad
    gust0: float | str = spec(0.0, choices=("stationary",))  # ft/s, or "stationary"
    gust_scale: float = spec(1.0, ge=0.0)   # multiplies the gust input f (0: no gust)
    substeps: int = spec(8, ge=8, le=1000)  # minimum per control period (seed 2: >= 8); the
    # plant integrates on the common 2.5 ms base (T = 0.1 s: 40), see missile.substeps_for


#: realtime: the actuation instant of the time-triggered schedule, t_k + 5 ms (two steps of
#: the plant's common 2.5 ms base; fcc's FCC_APP_MSL_RT_DELAY): room for 3.5 ms of simulator
#: lateness in the loaded UML guest; the delay-aware LQG loses 0.1-1.2 % RMS q to it (60 s,
#: T = 0.1-0.02 s, measured offline with simulate_missile)
RT_ACTUATION_DELAY = 0.005


@dataclass(frozen=True, kw_only=True)
class LqgOptions:
    """[lqg] of a missile scenario: sampling period and D/A word length."""

    period: float = spec(0.1, ge=0.005, le=1.0)   # s (seed 2 studies 0.05, 0.1, 0.2)
    bits: int = spec(8, ge=2, le=16)              # D/A word length
    closed_loop: bool = spec(True)                # false: open loop (elevator code 0)
    # the command of the sample at t_k acts from t_k + delay (s, < period); "auto": 0 in
    # lockstep, RT_ACTUATION_DELAY in realtime; fcc designs its LQG for it (--lqg-delay)
    delay: float | str = spec("auto", ge=0.0, le=1.0, choices=("auto",))

    def __post_init__(self) -> None:
        if isinstance(self.delay, float) and not self.delay < self.period:
            raise ValueError(f"field 'delay': {self.delay} s must be shorter than the period "
                             f"{self.period} s")

    def resolved_delay(self, realtime: bool) -> float:
        """The delay in seconds for a lockstep or a realtime run."""
        if isinstance(self.delay, float):
            return self.delay
        return RT_ACTUATION_DELAY if realtime else 0.0
