"""The missile's period with the D/A code switching inside it (the wire-time bus's commands,
MissileSimulation.advance_switched): one integration loop with advance and advance_substeps
(MissilePlant.step_substeps), checked against them on sub-step boundaries and against an
independent computation (scipy's expm) inside sub-steps."""
from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import expm

from hil.scenario.file import load_default_scenario
from hil.sim import missile
from hil.sim.missile_runs import MissileSimulation

H_NS = 2_500_000   # the default missile: T = 0.1 s, 40 sub-steps of 2.5 ms


def _sims(n: int = 2) -> list[MissileSimulation]:
    sc = load_default_scenario("missile")
    sims = [MissileSimulation(sc) for _ in range(n)]
    assert sims[0].n_sub == 40 and round(sims[0].period / sims[0].n_sub * 1e9) == H_NS
    return sims


def test_one_block_draw_is_the_numbers_of_one_draw_per_sub_step() -> None:
    """The claim step_substeps rests on: the generator fills a block in order."""
    block = np.random.default_rng([5, 0x6D73]).standard_normal((40, 3))
    one = np.random.default_rng([5, 0x6D73])
    np.testing.assert_array_equal(block, np.concatenate([one.standard_normal((1, 3)) for _ in range(40)]))


def test_one_code_per_sub_step_flies_like_advance_bit_for_bit() -> None:
    a, b = _sims()
    for code in (3, -7, 0, 12):
        a.sample()
        b.sample()
        np.testing.assert_array_equal(a.advance(code), b.advance_substeps([code] * b.n_sub))
    np.testing.assert_array_equal(a.plant.x, b.plant.x)


@pytest.mark.parametrize("switches", [
    [],
    [(0, 9)],
    [(3 * H_NS, 9)],
    [(3 * H_NS, 9), (3 * H_NS, -4)],            # two at once: the later one acts
    [(0, 2), (17 * H_NS, -20), (39 * H_NS, 5)],
])
def test_switches_on_sub_step_boundaries_fly_like_advance_substeps(switches: list[tuple[int, int]]) -> None:
    a, b = _sims()
    for _ in range(3):   # the code in force carries over from period to period
        a.sample()
        b.sample()
        codes, code = [], a.last_code
        for j in range(a.n_sub):
            code = next((c for at, c in reversed(switches) if at == j * H_NS), code)
            codes.append(code)
        np.testing.assert_array_equal(a.advance_switched(switches), b.advance_substeps(codes))
        assert a.last_code == b.last_code == code
        switches = [(at, c + 1) for at, c in switches]


def _gamma(tau: float) -> np.ndarray:
    """int_0^tau e^{F s} G ds, by scipy's expm of [[F, G], [0, 0]] tau (not hil's series)."""
    blk = np.zeros((4, 4))
    blk[:3, :3], blk[:3, 3] = missile.F, missile.G
    return expm(blk * tau)[:3, 3]


def test_switches_inside_sub_steps_against_an_independent_computation() -> None:
    """The same seed flown with the code switching inside sub-steps and with the code held:
    the gust is the same (it does not depend on when a command came), so the difference of the
    two traces is the response to the difference of the inputs alone, computed here on each
    sub-step as the sum over its pieces [a, b) of e^{F (h - b)} Gamma(b - a) du."""
    switched, held = _sims()
    switches = [(1_234_567, 37), (2_000_000, -12), (20 * H_NS + 7, 64), (39 * H_NS + 2_499_999, -128)]
    switched.sample()
    held.sample()
    ts = switched.advance_switched(switches)
    th = held.advance(0)
    h = H_NS * 1e-9
    phi = expm(missile.F * h)
    lsb = switched.dac.lsb
    du_at = [(0, 0.0)] + [(at, code * lsb) for at, code in switches]   # the held code is 0
    d = np.zeros(3)
    for j in range(switched.n_sub):
        start, end = j * H_NS, (j + 1) * H_NS
        cuts = [start] + [at for at, _ in du_at if start < at < end] + [end]
        d = phi @ d
        for a, b in zip(cuts, cuts[1:]):
            du = next(v for at, v in reversed(du_at) if at <= a)
            d = d + expm(missile.F * (end - b) * 1e-9) @ _gamma((b - a) * 1e-9) * du
        np.testing.assert_allclose(ts[j + 1] - th[j + 1], d, rtol=1e-9, atol=1e-13)
    assert switched.last_code == -128
    assert np.any(ts[1:] != th[1:])


def test_a_switch_outside_the_period_is_refused() -> None:
    (sim,) = _sims(1)
    sim.sample()
    with pytest.raises(ValueError, match="outside the period"):
        sim.advance_switched([(40 * H_NS, 1)])
