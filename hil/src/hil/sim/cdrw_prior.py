"""The CDRW's "wind-tunnel" model at trim: the prior A0, B0 of the identification (seed 1).

The paper compared its MLS estimate with a wind-tunnel model; a wind tunnel measures the
quasi-steady aerodynamics, i.e. the separation point at its static value X = X0(alpha).
So the prior is the Jacobian of the (alpha, q) rates with X = X0(alpha) at the trim point,
discretised with the paper's Euler formula (eq. 3): A0 = I + dt A_c, B0 = dt B_c, and the
affine term c0 = dt (f(x*, de*) - A_c x* - B_c de*) of the same local model in absolute
coordinates (x_{k+1} ~ A0 x_k + B0 de_k + c0; f(x*, de*) = 0 at trim).

The paper's regression has no constant term.  A prior for it must keep the trim a fixed
point, otherwise the filters drift by c0 every step until the MLS has data; ``paper_form``
absorbs c0 into [A0 B0] by the smallest (Frobenius) change that does so:
    [A B] = [A0 B0] + c0 phi*^T / |phi*|^2,   phi* = (alpha*, q*, de*),
which is also what a least-squares fit without intercept converges to on trim data.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hil.scenario.cdrw_params import DEFAULT_PARAMS, CdrwParams
from hil.sim.cdrw import DT_FRAME, CdrwPlant


@dataclass(frozen=True)
class WindTunnelPrior:
    A: np.ndarray      # 2x2, Euler, static separation
    B: np.ndarray      # 2
    c: np.ndarray      # 2, affine term at trim (absolute coordinates)
    x_trim: np.ndarray  # (alpha*, q*) = (alpha_trim, 0)
    de_trim: float

    def paper_form(self) -> tuple[np.ndarray, np.ndarray]:
        """(A, B) with c absorbed so that the trim is a fixed point (no intercept)."""
        phi = np.array([self.x_trim[0], self.x_trim[1], self.de_trim])
        d = np.outer(self.c, phi) / float(phi @ phi)
        return self.A + d[:, :2], self.B + d[:, 2]

    def flat(self, affine: bool = False) -> np.ndarray:
        """(a11, a12, a21, a22, b1, b2) of the paper's form, or (..., c1, c2) with c."""
        if affine:
            return np.concatenate([self.A.ravel(), self.B, self.c])
        a, b = self.paper_form()
        return np.concatenate([a.ravel(), b])


def wind_tunnel_prior(params: CdrwParams = DEFAULT_PARAMS, dt: float = DT_FRAME,
                      eps: float = 1e-6) -> WindTunnelPrior:
    """Quasi-steady linearisation at trim (central differences), Euler form."""
    plant = CdrwPlant(params)
    tr = plant.trim
    x0 = np.array([tr.alpha, 0.0])
    a_c = np.empty((2, 2))
    for j in range(2):
        xp, xm = x0.copy(), x0.copy()
        xp[j] += eps
        xm[j] -= eps
        a_c[:, j] = (np.array(plant.static_rates(xp[0], xp[1], tr.de))
                     - np.array(plant.static_rates(xm[0], xm[1], tr.de))) / (2.0 * eps)
    b_c = (np.array(plant.static_rates(x0[0], x0[1], tr.de + eps))
           - np.array(plant.static_rates(x0[0], x0[1], tr.de - eps))) / (2.0 * eps)
    f0 = np.array(plant.static_rates(x0[0], x0[1], tr.de))
    c = dt * (f0 - a_c @ x0 - b_c * tr.de)
    return WindTunnelPrior(A=np.eye(2) + dt * a_c, B=dt * b_c, c=c, x_trim=x0, de_trim=tr.de)
