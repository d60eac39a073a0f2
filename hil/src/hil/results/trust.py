"""A run's outputs, judged: did another node send as fcc, and do fcc's rows agree with the
reference on the same readings?

Every figure of the run comes from fcc's authenticated frames (hil.results.buslog): a forged
estimate, bound or flag reaches no table.  What was refused is still evidence of an attack on
the bus, and so is every frame fcc itself saw on one of its own identifiers (it never receives
its own: FCC_E2E_FAULTS.own_id, in its authenticated heartbeat).  The reference cross-check
(hil.results.rowtables.cross_check: sid_replay on the readings) must agree within a resolution
step of each frame and on every fault flag wherever the replay is faithful: a lockstep flight
of the host's fcc (the same arithmetic as sid_replay) without a degraded step (fcc used every
reading as the simulator sent it).

summary.json's `bus_trust` is this verdict; `hil run` prints its line and exits 7 (hil.cli)
when it is not "ok", the results complete in --out (every figure from authentic frames), as
for an attacked time synchronisation (hil.results.sync).
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from hil.rig.status import StatusCounters
from hil.targets import registry


@dataclass
class Forgeries:
    """What the reading refused on fcc's output identifiers: per authenticator (SID_OUT_AUTH,
    MSL_ELEV_CMD_AUTH), the frames and authenticators that did not verify (forged, replayed,
    or a genuine frame displaced by them), and the different second copies of a frame before
    its authenticator (``conflicts``)."""

    refused: dict[str, int] = field(default_factory=dict)
    conflicts: dict[str, int] = field(default_factory=dict)

    @property
    def total(self) -> int:
        return sum(self.refused.values()) + sum(self.conflicts.values())

    def describe(self) -> str:
        """'SID_OUT_AUTH: 12 refused, 3 conflicting copies; ...' (empty: nothing forged)."""
        return "; ".join(f"{name}'s group: {self.refused.get(name, 0)} refused, "
                         f"{self.conflicts.get(name, 0)} conflicting copies"
                         for name in sorted({*self.refused, *self.conflicts})
                         if self.refused.get(name) or self.conflicts.get(name))


def faithful_replay(mode: str, target: str, degraded_steps: int) -> str:
    """Why the cross-check's bound does not apply to this flight ('' : it applies)."""
    if mode != "lockstep":
        return "realtime: fcc steps on its own clock, the replay on the simulator's samples"
    if not registry.target(target).replay_exact:
        return f"target {target}: its arithmetic is not sid_replay's"
    if degraded_steps:
        return f"{degraded_steps} degraded steps: fcc held or refused readings the replay used"
    return ""


def _cross_check_failure(check: Mapping[str, Any]) -> str:
    """The cross-check's line when it exceeds its bound ('' : within it)."""
    res = check.get("resolution") or {}
    over = [f"{kind}s differ by {check[f'max_abs_{kind}_difference']:.2e} (bound {res[kind]:.0e})"
            for kind in ("estimate", "bound")
            if kind in res and check.get(f"max_abs_{kind}_difference", 0.0) > res[kind]]
    if check.get("fault_flag_mismatches"):
        over.append(f"fault flags differ at {check['fault_flag_mismatches']} steps")
    if not over:
        return ""
    return "fcc's rows disagree with sid_replay's on the same readings: " + ", ".join(over)


def bus_trust(forgeries: Forgeries, status: StatusCounters, replay_check: Mapping[str, Any] | None,
              not_faithful: str) -> dict[str, Any]:
    """summary.json's `bus_trust`: what was refused on fcc's outputs, fcc's count of frames on
    its own identifiers, whether the cross-check applied and held; the verdict (ok, forged,
    impersonated, cross_check) and its one line."""
    own_id = status.get("FCC_E2E_FAULTS.own_id")
    found: list[tuple[str, str]] = []
    if forgeries.total:
        found.append(("forged", f"frames forged on fcc's outputs refused ({forgeries.describe()})"))
    if own_id:
        found.append(("impersonated", f"fcc counted {own_id} frames on its own identifiers "
                                      "(another node sent as fcc)"))
    cross = _cross_check_failure(replay_check or {}) if not not_faithful else ""
    if cross:
        found.append(("cross_check", cross))
    verdict = found[0][0] if found else "ok"
    line = ("bus attacked or outputs untrustworthy: " + "; ".join(t for _, t in found)) if found else ""
    return {"verdict": verdict, "message": line, "own_id": own_id,
            "forged": {"refused": forgeries.refused, "conflicts": forgeries.conflicts},
            "cross_check": "applied" if not not_faithful else f"not applied: {not_faithful}"}
