"""The contract layer (cshape/_checks.py): one rule, one message per bad argument, in every
function; old mode-name spellings accepted with a DeprecationWarning."""

from __future__ import annotations

import numpy as np
import pytest

import cshape
from cshape.batch import DescriptorTable
from cshape.compare import DESCRIPTOR_KINDS, descriptor_matrix, descriptor_size
from cshape.index import DescriptorIndex

LAM = 4 * np.pi * np.arange(12.0) + np.sin(np.arange(12.0))  # a normalised Shape-DNA


# ------------------------------------------------------------------ mode names
OLD_KINDS = {"shape_dna": "shape-dna", "cshape_complex": "cshape-complex",
             "truncated_log": "truncated-log"}


def _table():
    rng = np.random.default_rng(0)
    lam = np.c_[np.zeros(4), np.cumsum(rng.uniform(0.5, 2.0, (4, 29)), axis=1)]
    return DescriptorTable(["a", "b", "c", "d"], lam, rng.uniform(1, 2, 4), ["x", "x", "y", "y"],
                           M=3)


def test_mode_names_are_hyphenated_lower_case():
    for names in (DESCRIPTOR_KINDS, cshape.descriptors.TRANSFORMS,
                  cshape.descriptors.NORMALIZATIONS, cshape.fem.BOUNDARY_CONDITIONS,
                  cshape.fem.MASS_TYPES):
        assert all(n == n.lower() and "_" not in n and " " not in n for n in names), names


@pytest.mark.parametrize("old, new", sorted(OLD_KINDS.items()))
def test_old_kind_spellings_warn_and_give_the_same_descriptors(old, new):
    t = _table()
    with pytest.warns(DeprecationWarning, match=f"kind='{old}' is deprecated; write kind='{new}'"):
        X_old = descriptor_matrix(t.lam, t.areas, old, M=3, N=20)
    np.testing.assert_array_equal(X_old, descriptor_matrix(t.lam, t.areas, new, M=3, N=20))
    with pytest.warns(DeprecationWarning, match="is deprecated") as rec:
        np.testing.assert_array_equal(t.descriptors(old, N=20), t.descriptors(new, N=20))
        assert descriptor_size(old, M=3, N=20) == descriptor_size(new, M=3, N=20)
        index = DescriptorIndex.from_table(t, old, N=20)
    assert index.recipe_["kind"] == new  # stored in the current spelling
    assert all(r.filename == __file__ for r in rec)  # the warning points at the caller


def test_old_spelling_is_accepted_only_where_its_new_name_is():
    with pytest.raises(ValueError, match=r"transform must be one of \{'weyl', 'log-weyl', "
                                         r"'log-weyl-dct'\}, got 'shape_dna'"):
        cshape.compact_shape_dna(LAM, M=1, N=5, transform="shape_dna")


def test_cli_query_accepts_the_old_kind_with_a_warning(tmp_path, capsys):
    from cshape.cli.main import main

    path = tmp_path / "t.npz"
    _table().save(path)
    assert main(["query", str(path), "a", "-k", "2", "--kind", "shape_dna", "-N", "20"]) == 0
    out, err = capsys.readouterr()
    assert "--kind shape_dna is deprecated; write --kind shape-dna" in err
    assert "by Shape-DNA N=20" in out
