"""Multibody mechanics: serial chains of rigid bodies on revolute joints (seed 002 eq. 1),
finite-segment flexible members (seed 000 §3.2–3.3), and joint elements.

Modules: ``vec`` (3-vector algebra on expressions), ``recursive`` (RNEA bias forces,
composite-rigid-body mass matrix, unrolled LDLᵀ solve), ``chain`` (the ``serial_chain``
component), ``flexible`` (``flexible_member``), ``joint_elements`` (angle sensor
on a joint port). The mechanism's degree-of-freedom count (seed 000 eq. 1) is a netlist
analysis: :mod:`hydrocli.graph.mobility`.
"""
