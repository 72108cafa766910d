"""Shared helpers for the test suite."""

from __future__ import annotations

import math

import pytest


def rel_err(actual: float, expected: float) -> float:
    """Relative error |actual - expected| / |expected| (absolute when expected is 0)."""
    return abs(actual - expected) / (abs(expected) if expected != 0 else 1.0)


@pytest.fixture
def close():
    def check(actual: float, expected: float, rel: float) -> None:
        assert math.isfinite(actual), actual
        assert rel_err(actual, expected) <= rel, (actual, expected, rel_err(actual, expected))

    return check


@pytest.fixture(autouse=True, scope="session")
def fea_cache_of_this_session(tmp_path_factory):
    """The commands' FEA disk cache (LINKSTRESS_CACHE) in a folder of this test session, never the user's."""
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("LINKSTRESS_CACHE", str(tmp_path_factory.mktemp("fea-cache")))
        yield
