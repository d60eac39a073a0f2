"""A realtime run's time synchronisation, judged: was fcc's sync attacked, refused or lost?

fcc reports its time sync in the authenticated heartbeat: FCC_SYNC_STATUS (state, losses) and
FCC_SYNC_REFUSALS (what it did not take from the time master: frames without a valid
TSYNC_AUTH, forged and replayed authenticators, authenticated pairs implausible against its own
clock; firmware/app/README.md "Time synchronisation").  The rig's own master says how many of
its frames went out without an authenticator (a SYNC whose echo never came): those, and only
those, fcc may drop as unauthenticated in a clean run.  summary.json's `sync` is this verdict;
`hil run` exits 7 (hil.cli) and prints its line when it is not "ok".
"""
from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from hil.bus.protocol import SYNC_STATE_NAMES, SYNC_STATES
from hil.rig.status import StatusCounters

REFUSALS = ("mac_failed", "freshness_failed", "unauthenticated", "step_refused", "rate_refused")
#: final states of a sync that held (LOCKING: relocking after nothing worse than a residual)
HELD = (SYNC_STATES["LOCKING"], SYNC_STATES["LOCKED"])


def sync_summary(status: StatusCounters, master: Mapping[str, Any] | None) -> dict[str, Any]:
    """summary.json's `sync`: fcc's state and counters at its last heartbeat, the master's
    unpaired frames, the verdict (ok, attacked, refused, lost) and its one line."""
    g = status.get
    state = int(status.last.get("FCC_SYNC_STATUS", {}).get("state", SYNC_STATES["FREE_RUN"]))
    refused = {k: g(f"FCC_SYNC_REFUSALS.{k}") for k in REFUSALS}
    losses = g("FCC_SYNC_STATUS.losses")
    unpaired = int((master or {}).get("unpaired_frames", 0))
    forged_frames = max(0, refused["unauthenticated"] - unpaired)
    implausible = refused["step_refused"] + refused["rate_refused"]
    name = SYNC_STATE_NAMES.get(state, str(state))
    found: list[tuple[str, str]] = []
    if implausible or state == SYNC_STATES["REFUSED"]:
        found.append(("refused", f"time master refused: {implausible} authenticated SYNC/FOLLOW_UP "
                                 f"pairs implausible against fcc's clock (step "
                                 f"{refused['step_refused']}, rate {refused['rate_refused']})"))
    if forged_frames or refused["mac_failed"] or refused["freshness_failed"]:
        found.append(("attacked", f"time sync attacked: {forged_frames} forged SYNC/FOLLOW_UP "
                                  f"frames, {refused['mac_failed']} forged and "
                                  f"{refused['freshness_failed']} replayed TSYNC_AUTH refused"))
    if losses or state not in HELD + (SYNC_STATES["REFUSED"],):
        found.append(("lost", f"time sync lost: {losses} losses"))
    verdict = found[0][0] if found else "ok"
    line = ("; ".join(text for _, text in found) + f" (fcc {name} at the end)") if found else ""
    return {"state": name, "losses": losses, "rejected": g("FCC_SYNC_STATUS.rejected"),
            "refused": refused, "master_unpaired_frames": unpaired, "verdict": verdict,
            "message": line}
