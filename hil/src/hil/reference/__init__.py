"""Numpy reference of the seed-1 identification (MLS, KF, ZKF, AZKF).

Same semantics as the C modules in firmware/sid (same defaults, same row
meaning, same reduction rule), written the way the equations read, so that
the tests can compare the firmware with an independent implementation and
the benchmark can time the same step in numpy.  cdrw_study: Tables 4-5 of the reference on
the simulated CDRW flights against sid_replay (`python -m hil.reference.cdrw_study`).

Room 10: may import hil.util, hil.io, hil.bus, hil.scenario, hil.sim, hil.targets, hil.apps, hil.rig,
hil.results.
"""
from hil.reference.kf import Kf
from hil.reference.mls import Mls, MlsConfig, batch_fit
from hil.reference.model import Model, default_prior, default_prior_affine, norm2, spectral_radius
from hil.reference.sid import SidConfig, SidLoop, replay
from hil.reference.zkf import Azkf, AzkfConfig, Detector, DetectorConfig, Zkf
from hil.reference.zonotope import contains, hull, reduce_order

__all__ = [
    "Azkf", "AzkfConfig", "Detector", "DetectorConfig", "Kf", "Mls", "MlsConfig", "Model",
    "SidConfig", "SidLoop", "Zkf", "batch_fit", "contains", "default_prior", "default_prior_affine",
    "hull", "norm2",
    "reduce_order", "replay", "spectral_radius",
]
