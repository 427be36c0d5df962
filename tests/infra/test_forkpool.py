"""``fork_map`` maps a function over items on forked workers that inherit the caller's state, in order, and in this
process when that is not possible or not worth it; a case's exception reaches the caller as it was."""
from __future__ import annotations

import os

import pytest

from chainid.infra.forkpool import can_fork, fork_map

STATE = {"offset": 0}


def _square_plus_state(x: int) -> tuple[int, int]:
    return x * x + STATE["offset"], os.getpid()


needs_two = pytest.mark.skipif(can_fork(2) == 0, reason="no fork start method here")


@needs_two
def test_results_in_order_from_workers_that_see_the_state_set_before_the_fork():
    STATE["offset"] = 1000  # set in this process only, after import: a spawned worker would not see it
    try:
        out = fork_map(_square_plus_state, range(12), workers=2)
    finally:
        STATE["offset"] = 0
    assert [v for v, _ in out] == [x * x + 1000 for x in range(12)]
    assert {pid for _, pid in out} - {os.getpid()}  # the work ran in other processes


def test_fewer_items_than_min_items_or_one_worker_run_here():
    assert [p for _, p in fork_map(_square_plus_state, range(3), workers=2, min_items=4)] == [os.getpid()] * 3
    assert [p for _, p in fork_map(_square_plus_state, range(3), workers=1)] == [os.getpid()] * 3
    assert can_fork(1) == 0


def _fails_on_three(x: int) -> int:
    if x == 3:
        raise ValueError("case 3: F_c = -1 N is out of range")
    return x


@needs_two
def test_a_case_error_reaches_the_caller_with_its_message():
    with pytest.raises(ValueError, match="case 3: F_c = -1 N"):
        fork_map(_fails_on_three, range(6), workers=2)


PARENT = {"pid": 0}


def _dies_in_a_worker_on_two(x: int) -> int:
    import signal

    if x == 2 and os.getpid() != PARENT["pid"]:
        os.kill(os.getpid(), signal.SIGKILL)  # the OOM killer's way
    return 10 * x


@needs_two
def test_a_worker_that_dies_does_not_hang_the_map_its_items_run_here_with_a_warning():
    PARENT["pid"] = os.getpid()
    with pytest.warns(RuntimeWarning, match="a worker process died"):
        out = fork_map(_dies_in_a_worker_on_two, range(6), workers=2)
    assert out == [0, 10, 20, 30, 40, 50]


def _warns(x: int) -> int:
    import warnings

    warnings.warn(f"item {x}: x = {x} mm is implausible", UserWarning)
    return x


@needs_two
def test_the_warnings_of_the_items_reach_this_process_in_item_order():
    import warnings

    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        assert fork_map(_warns, range(4), workers=2) == [0, 1, 2, 3]
    assert [str(w.message) for w in seen] == [f"item {x}: x = {x} mm is implausible" for x in range(4)]


def _forks_here(_: int) -> int:
    return can_fork(2)


@needs_two
def test_a_worker_does_not_fork_workers_of_its_own():
    assert fork_map(_forks_here, range(2), workers=2) == [0, 0]
