"""The real quantiser's Monte Carlo (hil.sim.missile_quant) beside the LSB^2/12 model."""
from __future__ import annotations

import numpy as np

from hil.sim import missile_quant as mq


def test_quantise_matches_the_dac() -> None:
    from hil.sim.missile import DAConverter
    d = DAConverter(6)
    u = np.linspace(-1.0, 1.0, 401)
    assert np.allclose(mq.quantise(u, 6), [d.quantise(float(x)) for x in u])


def test_agrees_with_the_model_at_small_T() -> None:
    mc = mq.quantiser_study([0.05], [8], 0.8, 0.8, loops=40, seconds=20.0)
    d = mc["periods"][0]["dac"]["8"]
    for key in ("q", "alpha"):
        lo, hi = d["vs_open"][f"{key}_ci"]
        model = d["model_vs_open"][key]
        assert lo - 0.5 <= model <= hi + 0.5, (key, lo, hi, model)
        assert abs(d["vs_ideal"][key]) < 1.0     # 8 bits: no measurable cost


def test_model_overstates_the_6_bit_penalty_at_large_T() -> None:
    mc = mq.quantiser_study([0.2], [6], 0.8, 0.8, loops=60, seconds=30.0)
    d = mc["periods"][0]["dac"]["6"]
    assert d["vs_open"]["alpha_ci"][1] < d["model_vs_open"]["alpha"]
