"""Gymnasium's own MuJoCo v5 tests, run against gymfleet's ids (see conftest.py)."""
