"""Single-stage suspension / jet-pipe servovalve (seed 001 §3.1–3.2)."""
from __future__ import annotations

from ...model import expr as E
from ..base import Component, H, Param, Port, S, StateSpec, VariableSpec
from ..dynamics import first_order
from ..registry import register
from .hysteresis import ja_slope
from .valve import edge_opening
from .. import roles as RL
from ..roles import role


@register
class SuspensionServovalve(Component):
    """Suspension-type (jet-pipe-like) servovalve of the SARCOS joint (seed 001 §3.1–3.2).

    1. Coil current i_c = i/(1 + τ_c s) (gives di/dt for the hysteresis law).
    2. Jiles–Atherton hysteresis i → i_hys (eqs. 1–2): di_hys/dt = (di_hys/di)·di_c/dt, major
       and minor loops, saturating at i_s; Λ scales the slope (constant here; Carpenter's
       reversal-point-dependent Λ is not modelled).
    3. Valve tip: second order ẍ_v + 2ζω ẋ_v + ω² x_v = ω²·K_x·i_hys (eq. 3 with
       B/m_v = K_x ω², k_v/m_v = ω², b_v/m_v = 2ζω; eq. 16); x_v is a fraction of full tip travel.
    4. Receiver orifices (eq. 4): four edges P→A, P→B, A→T, B→T with the tip's underlap
       (open at null, as a jet pipe), q = Kv·ξ·dp/(dp² + dp_lam²)^¼; the port gains are
       asymmetric (Kv_A ≠ Kv_B, "K_v was made asymmetric", §5.1).
    5. Leakage through linear resistances: tip clearance P → T, G_leak·(p_P − p_T) (eqs. 5–6).
    """

    type = "servovalve_jet"
    roles = (role(RL.METERING_VALVE, {"supply": "P", "tank": "T", "work_a": "A", "work_b": "B", "command": "cmd"},
                  flow_gain=("Kv_A", "Kv_B"), edge_leak="G_leak"),)
    family = "hydraulic"
    description = "Suspension/jet-pipe servovalve: Jiles–Atherton hysteresis, 2nd-order tip, asymmetric ports"
    source = "seed 001 eqs. 1–6, 16–18"
    ports = (Port("P", H, "supply (P_sv)"), Port("T", H, "return (P_rl)"), Port("A", H, "control port 1"),
             Port("B", H, "control port 2"), Port("cmd", S, "input current i [A]", direction="in"))
    parameters = (
        Param("tau_c", "s", 1e-3, "coil current lag", positive=True, bounds=(1e-5, 1e-1)),
        Param("hysteresis", "1", 1, "1: Jiles–Atherton hysteresis; 0: i_hys = i", structural=True, min=0, max=1),
        Param("i_s", "A", 0.5, "saturation of the virtual current", source="seed 001 eq. 1", positive=True,
              bounds=(0.01, 10.0)),
        Param("mu0", "1/A", 8.0, "Langevin scale μ_o (inclination)", source="seed 001 eqs. 1–2", positive=True,
              bounds=(0.1, 1000.0)),
        Param("alpha", "1", 0.05, "inter-domain coupling α", source="seed 001 eqs. 1–2", min=0.0, bounds=(0.0, 1.0)),
        Param("k", "1", 0.2, "pinning parameter k (loop width)", source="seed 001 eq. 1", positive=True,
              bounds=(1e-3, 10.0)),
        Param("Lambda", "1", 1.0, "slope scaling Λ (≤ 1)", source="seed 001 eq. 1", positive=True, max=1.0),
        Param("rate_eps", "A/s", 1e-6, "input rate below which the direction δ is taken as +1", positive=True),
        Param("K_x", "1/A", 2.0, "static gain tip travel / virtual current", source="seed 001 eqs. 16–18",
              positive=True, bounds=(0.01, 100.0)),
        Param("omega", "rad/s", 600.0, "tip natural frequency ω_np", source="seed 001 eq. 16", positive=True,
              bounds=(10.0, 1e4)),
        Param("zeta", "1", 1.0, "tip damping ratio ζ_p (critically damped, §4.2.1)", source="seed 001 eq. 16",
              positive=True, bounds=(0.1, 3.0)),
        Param("Kv_A", "m^3/s/Pa^0.5", 2e-8, "flow coefficient of the port-1 edges", positive=True,
              bounds=(1e-10, 1e-5)),
        Param("Kv_B", "m^3/s/Pa^0.5", 2e-8, "flow coefficient of the port-2 edges (asymmetry, §5.1)",
              positive=True, bounds=(1e-10, 1e-5)),
        Param("underlap", "1", 0.05, "opening of each edge at null (fraction of full travel)", min=0.0, max=0.5,
              bounds=(0.0, 0.3)),
        Param("dp_lam", "Pa", 5e4, "laminar transition pressure drop", positive=True),
        Param("eps_x", "1", 1e-4, "smoothing of the edge openings", positive=True),
        Param("G_leak", "m^3/s/Pa", 1e-13, "tip-clearance leakage conductance P → T", source="seed 001 eqs. 5–6",
              min=0.0, bounds=(0.0, 1e-10)),
    )
    states = (
        StateSpec("i_c", "A", "coil current", nominal=0.01),
        StateSpec("i_hys", "A", "virtual current after hysteresis", nominal=0.01),
        StateSpec("xv", "1", "valve tip position (fraction)", nominal=0.01),
        StateSpec("xv_dot", "1/s", "valve tip velocity", nominal=1.0),
    )
    variables = (
        VariableSpec("i_hys", "A", "virtual current"), VariableSpec("x_tip", "1", "tip position"),
        VariableSpec("qA", "m^3/s", "flow out of port A"), VariableSpec("qB", "m^3/s", "flow out of port B"),
        VariableSpec("q_leak", "m^3/s", "tip leakage P → T"),
    )

    def equations(self, c):
        p = c.p
        ic = c.state("i_c")
        di = first_order(ic, c.signal("cmd"), p.tau_c)
        c.der("i_c", di)
        ih = c.state("i_hys")
        if int(c.value("hysteresis")):
            delta = E.where(di >= 0.0, 1.0, -1.0)
            c.der("i_hys", ja_slope(ic, ih, delta, p.Lambda, p.mu0, p.alpha, p.k, p.i_s) * di)
        else:
            c.der("i_hys", (ic - ih) / p.tau_c)
        c.let("i_hys", ih)
        xv, xd = c.state("xv"), c.state("xv_dot")
        c.der("xv", xd)
        c.der("xv_dot", p.omega * p.omega * (p.K_x * ih - xv) - 2.0 * p.zeta * p.omega * xd)
        x = c.let("x_tip", xv)
        pP, pT, pA, pB = (c.across(n) for n in "PTAB")

        def edge(dp, xx, kv):
            return kv * edge_opening(xx, -p.underlap, p.eps_x) * E.signed_sqrt(dp, p.dp_lam)

        q_pa, q_at = edge(pP - pA, x, p.Kv_A), edge(pA - pT, -x, p.Kv_A)
        q_pb, q_bt = edge(pP - pB, -x, p.Kv_B), edge(pB - pT, x, p.Kv_B)
        q_l = c.let("q_leak", p.G_leak * (pP - pT) if c.active("G_leak") else 0.0)
        qa = c.let("qA", q_pa - q_at)
        qb = c.let("qB", q_pb - q_bt)
        c.through("A", -qa)
        c.through("B", -qb)
        c.through("P", q_pa + q_pb + q_l)
        c.through("T", -(q_at + q_bt + q_l))
