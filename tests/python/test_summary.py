"""The end-of-run summary's choice of stress estimate (analysis/summary.py)."""

import math

from softpack.analysis.summary import stress_source


def _stress(contact, fe, wall=5000.0):
    return {"contact_P": [contact], "fe_P": [fe], "wall_P": [wall]}


def test_the_contacts_when_they_are_known_else_the_particles_else_the_walls():
    assert stress_source(_stress(4000.0, 3900.0), 0, rigid=False)[0] == \
        "contact"
    assert stress_source(_stress(4000.0, 3900.0), 0, rigid=True)[0] == \
        "contact"
    # Without fields the contact estimate is NaN: the particles' own
    # stress, which misses rigid bodies, so with them the walls'.
    source, why = stress_source(_stress(math.nan, 3900.0), 0, rigid=False)
    assert source == "fe" and "output.fields" in why
    source, why = stress_source(_stress(math.nan, 3900.0), 0, rigid=True)
    assert source == "wall" and "output.fields" in why
    assert stress_source(_stress(math.nan, math.nan), 0, False)[0] == "wall"
