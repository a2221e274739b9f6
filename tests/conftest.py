"""Fixtures shared by several test modules."""

from __future__ import annotations

import multiprocessing
import os
import sys

import pytest


@pytest.fixture
def forking(monkeypatch):
    """Let this process fork as a command's process would. A test that ran before may have left
    a thread here (Dask's offload thread, after the distributed study's tests), and
    :func:`railexu.runtime.warm_process.can_fork` refuses to fork a process with threads; that
    thread is idle and the children these tests fork run only railexu's code."""
    import threading

    if (
        "fork" not in multiprocessing.get_all_start_methods()
        or (os.cpu_count() or 1) < 2
        or sys.platform != "linux"
    ):
        pytest.skip("no fork here")
    monkeypatch.setattr(threading, "active_count", lambda: 1)
