"""What the cluster runs report, read without a cluster: the scheduler's events of removed workers
become retried tasks, and regress's JSON holds every check (runs on installs without Dask)."""

from __future__ import annotations

import json

import numpy as np

from linkstress.commands.regress import regress_json, retried_lines
from linkstress.executors import Retry, retries
from linkstress.validation.regression import CaseResult, Check

LABELS = {"linkstress-0-ab12": "six_bar", "linkstress-1-ab12": "bell_crank", "linkstress-2-ab12": "arc_coupler"}


def removed(worker: str, processing=(), computed=(), expected=False) -> tuple[float, dict]:
    """An event as distributed's Scheduler.remove_worker logs it to the "all" topic."""
    return (1.0, {"action": "remove-worker", "processing-tasks": set(processing), "lost-computed-tasks": set(computed),
                  "lost-scattered-tasks": set(), "stimulus_id": "handle-worker-cleanup-1", "expected": expected,
                  "worker": worker})


def test_a_task_running_or_held_on_a_removed_worker_is_retried_once_with_that_worker_named():
    events = [
        (0.5, {"action": "add-worker", "worker": "tcp://10.0.0.7:40331"}),
        removed("tcp://10.0.0.7:40331", processing=["linkstress-1-ab12", "someone-else"], computed=["linkstress-2-ab12"]),
        removed("tcp://10.0.0.8:40400", processing=["linkstress-1-ab12"], expected=True),
    ]
    assert retries(events, LABELS) == [
        Retry("bell_crank", "worker tcp://10.0.0.7:40331 lost"), Retry("arc_coupler", "worker tcp://10.0.0.7:40331 lost"),
    ]


def test_a_worker_retired_on_purpose_is_said_to_have_left():
    events = [removed("tcp://10.0.0.8:40400", processing=["linkstress-0-ab12"], expected=True)]
    assert retries(events, LABELS) == [Retry("six_bar", "worker tcp://10.0.0.8:40400 left")]


def test_no_removed_worker_no_retry_and_no_report_line():
    assert retries([(0.5, {"action": "add-worker", "worker": "tcp://10.0.0.7:40331"})], LABELS) == []
    assert retried_lines([]) == ""


def test_regress_json_holds_every_check_and_a_missing_value_as_null():
    # a value the run no longer gives is infinitely far off (compare_validation): null in JSON
    result = CaseResult("six_bar", [Check("six_bar", "crank nominal_error_pct", np.inf, 1.7, "percent")])
    data = regress_json([result], "tcp://10.0.0.5:8786", [Retry("six_bar", "worker tcp://10.0.0.7:40331 lost")])
    assert json.loads(json.dumps(data, allow_nan=False)) == {
        "cases": [{"case": "six_bar", "passed": False, "error": "", "checks": [
            {"what": "crank nominal_error_pct", "worst": None, "allowed": 1.7, "passed": False, "detail": "percent"},
        ]}],
        "scheduler": "tcp://10.0.0.5:8786",
        "retried": [{"task": "six_bar", "reason": "worker tcp://10.0.0.7:40331 lost"}],
    }
