"""How benchmarks/mutation_select.py maps coverage contexts to the tests a mutant gets: pytest-cov's per-test,
per-phase contexts, a fixture's set-up line mapped to every test of its file, and a coverage file that holds no
per-test data refused instead of read as "no test reaches this line"; and SIGTERM unwinding the run like Ctrl-C."""
from __future__ import annotations

import sys
from pathlib import Path

import pytest

BENCH = Path(__file__).resolve().parents[2] / "benchmarks"


@pytest.fixture(scope="module")
def ms():
    sys.path.insert(0, str(BENCH))
    try:
        import mutation_select
    finally:
        sys.path.remove(str(BENCH))
    return mutation_select


MODULES = {"test_a": "tests/x/test_a.py", "test_b": "tests/y/test_b.py"}
IN_FILE = {"tests/x/test_a.py": {"tests/x/test_a.py::test_one", "tests/x/test_a.py::test_two"},
           "tests/y/test_b.py": {"tests/y/test_b.py::test_three"}}


def test_a_pytest_cov_context_names_its_test_without_parameters_or_phase(ms):
    assert ms.test_id("tests/x/test_a.py::test_one[1-abc|d]|run", MODULES) == "tests/x/test_a.py::test_one"
    assert ms.test_id("tests/x/test_a.py::TestK::test_k|teardown", MODULES) == "tests/x/test_a.py::TestK::test_k"
    assert ms.test_id("test_a.test_one", MODULES) == "tests/x/test_a.py::test_one"  # coverage.py's own contexts
    assert ms.test_id("", MODULES) is None and ms.test_id("conftest.helper", MODULES) is None


def test_a_line_run_in_a_fixtures_set_up_reaches_every_test_of_that_file(ms):
    """A module-scoped fixture runs in the set-up of its file's first test and serves the others: a mutant in the
    code it runs must get them all (the report's figure tests read what the fixture drew)."""
    assert ms.line_tests(["tests/x/test_a.py::test_one|setup"], MODULES, IN_FILE) == IN_FILE["tests/x/test_a.py"]
    assert ms.line_tests(["tests/x/test_a.py::test_one|run", "tests/y/test_b.py::test_three|run", ""], MODULES,
                         IN_FILE) == {"tests/x/test_a.py::test_one", "tests/y/test_b.py::test_three"}


def test_a_coverage_file_without_per_test_contexts_is_not_a_map(ms, tmp_path):
    CoverageData = pytest.importorskip("coverage").CoverageData  # the mutation extra's, not the tests'

    assert ms._has_contexts(tmp_path / "missing") is False
    empty = CoverageData(basename=str(tmp_path / "empty"))
    empty.add_lines({str(tmp_path / "m.py"): [1, 2]})  # lines, but measured under no test's context
    empty.write()
    assert ms._has_contexts(tmp_path / "empty") is False
    full = CoverageData(basename=str(tmp_path / "full"))
    full.set_context("tests/x/test_a.py::test_one|run")
    full.add_lines({str(tmp_path / "m.py"): [1, 2]})
    full.write()
    assert ms._has_contexts(tmp_path / "full") is True


def test_junit_times_are_keyed_by_the_node_ids_pytest_cov_names(ms, tmp_path):
    """The JUnit file's class names are dotted paths (with a test class after the module): each test's time, its
    parameters summed, under the node id that :func:`test_id` gives for the same test."""
    (tmp_path / "j.xml").write_text(
        '<testsuites><testsuite name="pytest">'
        '<testcase classname="tests.report.test_steps" name="test_fig[a|b]" time="1.5"/>'
        '<testcase classname="tests.report.test_steps" name="test_fig[c]" time="0.5"/>'
        '<testcase classname="tests.x.test_a.TestK" name="test_k" time="2.0"/>'
        "</testsuite></testsuites>", encoding="utf-8")
    times = ms.test_times(tmp_path / "j.xml")
    assert times == {"tests/report/test_steps.py::test_fig": 2.0, "tests/x/test_a.py::TestK::test_k": 2.0}
    assert set(times) == {ms.test_id("tests/report/test_steps.py::test_fig[a|b]|run", {}),
                          ms.test_id("tests/x/test_a.py::TestK::test_k|setup", {})}


def test_sigterm_unwinds_the_run_as_an_exit_with_128_plus_the_signal(ms):
    import signal

    with pytest.raises(SystemExit) as e:
        ms.terminate(signal.SIGTERM, None)
    assert e.value.code == 128 + 15
