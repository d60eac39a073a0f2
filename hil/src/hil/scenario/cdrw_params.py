"""CDRW (Cropped Delta Reflex Wing) UAV: every number of the simulated airframe, in one place.

The paper (seed 1, Table 3, after Saderla et al. 2019) publishes only the geometry and the
weight.  No aerodynamic derivatives are published for this aircraft, so the values below are
*representative* of a small, tailless, low-aspect-ratio delta wing and each one says where it
comes from or how it was chosen.  They are tuned together so that the default flight looks
like the paper's Fig. 5: trim at alpha ~ 9 deg, a pull-up that passes 15 deg near 3 s and is
back below 15 deg by ~5 s, with reduced stability above ~15 deg and hysteresis on recovery.

Conventions: stability axes, angles in rad, rates in rad/s, SI units; positive elevator
(elevon) deflection = trailing edge down = nose-down moment (C_m_de < 0), so a pull-up is a
negative elevator step.  Non-dimensional rate: q_hat = q * cbar / (2 V).

Flow-separation model (Goman & Khrabrov 1994, Kirchhoff-type separation point x in [0, 1],
1 = attached, 0 = fully separated):

    tau1 * dX/dt + X = X0(alpha - tau2 * alpha_dot)
    X0(a) = 0.5 * (1 - tanh(a1 * (a - alpha_star)))

and the coefficients blend attached and separated flow linearly in X:

    C_L = C_L0 + C_La * alpha * (X + (1-X)*eta_L) + C_Lq * q_hat + C_Lde * de
    C_m = C_m0 + C_ma * alpha * (X + (1-X)*eta_m) + dCm_sep * (1-X)
          + C_mq * q_hat * (X + (1-X)*eta_q) + C_mde * de

Separated flow keeps a fraction eta_* of the attached lift slope, pitch stiffness and pitch
damping; because X lags alpha (tau1) and is driven by alpha - tau2*alpha_dot, the same alpha
gives a larger X on the up-stroke than on the down-stroke: that is the hysteresis.

Resulting numbers (computed from these parameters; tests/python/sim/test_plant_cdrw.py checks
the flight they give): trim at alpha = 9 deg needs V = 11.96 m/s (qbar = 87.5 Pa,
cbar/V = 0.051 s) and de = -2.41 deg; attached-flow short period -5.88 +- 6.97j
(wn = 9.1 rad/s, zeta = 0.64, rho of the 20 ms discrete A = 0.889); fully separated
-1.23 +- 4.54j (zeta = 0.26, rho = 0.976).  The default flight peaks at ~23 deg with
min X ~ 0.17 and rho(A_true) ~ 0.96.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

#: standard gravity, m/s^2 (the task fixes the weight-to-mass conversion with it)
G0 = 9.80665


@dataclass(frozen=True)
class CdrwParams:
    # ---- geometry and mass: seed 1, Table 3 (Saderla et al. 2019) -------------------------
    span: float = 1.5            # m, Table 3
    S: float = 0.787             # m^2, reference area, Table 3
    cbar: float = 0.61           # m, mean aerodynamic chord, Table 3
    weight: float = 34.33        # N, Table 3; mass = weight / G0 = 3.5007 kg
    # Pitch inertia is not published.  A 3.5 kg flying wing of ~1 m length with the mass
    # concentrated near the centre line has a pitch radius of gyration of ~0.24 m
    # (~0.27 root chord, typical of small flying wings), J_y = m * 0.24^2 ~ 0.20 kg m^2.
    Jy: float = 0.20             # kg m^2

    # ---- atmosphere -------------------------------------------------------------------------
    rho_air: float = 1.225       # kg/m^3, ISA sea level (the flight tests were near sea level)

    # ---- attached-flow aerodynamics ---------------------------------------------------------
    # Lift slope: Helmbold's low-aspect-ratio formula 2*pi*A / (2 + sqrt(A^2 + 4)) with the
    # Table 3 aspect ratio A = 2.9259 gives 3.32 /rad.  (Table 3 is not quite consistent:
    # span^2 / S = 2.859; with that A the formula gives 3.27 /rad, a 1.5 % difference.)
    C_L0: float = 0.0            # reflexed section: near-zero camber, zero-lift at alpha ~ 0
    C_La: float = 3.32           # /rad, Helmbold, A = 2.93
    C_Lq: float = 1.5            # /rad, tailless wing: small (order 1-3), from the wing alone
    C_Lde: float = 0.45          # /rad, full-span elevons on a low-AR wing (order 0.3-0.6)
    # Reflex gives a small positive zero-lift moment, which is what lets a tailless wing trim.
    C_m0: float = 0.02
    # Static margin ~7.5 % cbar, typical for flying wings: C_ma = -0.075 * C_La ~ -0.25 /rad.
    C_ma: float = -0.25          # /rad
    # Tailless delta wings have weak pitch damping (order -1 ... -2 /rad).
    C_mq: float = -1.2           # /rad
    # Elevon effectiveness, short moment arm of a tailless wing (order -0.3 ... -0.6 /rad).
    C_mde: float = -0.45         # /rad

    # ---- separated-flow fractions and separation dynamics -----------------------------------
    # Separated flow keeps 45 % of the lift slope (low-AR deltas keep part of their lift via
    # the leading-edge vortex; 1 would mean no stall at all, ~0.25 is Kirchhoff's flat plate).
    eta_L: float = 0.45
    # ... 45 % of the pitch stiffness (the centre of pressure moves forward as the outer
    # panels stall: the classic delta/swept-wing loss of static stability).
    eta_m: float = 0.45
    # ... and none of the pitch damping: delta and swept wings lose their pitch damping near
    # and past the stall (C_mq -> 0 or even > 0 is reported in high-alpha wind-tunnel data).
    # This, with the lift-slope loss (less alpha damping Z_alpha), is what raises rho(A).
    eta_q: float = 0.0
    # Extra moment at full separation (0: the break itself is neither nose-up nor nose-down;
    # the stability loss comes from eta_L, eta_m and eta_q).
    dCm_sep: float = 0.0
    # Breakpoint alpha* and steepness a1: X0(9 deg) = 0.985, X0(15 deg) = 0.74,
    # X0(19 deg) = 0.26, so the change of dynamics starts at ~15 deg as in the paper's Fig. 7.
    # Between ~15.5 and ~21 deg the *static* moment slope (with X = X0(alpha)) is slightly
    # positive: the delta-wing pitch-up; the lag tau1 keeps the flight controllable.
    alpha_star_deg: float = 17.0
    a1: float = 15.0             # 1/rad
    # Time constants: the literature on delta and transport wings (Goman & Khrabrov 1994,
    # Fischenberg 1995) reports tau1 of order 10-30 convective times cbar/V and tau2 of a
    # few; with cbar/V ~ 0.05 s here, tau1 = 0.5 s (~10 cbar/V) and tau2 = 0.15 s
    # (~3 cbar/V).  tau1 ~ 0.5 s makes the post-stall difference of Fig. 7 last ~1-1.5 s
    # after alpha is back under 15 deg, as the paper describes.
    tau1: float = 0.5            # s
    tau2: float = 0.15           # s

    # ---- default flight (the paper's Fig. 5) ------------------------------------------------
    alpha_trim_deg: float = 9.0  # trim alpha; the speed that trims there is derived (trim())

    def __post_init__(self) -> None:
        for name in ("span", "S", "cbar", "weight", "Jy", "rho_air", "a1", "tau1"):
            if not getattr(self, name) > 0.0:
                raise ValueError(f"CDRW parameter {name} must be > 0, got {getattr(self, name)}")
        if self.tau2 < 0.0:
            raise ValueError(f"CDRW parameter tau2 must be >= 0, got {self.tau2}")
        if self.C_mde == 0.0:
            raise ValueError("CDRW parameter C_mde must be non-zero (the elevator must trim)")

    @property
    def mass(self) -> float:
        """kg, from the Table 3 weight and standard gravity."""
        return self.weight / G0

    @property
    def aspect_ratio(self) -> float:
        return self.span**2 / self.S

    @property
    def alpha_star(self) -> float:
        return math.radians(self.alpha_star_deg)

    @property
    def alpha_trim(self) -> float:
        return math.radians(self.alpha_trim_deg)


#: the parameters every default run uses
DEFAULT_PARAMS = CdrwParams()
