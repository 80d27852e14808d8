"""How make test's parallel run shares the tests among its workers (tests/conftest.py)."""

from __future__ import annotations

from conftest import LONG_MODULES, SPREAD_MODULES, _order, _scope


def test_a_module_runs_on_one_worker_unless_its_tests_are_spread():
    assert _scope("tests/test_fem.py::test_a") == _scope("tests/test_fem.py::test_b[x]") \
        == "tests/test_fem.py"
    one, two = ("tests/test_assignments.py::test_nbgrader_course_full_cycle",
                "tests/test_assignments.py::test_nbgrader_grades_a_small_assignment")
    assert _scope(one) == one and _scope(two) == two
    assert {"test_assignments", "test_notebooks", "test_browser"} <= SPREAD_MODULES


def test_the_long_tests_are_queued_first():
    spread = "tests/test_assignments.py::test_nbgrader_course_full_cycle"
    docs, fem, small = "tests/test_docs.py", "tests/test_fem.py", "tests/test_mesh.py"
    assert "test_docs" in LONG_MODULES
    queue = sorted([(small, 3), (fem, 40), (docs, 5), (spread, 1)], key=lambda u: _order(*u))
    assert [scope for scope, _ in queue] == [spread, docs, fem, small]
