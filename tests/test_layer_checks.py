"""The shared checks that the layers use (cshape/_checks.py), and the layers' arguments that
go through them: a wrong type is a TypeError, a bad value a ValueError, and the message names
the argument and the fix, as in the core (tests/test_validation.py)."""

from __future__ import annotations

import numpy as np
import pytest

from cshape._checks import check_entries, check_flag_or_choice, check_points, check_real

pytest.importorskip("matplotlib")

Y12 = np.random.default_rng(0).normal(size=(12, 2))


# ====================================================================== the checks themselves
CHECKS = [
    pytest.param(check_real, dict(name="factor", value=1.0, above=1), ValueError,
                 r"^factor must be a finite number > 1, got 1\.0$", id="real-above-equal"),
    pytest.param(check_real, dict(name="factor", value=0, above=1), ValueError,
                 r"^factor must be a finite number > 1, got 0\.0$", id="real-above-below"),
    pytest.param(check_real, dict(name="factor", value=np.inf, above=1), ValueError,
                 r"^factor must be a finite number > 1, got inf$", id="real-above-inf"),
    pytest.param(check_real, dict(name="factor", value="5", above=1), TypeError,
                 r"^factor must be a real number, got str '5'$", id="real-above-str"),
    pytest.param(check_points, dict(Y=np.zeros((3, 3)), d=2, fix="use mds_embedding(D)"),
                 ValueError, r"^Y must have shape \(p, 2\), got \(3, 3\); use mds_embedding\(D\)$",
                 id="points-columns"),
    pytest.param(check_points, dict(Y=np.zeros(3)), ValueError,
                 r"^Y must have shape \(p, d\), got \(3,\)$", id="points-1d"),
    pytest.param(check_points, dict(Y=np.zeros((0, 2)), min_points=1), ValueError,
                 r"^Y has 0 points; pass at least 1$", id="points-empty"),
    pytest.param(check_points, dict(Y=[[0.0, 1.0], [np.nan, 0.0]]), ValueError,
                 r"^Y contains NaN or infinite values \(first at row 1, column 0\)",
                 id="points-nan"),
    pytest.param(check_points, dict(Y="ab", name="P"), TypeError,
                 r"^P must be an array of real coordinates, shape \(p, d\), got str 'ab'$",
                 id="points-str"),
    pytest.param(check_points, dict(Y=[[1.0, 2.0], [3.0]]), TypeError,
                 r"^Y must be an array of real coordinates", id="points-ragged"),
    pytest.param(check_points, dict(Y=np.ones((2, 2), dtype=complex)), TypeError,
                 r"^Y must be an array of real coordinates", id="points-complex"),
    pytest.param(check_entries, dict(name="names", value=["a"], p=3), ValueError,
                 r"^names has 1 entries but Y has 3 points; pass one entry for each, in order$",
                 id="entries-length"),
    pytest.param(check_entries, dict(name="labels", value=[1, 2], p=3, of="D", unit="rows"),
                 ValueError, r"^labels has 2 entries but D has 3 rows", id="entries-rows"),
    pytest.param(check_entries, dict(name="names", value="abc", p=3), TypeError,
                 r"^names must be a sequence with one entry for each of the points of Y, got "
                 r"str 'abc'$", id="entries-str"),
    pytest.param(check_entries, dict(name="names", value=3, p=3), TypeError,
                 r"^names must be a sequence .*, got int 3$", id="entries-int"),
    pytest.param(check_entries, dict(name="names", value=np.zeros((3, 1)), p=3), TypeError,
                 r"^names must be a sequence", id="entries-2d"),
    pytest.param(check_flag_or_choice, dict(name="legend", value=1, allowed=("outside",)),
                 TypeError, r"^legend must be True, False or one of \{'outside'\}, got int 1$",
                 id="flag-int"),
    pytest.param(check_flag_or_choice, dict(name="legend", value=None, allowed=("outside",)),
                 TypeError, r"^legend must be True, False or one of \{'outside'\}, got NoneType$",
                 id="flag-None"),
    pytest.param(check_flag_or_choice, dict(name="legend", value="inside",
                                            allowed=("outside",)),
                 ValueError, r"^legend must be True, False or one of \{'outside'\}, got 'inside'$",
                 id="flag-value"),
]


@pytest.mark.parametrize("call, kwargs, exc, match", CHECKS)
def test_checks(call, kwargs, exc, match):
    with pytest.raises(exc, match=match):
        call(**kwargs)


def test_checks_return_what_they_accept():
    assert check_real("factor", np.float32(1.5), above=1) == 1.5
    assert check_real("x", 0.0, above=-1) == 0.0
    Y = check_points([[0, 1], [2, 3]], d=2)
    assert Y.dtype == np.float64 and Y.shape == (2, 2)
    assert check_points(np.zeros((0, 3))).shape == (0, 3)  # no points, when allowed
    assert check_entries("names", ("a", "b"), 2) == ["a", "b"]
    assert check_entries("mask", np.array([True, False]), 2) == [True, False]
    assert check_flag_or_choice("legend", np.bool_(False), ("outside",)) is False
    assert check_flag_or_choice("legend", True, ("outside",)) is True
    assert check_flag_or_choice("legend", "Outside", ("outside",)) == "outside"


# ====================================================================== the layers
def _plots():
    from cshape.plots import collection

    return collection


def _compare():
    from cshape import compare

    return compare


def _explore():
    from cshape.plots import overview

    return overview


PLOTS = [
    pytest.param(lambda: _plots().plot_mds(np.zeros((3, 3))), ValueError,
                 r"Y must have shape \(p, 2\), got \(3, 3\); use mds_embedding\(D\)", id="mds-Y"),
    pytest.param(lambda: _plots().plot_mds(np.zeros((0, 2))), ValueError,
                 r"Y has 0 points; pass at least 1", id="mds-empty"),
    pytest.param(lambda: _plots().plot_mds(np.full((3, 2), np.nan)), ValueError,
                 r"Y contains NaN or infinite values", id="mds-nan"),
    pytest.param(lambda: _plots().plot_mds(Y12, names=["a"]), ValueError,
                 r"names has 1 entries but Y has 12 points", id="mds-names"),
    pytest.param(lambda: _plots().plot_mds(Y12, labels=["a"] * 11), ValueError,
                 r"labels has 11 entries but Y has 12 points", id="mds-labels"),
    pytest.param(lambda: _plots().plot_mds(Y12, labels="abcdefghijkl"), TypeError,
                 r"labels must be a sequence with one entry for each of the points of Y",
                 id="mds-labels-str"),
    pytest.param(lambda: _plots().plot_mds(Y12, legend="inside"), ValueError,
                 r"legend must be True, False or one of \{'outside'\}, got 'inside'",
                 id="mds-legend"),
    pytest.param(lambda: _plots().plot_mds(Y12, legend=1), TypeError,
                 r"legend must be True, False or one of \{'outside'\}, got int 1",
                 id="mds-legend-int"),
    pytest.param(lambda: _plots().plot_mds(Y12, max_names=2.5), TypeError,
                 r"max_names must be an integer, got float 2\.5", id="mds-max-names"),
    pytest.param(lambda: _plots().plot_mds(Y12, outliers="yes"), ValueError,
                 r"outliers must be one of \{'auto'\}, got 'yes'", id="mds-outliers"),
    pytest.param(lambda: _plots().plot_mds(Y12, outliers=[True]), ValueError,
                 r"outliers has 1 entries but Y has 12 points", id="mds-outliers-mask"),
    pytest.param(lambda: _compare().mds_outliers(Y12, factor=0.5), ValueError,
                 r"factor must be a finite number > 1, got 0\.5", id="outliers-factor"),
    pytest.param(lambda: _compare().mds_outliers(np.zeros(4)), ValueError,
                 r"Y must have shape \(p, d\), got \(4,\)", id="outliers-Y"),
    pytest.param(lambda: _plots().mds_layout(Y12, margin=-0.1), ValueError,
                 r"margin must be a finite number >= 0, got -0\.1", id="layout-margin"),
    pytest.param(lambda: _compare().median_distances(Y12, reference=0), ValueError,
                 r"reference must be an integer >= 1, got 0", id="median-reference"),
    pytest.param(lambda: _compare().nearest_neighbours(np.zeros((3, 3)), k=1.0), TypeError,
                 r"k must be an integer, got float 1\.0", id="neighbours-k-float"),
    pytest.param(lambda: _compare().nearest_neighbours(np.zeros((3, 3)), k=0), ValueError,
                 r"k must be an integer >= 1, got 0", id="neighbours-k-0"),
    pytest.param(lambda: _plots().plot_distance_matrix(np.zeros((3, 3)), names=["a"]),
                 ValueError, r"names has 1 entries but D has 3 rows", id="matrix-names"),
    pytest.param(lambda: _plots().plot_distance_matrix(np.zeros((3, 3)), labels="abc"),
                 TypeError, r"labels must be a sequence with one entry for each of the rows of D",
                 id="matrix-labels-str"),
    pytest.param(lambda: _plots().plot_distance_matrix(np.zeros((3, 3)), scale=1), TypeError,
                 r"scale must be True or False, got int 1", id="matrix-scale"),
    pytest.param(lambda: _plots().plot_distance_matrix(np.zeros((3, 3)), colorbar="yes"),
                 TypeError, r"colorbar must be True or False, got str 'yes'",
                 id="matrix-colorbar"),
    pytest.param(lambda: _plots().plot_distance_matrix(np.zeros((3, 3)), vmax=0), ValueError,
                 r"vmax must be a positive finite number, got 0\.0", id="matrix-vmax"),
    pytest.param(lambda: _explore().interactive_mds(np.zeros((3, 3)), list("abc")), ValueError,
                 r"Y must have shape \(p, 2\), got \(3, 3\); use mds_embedding\(D\)",
                 id="interactive-Y"),
    pytest.param(lambda: _explore().interactive_mds(Y12, list("ab")), ValueError,
                 r"names has 2 entries but Y has 12 points", id="interactive-names"),
]


@pytest.mark.parametrize("call, exc, match", PLOTS)
def test_plots(call, exc, match):
    with pytest.raises(exc, match=match):
        call()


def test_plot_mds_takes_numpy_values_of_its_options():
    fig = _plots().plot_mds(Y12, labels=np.arange(12) % 3, legend=np.bool_(False),
                            max_names=np.int64(5))
    assert fig.axes[0].get_legend() is None


def test_data_numbers_go_through_the_shared_checks(tmp_path):
    from cshape import data
    from cshape.data import creatures, suite

    with pytest.raises(TypeError, match=r"variation must be a real number, got str '1'"):
        creatures.creature_capsules("human", 0, variation="1")
    with pytest.raises(ValueError, match=r"variation must be a finite number >= 0, got -1\.0"):
        suite.identity_bones("human", 0, variation=-1)
    with pytest.raises(TypeError, match=r"variation must be a real number, got bool True"):
        suite.identity_bones("human", 0, variation=True)
    with pytest.raises(TypeError, match=r"n_jobs must be an integer, got float 2\.0"):
        data.load_collection("articulated", cache_dir=tmp_path, n_jobs=2.0)
