"""Helpers for two-port (branch) elements of the linear graph: an element between nodes
a and b carries one through variable, taken from a and given to b."""
from __future__ import annotations


def across_drop(c, a: str = "a", b: str = "b"):
    """Across difference a − b (pressure drop, relative velocity, relative speed)."""
    return c.across(a) - c.across(b)


def branch(c, name: str, value, a: str = "a", b: str = "b"):
    """Name the element's through variable and stamp it: taken from node a, given to b."""
    q = c.let(name, value)
    c.through(a, q)
    c.through(b, -q)
    return q


def signal_or_param(c, port: str, param: str):
    """The signal at an optional input port when connected, else the parameter's value."""
    return c.signal(port) if c.connected(port) else c.param(param)
