"""chainid.infra.parallel.run_cases: same results, in case order, on every back end; errors propagate cleanly."""
import multiprocessing
import sys

import pytest

from chainid.infra.parallel import dask_available, run_cases


def _square_plus(case):
    """A top-level (picklable) function of one case: (a, b) -> a**2 + b."""
    a, b = case
    return a * a + b


def _fail_on_three(case):
    if case == 3:
        raise RuntimeError("case 3 failed")
    return case


CASES = [(i, 10 * i) for i in range(7)]
EXPECTED = [i * i + 10 * i for i in range(7)]  # by hand: 0, 11, 24, 39, 56, 75, 96


def test_serial_in_order():
    assert run_cases(_square_plus, CASES, scheduler="serial", progress=False) == EXPECTED
    assert EXPECTED[:4] == [0, 11, 24, 39]


def test_processes_same_as_serial():
    assert run_cases(_square_plus, CASES, scheduler="processes", n_workers=2, progress=False) == EXPECTED
    assert multiprocessing.active_children() == []


@pytest.mark.skipif(not dask_available(), reason="dask.distributed not installed")
def test_local_cluster_same_as_serial():
    assert run_cases(_square_plus, CASES, scheduler="local", n_workers=2, progress=False) == EXPECTED
    assert multiprocessing.active_children() == []


@pytest.mark.skipif(not dask_available(), reason="dask.distributed not installed")
def test_existing_cluster_by_address_results_and_errors():
    """An existing scheduler (here an in-process one: fast) is used by address and left running."""
    from distributed import LocalCluster
    with LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None) as cluster:
        addr = cluster.scheduler_address
        assert run_cases(_square_plus, CASES, scheduler=addr, progress=False) == EXPECTED
        with pytest.raises(RuntimeError, match="case 3 failed"):
            run_cases(_fail_on_three, range(6), scheduler=addr, progress=False)
        assert run_cases(_square_plus, CASES[:2], scheduler=addr, progress=False) == EXPECTED[:2]  # still up


def test_empty_cases():
    assert run_cases(_square_plus, [], scheduler="processes") == []


def test_progress_bar_on_stderr(capsys, monkeypatch):
    run_cases(_square_plus, CASES, scheduler="serial", progress=True, desc="sweep")
    assert capsys.readouterr().err == ""  # stderr is not a terminal (issue 19): no bar in pipes and logs
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True, raising=False)
    run_cases(_square_plus, CASES, scheduler="serial", progress=True, desc="sweep")
    err = capsys.readouterr().err
    assert "sweep" in err and "7/7" in err
    run_cases(_square_plus, CASES, scheduler="serial", progress=False, desc="sweep")
    assert capsys.readouterr().err == ""


@pytest.mark.parametrize("scheduler", ["serial", "processes"])
def test_case_exception_propagates_and_workers_stop(scheduler):
    with pytest.raises(RuntimeError, match="case 3 failed"):
        run_cases(_fail_on_three, range(6), scheduler=scheduler, n_workers=2, progress=False)
    assert multiprocessing.active_children() == []


@pytest.mark.parametrize("kw, field", [({"n_workers": 0}, "n_workers"), ({"scheduler": ""}, "scheduler"),
                                      ({"n_workers": 1.5}, "n_workers")])
def test_bad_arguments(kw, field):
    with pytest.raises(ValueError, match=field):
        run_cases(_square_plus, CASES, progress=False, **kw)
