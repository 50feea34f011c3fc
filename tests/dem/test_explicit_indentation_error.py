"""Error bars of the indentation's numbers (dem.explicit.indentation_error)."""

import math
from types import SimpleNamespace

import numpy as np
import pytest

from dem.explicit import ExplicitSettings, IndentationSettings, curve_summary, simulate_indentation
from dem.explicit.indentation_error import QUANTITIES, curve_sampling
from dem.scenes.tis_panel import tis_panel
from dem.tis_stiffness import tis_panel_k_def
from dem.units import MM


def _triangle(h: float):
    """The triangular curve P = 100 delta up to delta = 1, then 100 (2 - delta), recorded every
    ``h``, as a result: peak 100 at 1, out at 1.95 (P below 5 for 0.5 of travel)."""
    delta = np.arange(1, round(4.0 / h) + 1) * h
    load = np.where(delta <= 1.0, 100 * delta, np.maximum(0.0, 100 * (2.0 - delta)))
    summary = curve_summary(delta, load, ultimate_fraction=0.05, out_confirm=0.5)
    return SimpleNamespace(delta=delta, load=load, **summary)


def test_curve_sampling_closed_form():
    """On the triangle recorded every h: the peak rises by at most the slope times h between
    records (100 h), the deflection at peak and the ultimate deflection are known to one
    record (h), the loading energy to the area of one record at the load where the block is
    out (h P(delta_u), P(delta_u) = 100 (2 - delta_u) just below 5)."""
    h = 1e-3
    widths = curve_sampling(_triangle(h), h)
    np.testing.assert_allclose(widths["peak_load"], 100 * h, rtol=1e-9)
    np.testing.assert_allclose(widths["deflection_at_peak"], h)
    np.testing.assert_allclose(widths["ultimate_deflection"], h)
    res = _triangle(h)
    np.testing.assert_allclose(widths["loading_energy"], h * 100 * (2 - res.ultimate_deflection))
    # the bars hold the continuous curve's numbers (peak 100 at 1, out at 1.95)
    assert abs(res.peak_load - 100.0) <= widths["peak_load"]
    assert abs(res.ultimate_deflection - 1.95) <= widths["ultimate_deflection"] + 1e-12


def test_unreached_peak_is_unbounded():
    """A curve still rising at its end: its largest load is a lower bound of the peak, so
    every bar is infinite (never a finite bar on a number that may still grow)."""
    h = 1e-3
    delta = np.arange(1, 500) * h
    res = SimpleNamespace(delta=delta, load=100 * delta,
                          **curve_summary(delta, 100 * delta, 0.05, 0.5))  # fmt: skip
    assert not res.peak_reached
    assert all(math.isinf(w) for w in curve_sampling(res, h).values())


def test_a_rerun_whose_block_stays_in_leaves_the_loading_energy_unbounded():
    """The rerun's curve stops at delta = 1.5, after its peak but before the block is out: its
    peak load is comparable (a finite bar, twice the change, here 0), its loading energy is
    the work up to the stop, not up to an ultimate deflection, so that source is unbounded."""
    from dem.explicit.indentation_error import indentation_estimates

    h = 1e-3
    full = _triangle(h)
    cut = full.delta <= 1.5
    stopped = SimpleNamespace(**curve_summary(full.delta[cut], full.load[cut], 0.05, 0.5))
    assert stopped.peak_reached and math.isnan(stopped.ultimate_deflection)
    indentation = IndentationSettings(record_interval=h)
    est = indentation_estimates(lambda s, i: stopped, ExplicitSettings(k_n=1e9), indentation, full,
                                "cheap")  # fmt: skip
    assert est["peak_load"].sources["loading rate"] == 0.0
    assert math.isinf(est["loading_energy"].sources["loading rate"])
    assert math.isinf(est["ultimate_deflection"].sources["loading rate"])


def test_a_rerun_stopped_after_its_block_got_out_keeps_every_bar_finite(caplog):
    """A rerun stopped at delta = 3 (blocks passing through each other after the block was
    confirmed out at 1.95): its numbers are those of the whole curve, so every source is
    finite (here 0); a rerun stopped at 1.5, before the block got out, leaves the ultimate
    deflection and the loading energy unbounded and says why."""
    from dem.explicit.indentation_error import indentation_estimates

    h = 1e-3
    full = _triangle(h)
    indentation = IndentationSettings(record_interval=h)
    for end, bounded in ((3.0, True), (1.5, False)):
        cut = full.delta <= end
        rerun = SimpleNamespace(info={"stopped_by": "blocks 1 and 2 overlap"},
                                **curve_summary(full.delta[cut], full.load[cut], 0.05, 0.5))
        caplog.clear()
        est = indentation_estimates(lambda s, i, r=rerun: r, ExplicitSettings(k_n=1e9),
                                    indentation, full, "cheap")  # fmt: skip
        for name in ("loading_energy", "ultimate_deflection"):
            width = est[name].sources["loading rate"]
            assert width == 0.0 if bounded else math.isinf(width)
        assert ("blocks 1 and 2 overlap" in caplog.text) is not bounded


FAST = IndentationSettings(speed=50 * MM, max_deflection=0.15 * MM, record_interval=0.005 * MM)


def test_error_budgets_on_a_short_run():
    """A run stopped before its peak: with the budget "none" every number has an unknown bar;
    with "cheap" the rerun at half the speed is paid for (its cost is reported), and every
    source is unbounded, neither run reaching its peak; a bad budget is refused."""
    scene = tis_panel(3, 2.5)
    settings = ExplicitSettings(k_n=tis_panel_k_def(3), node_spacing=1.5 * MM)
    none = simulate_indentation(scene, settings, FAST, error="none")
    assert set(none.estimates) == {"peak_load", "deflection_at_peak", "loading_energy"}
    assert none.estimates["peak_load"].value == none.peak_load
    assert all(math.isinf(e.error) for e in none.estimates.values())
    cheap = simulate_indentation(scene, settings, FAST, error="cheap")
    peak = cheap.estimates["peak_load"]
    assert peak.value == none.peak_load  # the reruns leave the run itself alone
    assert peak.cost_s > 0
    assert math.isinf(peak.sources["loading rate"]) and math.isinf(peak.sources["curve sampling"])
    assert peak.omitted == ("time step", "node spacing") and not none.estimates["peak_load"].omitted
    with pytest.raises(ValueError, match="error budget"):
        simulate_indentation(scene, settings, FAST, error="some")
    assert set(QUANTITIES) >= set(cheap.estimates)
