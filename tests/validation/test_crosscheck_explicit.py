"""The cross-check's explicit step names the contacts that resisted above the upper bound."""

import math
from types import SimpleNamespace

from validation.crosscheck.dem_steps import _resisting


def test_resisting_contacts_named_only_above_the_upper_bound():
    """The cross-check's explicit step names the contacts when the run rested above the upper
    bound, pairs without a face interface first, with gap and force; otherwise nothing."""
    forces = SimpleNamespace(
        describe=lambda: "blocks 2-4 (no face interface, gap 0 mm, 141 N)",
    )
    res = SimpleNamespace(lambda_stable=0.45, contacts_at_rest=forces)
    lim = SimpleNamespace(values={"upper": 0.397})
    text = _resisting(res, lim)
    assert "above the upper bound 0.397" in text and "blocks 2-4 (no face interface" in text
    assert _resisting(SimpleNamespace(lambda_stable=0.33, contacts_at_rest=forces), lim) == ""
    assert _resisting(res, None) == ""
    assert _resisting(res, SimpleNamespace(values={"upper": math.inf})) == ""
