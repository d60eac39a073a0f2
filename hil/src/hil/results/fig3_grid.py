"""Fig. 3's grid of sampling periods: 0.02 to 0.3 s every 10 ms (29 points).  A module of its
own so that the CLI's defaults cost no import of the results' numpy modules."""
from __future__ import annotations

FIG3_PERIODS = tuple(round(0.02 + 0.01 * i, 2) for i in range(29))
