"""How make test's parallel run shares the tests among its workers (tests/conftest.py)."""

from __future__ import annotations

from conftest import SHARED_SERVER, SPREAD_MODULES, _scope


def test_a_module_runs_on_one_worker_unless_its_tests_are_spread():
    assert _scope("tests/test_fem.py::test_a") == _scope("tests/test_fem.py::test_b[x]") \
        == "tests/test_fem.py"
    one, two = ("tests/test_assignments.py::test_nbgrader_course_full_cycle[week1]",
                "tests/test_assignments.py::test_nbgrader_course_full_cycle[week2]")
    assert _scope(one) == one and _scope(two) == two
    # the browser tests that share a JupyterLab server share a worker
    a, b = (f"tests/test_browser.py::{name}" for name in sorted(SHARED_SERVER))
    alone = "tests/test_browser.py::test_ensure_browser_is_idempotent"
    assert _scope(a) == _scope(b) != _scope(alone)
    assert {"test_assignments", "test_notebooks", "test_browser"} <= SPREAD_MODULES


def test_the_shared_server_tests_exist():
    import test_browser

    assert all(hasattr(test_browser, name) for name in SHARED_SERVER)
