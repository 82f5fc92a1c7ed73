"""``hanging_payload``: a payload on a rope from an arm's tip, the exact pendulum on a moving
support, with its bob driven by the arm's angular acceleration (``Context.rate``).

References, each independent of the element: the double pendulum's Lagrangian integrated here
with SciPy (the family truth's ``RopePendulum`` form) under a driving torque that swings the
rope up to 0.75 rad; the energy without drive or damping; and, hanging and slow, the tangential
spring–mass (m_p·r² on a shaft of m_p·g·r²/L) built from an inertia and a shaft."""
from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from hydrocli.errors import HydroError
from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist_text
from hydrocli.solve.simulate import InputTable, SolverOptions, simulate

G = 9.81
MP, R, L, CR = 3.0, 0.6, 0.5, 0.05      # kg, m, m, N·m·s/rad: the payload, the arm's radius, the rope
J, W_ARM = 0.8, 60.0                    # the arm's inertia and weight moment
W = W_ARM + MP * G * R                  # the gravity load carries the bob's weight moment too
T = np.linspace(0.0, 2.0, 2001)

ARM = """
name: arm_payload
inputs: {{u: {{unit: "N*m"}}}}
components:
  arm: {{type: inertia, ports: {{r: n}}, J: {J}}}
  weight: {{type: gravity_load, ports: {{r: n}}, W: {W}, theta0: {th0}}}
  drive: {{type: torque_source, ports: {{a: n, tau: u}}}}
  bob: {{type: hanging_payload, ports: {{r: n}}, J_p: {jp}, L: {L}, r: {r}, c: {c}, theta0: {th0}}}
outputs: {{th: n.theta, w: n.w, phi: bob.phi, phid: bob.phid}}
initial: {{n.theta: {x0}, n.w: {w0}}}
"""


def _run(text: str, torque=None) -> dict:
    model = build_model(load_netlist_text(text))
    u = np.zeros_like(T) if torque is None else torque
    res = simulate(model, InputTable(T, u[:, None]), T, opts=SolverOptions(rtol=1e-10, atol_factor=1e-3))
    return {o: res.Y[:, i] for i, o in enumerate(model.output_names)}


def _arm(c=CR, x0=0.6, w0=0.0, th0=0.0, torque=None):
    return _run(ARM.format(J=J, W=W, jp=MP * R * R, L=L, r=R, c=c, x0=x0, w0=w0, th0=th0), torque)


def test_it_is_the_double_pendulum_under_a_driving_torque():
    torque = 15.0 * np.sign(np.sin(2 * np.pi * 0.7 * T))

    def exact(t, y):
        th, thd, ph, phd = y
        c, s = np.cos(th - ph), np.sin(th - ph)
        a11, a12, a22 = J + MP * R * R, MP * R * L * c, MP * L * L
        b1 = np.interp(t, T, torque) - W * np.sin(th) - MP * R * L * s * phd ** 2
        b2 = MP * R * L * s * thd ** 2 - MP * G * L * np.sin(ph) - CR * phd
        det = a11 * a22 - a12 * a12
        return [thd, (b1 * a22 - a12 * b2) / det, phd, (a11 * b2 - a12 * b1) / det]
    ref = solve_ivp(exact, (0.0, T[-1]), [0.6, 0.0, 0.0, 0.0], t_eval=T, rtol=1e-11, atol=1e-12,
                    method="DOP853", max_step=1e-3)
    y = _arm(torque=torque)
    assert np.max(np.abs(ref.y[2])) > 0.7 and np.ptp(ref.y[0]) > 1.0     # a large swing on a sweeping arm
    assert np.max(np.abs(y["th"] - ref.y[0])) <= 1e-7
    assert np.max(np.abs(y["phi"] - ref.y[2])) <= 1e-7


def test_energy_is_conserved_without_drive_or_damping():
    th0 = 0.3
    y = _arm(c=0.0, x0=0.2, w0=4.0, th0=th0)
    a, w, phi, phid = y["th"] + th0, y["w"], y["phi"], y["phid"]
    energy = (0.5 * J * w ** 2 + 0.5 * MP * (R ** 2 * w ** 2 + L ** 2 * phid ** 2 + 2 * R * L * w * phid * np.cos(a - phi))
              + W_ARM * (1.0 - np.cos(a)) + MP * G * (R * (1.0 - np.cos(a)) + L * (1.0 - np.cos(phi))))
    assert np.max(np.abs(phi)) > 0.2
    assert np.max(np.abs(energy - energy[0])) <= 1e-7 * energy[0]


def test_hanging_and_slow_it_is_the_tangential_spring_mass():
    """Small swings about the hanging pose: the bob is m_p·r² on a torsion spring m_p·g·r²/L
    (its weight moment hangs on the tip: the arm's gravity load carries it), to the second order."""
    y = _arm(c=0.0, x0=0.001)
    tip = _run(f"""
name: arm_tip
inputs: {{u: {{unit: "N*m"}}}}
components:
  arm: {{type: inertia, ports: {{r: n}}, J: {J}}}
  weight: {{type: gravity_load, ports: {{r: n}}, W: {W}}}
  pj: {{type: inertia, ports: {{r: s}}, J: {MP * R * R}}}
  rope: {{type: shaft, ports: {{a: n, b: s}}, k: {MP * G * R * R / L}}}
outputs: {{w: n.w}}
initial: {{n.theta: 0.001, s.theta: 0.001}}
""")
    assert np.max(np.abs(y["w"] - tip["w"])) <= 1e-3 * np.max(np.abs(tip["w"]))


def test_on_a_node_a_source_drives_it_is_an_error():
    text = """
name: imposed
inputs: {u: {unit: "1"}}
components:
  load: {type: inertia, ports: {r: out}}
  gear: {type: gearbox, ports: {in: n, out: out}}
  bob: {type: hanging_payload, ports: {r: n}}
"""
    with pytest.raises(HydroError, match="imposed by .gear"):
        build_model(load_netlist_text(text))
