"""The guarded pool: a task past its timeout is killed and its worker replaced; errors and dead workers are
reported; what a task emitted before it ended is kept; a task's time starts when its worker begins it."""

import os
import time

from neuromuscle.bench.guarded_pool import guarded_map

# a spawned worker imports this module before it begins a task: the start-up test makes that import slow
time.sleep(float(os.environ.get("NEUROMUSCLE_TEST_SLOW_IMPORT_S", "0")))


def _task(item, emit):
    print(f"worker prints {item}")
    emit(("started", item))
    if item == "hang":
        time.sleep(600)
    elif item == "raise":
        raise ValueError("bad item")
    elif item == "die":
        os._exit(3)
    emit(("finished", item))


def test_hung_raising_and_dying_tasks_are_reported_and_the_rest_run(capfd):
    items = ["ok1", "hang", "raise", "die", "ok2", "ok3"]
    start = time.monotonic()
    # a task's clock starts when its worker begins it, so a slow worker start-up does not time out "ok1"
    outcomes = {o.index: o for o in guarded_map(_task, items, workers=2, timeout_s=5.0)}
    assert time.monotonic() - start < 300  # the hung task was killed, not waited for (it sleeps 600 s)
    assert sorted(outcomes) == list(range(len(items)))
    status = {items[i]: o.status for i, o in outcomes.items()}
    assert status == {"ok1": "done", "hang": "timeout", "raise": "error", "die": "died", "ok2": "done",
                      "ok3": "done"}
    assert outcomes[1].messages == [("started", "hang")] and outcomes[1].wall_s >= 5.0
    assert "ValueError: bad item" in outcomes[2].error
    assert "exit code 3" in outcomes[3].error
    assert outcomes[5].messages == [("started", "ok3"), ("finished", "ok3")]
    out, err = capfd.readouterr()
    assert "worker prints" not in out and "worker prints ok3" in err  # the parent's stdout stays its own


def _slow_start(item, emit):
    emit(("ran", item))


def test_a_worker_start_up_is_not_counted_against_the_task(monkeypatch):
    """The first task's worker imports its module before it begins; with a timeout shorter than that start-up,
    the task still runs (its clock starts when the worker begins it)."""
    monkeypatch.setenv("NEUROMUSCLE_TEST_SLOW_IMPORT_S", "2")
    outcomes = list(guarded_map(_slow_start, ["a"], workers=1, timeout_s=0.5))
    assert [o.status for o in outcomes] == ["done"] and outcomes[0].messages == [("ran", "a")]
