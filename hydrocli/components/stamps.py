"""What a component's ``equations(c)`` may call on ``c``: the stamp interface.

Components are written against this protocol; :class:`hydrocli.model.context.Context`
implements it. Keeping the interface here (components' side) lets the model depend on the
components, never the other way round. The meaning of each call is in docs/ARCHITECTURE.md.
"""
from __future__ import annotations

from typing import Any, Protocol

from ..model.expr import Expr


class Stamps(Protocol):
    name: str          # the component instance's name
    p: Any             # ``c.p.Kv`` is ``c.param("Kv")``
    time: Expr         # simulation time t [s]

    def param(self, pname: str) -> Any: ...                        # symbol (list for vector params)
    def value(self, pname: str) -> Any: ...                        # build-time number (structure only)
    def active(self, pname: str) -> bool: ...                      # non-zero or free: include the effect
    def connected(self, port: str) -> bool: ...
    def node(self, port: str) -> Any: ...
    def across(self, port: str) -> Expr: ...                       # p [Pa], v [m/s], w [rad/s], signal
    def position(self, port: str) -> Expr: ...                     # x [m] or angle [rad]
    def through(self, port: str, value) -> None: ...               # flow/force/torque taken from the node
    def capacitance(self, port: str, value) -> None: ...           # V/β, mass or inertia on the node
    def impose(self, port: str, across, position=None) -> None: ...  # the component drives the node
    def node_through(self, port: str) -> Expr: ...                 # what the others take from the node
    def signal(self, port: str) -> Expr: ...
    def drive(self, port: str, value) -> None: ...                 # set a signal output
    def state(self, sname: str) -> Expr: ...
    def der(self, sname: str, value) -> None: ...
    def at_rest(self, sname: str, value) -> None: ...              # the state equals value at rest (a sensor)
    def let(self, vname: str, value, unit: str = "") -> Expr: ...  # named variable comp.NAME
    def guard(self, condition: Expr, message: str) -> None: ...    # stop the solver when it holds
    def warn(self, message: str) -> None: ...
