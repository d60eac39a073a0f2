"""The registered applications, by name: what the rig iterates over.  The shipped ones are
the CDRW and the missile; register() adds another (a test's, or a new application's module)."""
from __future__ import annotations

from hil.apps.application import Application
from hil.apps.cdrw import Cdrw
from hil.apps.missile import Missile

APPLICATIONS: dict[str, Application] = {}


def register(app: Application) -> Application:
    """Adds an application (its name must be new)."""
    if app.name in APPLICATIONS:
        raise ValueError(f"application {app.name!r} is already registered")
    APPLICATIONS[app.name] = app
    return app


def unregister(name: str) -> None:
    APPLICATIONS.pop(name)


def application(name: str) -> Application:
    """The application of a scenario's `aircraft`."""
    try:
        return APPLICATIONS[name]
    except KeyError:
        raise ValueError(f"no application {name!r} (registered: {', '.join(APPLICATIONS)})") from None


def of_code(code: int) -> Application:
    """The application of a SIM_TICK.app code."""
    for app in APPLICATIONS.values():
        if app.code == code:
            return app
    raise ValueError(f"no application with SIM_TICK.app {code}")


for _shipped in (Cdrw(), Missile()):
    register(_shipped)
