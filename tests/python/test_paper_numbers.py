"""The numbers docs/paper publishes (Phi_T of Eq. 14 with and without the
exclusion rule, Z, E and c_v at given Phi, the exclusion readings' |dZ|)
come from the committed per-seed series (docs/paper/seeds, docs/paper/mesh:
one row per output of each 100-disk run) through ``./softpack plot
--seeds``: regenerated here, every table must be the committed one, byte
for byte. A change in the fits, the averaging or the exclusion rules that
moves a published number fails until the docs are regenerated with it."""

import pytest

from softpack.paths import ROOT
from softpack.plots import paper

TABLES = ("summary.md", "exclusion_table.md", "fig8_fit.txt")


@pytest.mark.parametrize("folder", ["docs/paper", "docs/paper/mesh"])
def test_the_published_tables_are_regenerated_exactly(folder, tmp_path):
    pytest.importorskip("matplotlib")
    docs = ROOT / folder
    seeds = docs / "seeds" if (docs / "seeds").is_dir() else docs
    assert paper.main(["--seeds", str(seeds), "--out", str(tmp_path)]) == 0
    for name in TABLES:
        assert (tmp_path / name).read_text() == (docs / name).read_text(), \
            f"{folder}/{name} differs from what its seeds give"
