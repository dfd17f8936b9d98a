"""Narwhal validation harness: rungs as data, checks with tolerances, HTML reports."""
