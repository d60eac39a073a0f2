"""The [sensors] section of a scenario: noise options of both aircraft's sensors (the models
that draw the noise are in hil.sim.sensors).  Plain data, no numpy: the rig's bus side reads
scenarios without the noise models."""
from __future__ import annotations

from dataclasses import dataclass

from hil.bus.apps import APP_NAMES, sensor_signals

#: signal names a sensor-level fault may target, per aircraft (its sensor frames' readings)
SIGNALS = {app: sensor_signals(app) for app in APP_NAMES}

NOISE_DISTRIBUTIONS = ("uniform", "triangular", "truncated_normal")


@dataclass(frozen=True, kw_only=True)
class CdrwSensorOptions:
    """[sensors] of a CDRW scenario."""

    distribution: str = "uniform"          # one of NOISE_DISTRIBUTIONS
    bound: tuple[float, float] = (0.02, 0.02)  # |w_alpha| rad, |w_q| rad/s  (SPEC: F = 0.02 I)
    de_bound: float = 0.001                # |w_de| rad

    def __post_init__(self) -> None:
        if self.distribution not in NOISE_DISTRIBUTIONS:
            raise ValueError(f"distribution must be one of {', '.join(NOISE_DISTRIBUTIONS)}, "
                             f"got {self.distribution!r}")
        if len(self.bound) != 2 or min(self.bound) < 0.0 or self.de_bound < 0.0:
            raise ValueError("noise bounds must be >= 0 (bound = [alpha, q])")


@dataclass(frozen=True, kw_only=True)
class MissileSensorOptions:
    """[sensors] of a missile scenario."""

    var_gyro: float = 0.8   # E{v_g^2}, rad^2/s^2 (seed 2 as printed)
    var_acc: float = 0.8    # E{v_a^2}, ft^2/s^4
    #: multiplies the noise the sensors add (0: noise-free readings, for the deterministic
    #: responses of Figs. 4-6); the autopilot's design keeps the nominal variances above
    noise_scale: float = 1.0

    def __post_init__(self) -> None:
        if not (self.var_gyro > 0.0 and self.var_acc > 0.0):
            # the autopilot's Kalman filter divides by them: fcc refuses 0 (exit 1 at run time)
            raise ValueError("noise variances var_gyro and var_acc must be > 0")
        if not self.noise_scale >= 0.0:
            raise ValueError("noise_scale must be >= 0")
