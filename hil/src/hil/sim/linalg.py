"""scipy.linalg, imported on first use: the import costs seconds in the User-Mode Linux guest
(scripts/with-vcan) and a CDRW run never needs it."""
from __future__ import annotations

from typing import Any


def expm(a: Any) -> Any:
    from scipy.linalg import expm as f
    return f(a)


def solve_discrete_are(*args: Any, **kw: Any) -> Any:
    from scipy.linalg import solve_discrete_are as f
    return f(*args, **kw)


def solve_continuous_lyapunov(*args: Any, **kw: Any) -> Any:
    from scipy.linalg import solve_continuous_lyapunov as f
    return f(*args, **kw)


def solve_discrete_lyapunov(*args: Any, **kw: Any) -> Any:
    from scipy.linalg import solve_discrete_lyapunov as f
    return f(*args, **kw)
