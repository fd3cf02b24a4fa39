"""The guarded pool: a task past its timeout is killed and its worker replaced; errors and dead workers are
reported; what a task emitted before it ended is kept."""

import os
import time

from neuromuscle.bench.guarded_pool import guarded_map


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
    # the timeout covers a worker's start-up too: generous, so a loaded machine does not time out "ok1"
    outcomes = {o.index: o for o in guarded_map(_task, items, workers=2, timeout_s=30.0)}
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
