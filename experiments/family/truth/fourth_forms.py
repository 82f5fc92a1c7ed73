"""Fourth truth forms of the vocabulary effects (session 54): physically different again from
every earlier form of the same effect (forms.py, third_forms.py), written without reading the
diagnosis, so that a probe of its generality can be scored on forms nobody tuned it on.

Each class is an ``experiments.concealed.truth.effects.Effect`` (same hooks as forms.py), so it
runs on the EHA truth (FamilyEHATruth) and on the lift / rotary / winch truth (ActuatorTruth).
Hooks that carry no state read the state the truth stored for this right-hand-side call
(``model._y``). Nominal parameters and machines: catalogue.FOURTH. Every form vanishes at its
"off" value (a zero coefficient, or an infinite limit / stiffness for the forms whose size is a
limit: the pump's flow limit, the mount's stiffness, the transducer's resonance).
"""
from __future__ import annotations

import hashlib
import math

from experiments.concealed.truth import effects as C
from experiments.concealed.truth.eha import flow_law

from .forms import CompliantMount, _centre_leak, ports
from .third_forms import chamber_volumes, logistic

Effect = C.Effect
P_ATM = 1e5          # [Pa] the reference pressure of a free-air volume


# ---- 1. external_leakage: port relief valves that weep above their cracking pressure -------
class CrackingDrainLeakage(Effect):
    """Each chamber has a spring-loaded poppet (port / shock relief) to drain that is closed
    below its cracking pressure P_cr. Above it the poppet lifts in proportion to the pressure
    excess (spring rate), and the flow through the annular opening follows the orifice law:

        q_ei = K_r max(P_i - P_cr, 0) sqrt(P_i - Pd)          (i = 1, 2)

    Source: Merritt, Hydraulic Control Systems (1967), sec. 2.3 / 5.2 (orifice flow, relief
    valve steady characteristic); Manring, Hydraulic Control Systems (2005), ch. 5 (pressure
    relief valve: poppet stroke x = A (P - P_cr)/k, Q = C_d pi d x sqrt(2 dP / rho))."""
    name = "external_leakage"
    form = ("a poppet relief (weeping port relief valve) from EACH chamber to drain, closed below "
            "its cracking pressure: q_ei = K_r max(P_i - P_cr, 0) sqrt(P_i - Pd) (poppet lift "
            "proportional to the excess, orifice flow through it); no leak below P_cr")

    def drain(self, model, P: float) -> float:
        p = self.params
        exc = P - p["P_cr"]
        if exc <= 0.0 or p["K_r"] == 0.0:
            return 0.0
        return p["K_r"] * exc * math.sqrt(max(P - model.p["Pd"], 0.0))

    def leakages(self, model, P1, P2):
        return 0.0, self.drain(model, P1), self.drain(model, P2)


# ---- 2. internal_leakage: a clearance that the pressure opens elastically ------------------
class ElasticGapLeakage(Effect):
    """Laminar (Poiseuille) leakage through the piston's annular clearance, q = pi d h^3 dp /
    (12 mu L), whose height h grows elastically with the pressure difference across it (the
    barrel / the sleeve dilates): h = h0 (1 + |dp|/p_h), hence

        q = c0 (1 + |dp|/p_h)^3 dp,      dp = P1 - P2

    (super-linear; not laminar-constant, not orifice-like sub-linear).
    Source: Manring, Hydraulic Control Systems (2005), ch. 3 (leakage through an annular
    clearance); Ivantysyn & Ivantysynova, Hydrostatic Pumps and Motors (2001), ch. 5
    (pressure-deformed sealing gaps, q ~ h^3)."""
    name = "internal_leakage"
    form = ("laminar leak through an ELASTICALLY OPENING clearance: h = h0 (1 + |dp|/p_h), "
            "q = c0 (1 + |dp|/p_h)^3 (P1 - P2) (Poiseuille q ~ h^3)")
    base_overrides = {"c_il": 0.0}

    def leakages(self, model, P1, P2):
        p = self.params
        dp = P1 - P2
        return p["c0"] * (1.0 + abs(dp) / p["p_h"]) ** 3 * dp, 0.0, 0.0


# ---- 3. coulomb_friction: direction- and position-dependent (a tight spot) -----------------
class TightSpotCoulomb(Effect):
    """Dry friction whose level depends on the direction of motion AND on the position: over a
    band of the stroke (a bent rod, an out-of-round bore, a misaligned guide) the seal is
    squeezed harder and the friction rises by the factor (1 + a):

        F = Fc_+/- (1 + a w(x)) tanh(v / v_c),
        w(x) = s((x - x1)/d) s((x2 - x)/d)   (s the logistic; a band of the stroke),
        w(theta) = (1 + cos(theta - x1))/2    (the winch: once per drum revolution, an
                                               eccentric drum / motor bearing; ``period`` given)

    Source: Armstrong-Helouvry, Dupont, Canudas de Wit, "A survey of models, analysis tools and
    compensation methods for the control of machines with friction", Automatica 30 (1994),
    sec. 2 (position-dependent friction, direction-dependent Coulomb level)."""
    name = "coulomb_friction"
    form = ("truth base has NO Coulomb term; direction-dependent Coulomb level raised over a "
            "TIGHT SPOT of the stroke: F = Fc_+/- (1 + a w(x)) tanh(v/v_c), w = logistic band "
            "[x1, x2] (the winch: w = (1 + cos(theta - x1))/2, once per drum revolution)")
    base_overrides = {"kc_p": 0.0, "kc_m": 0.0}

    def window(self, x: float) -> float:
        p = self.params
        if p.get("period"):
            return 0.5 * (1.0 + math.cos(2.0 * math.pi * (x - p["x1"]) / p["period"]))
        return logistic((x - p["x1"]) / p["d"]) * logistic((p["x2"] - x) / p["d"])

    def level(self, v: float, x: float) -> float:
        p = self.params
        return (p["Fc_p"] if v >= 0.0 else p["Fc_m"]) * (1.0 + p["a"] * self.window(x))

    def extra_friction(self, model, v, P1, P2):
        return self.level(v, model._y[5]) * math.tanh(v / self.params["v_c"])


# ---- 4. entrained_air: free air that dissolves slowly (first-order gas-content state) -------
class DissolvingAir(Effect):
    """Each chamber holds free air whose amount is a STATE: g_i, the free-air volume at 1 bar per
    unit chamber volume, starting at alpha0 (oil aerated while the machine stood) and moving to
    its Henry-law equilibrium g_eq(P) = B max(P_sat - P, 0)/P_sat at first order, FAST when air
    comes out of solution (tau_r) and SLOW when it goes back in (tau_a):

        dg/dt = (g_eq(P) - g)/tau,   tau = tau_r if g_eq > g else tau_a
        gas volume (isothermal) V_g = g V P_atm / P:
        (V/beta + g V P_atm/P^2) dP/dt = Q_net + V P_atm (dg/dt)/P

    (above P_sat, as here, the air dissolves over the record: the chambers stiffen with time).
    Source: Zhou, Vacca, Manhartsgruber, "A novel approach for the prediction of dynamic
    features of air release and absorption in hydraulic oils", J. Fluids Eng. 135 (2013)
    (first-order release / absorption with tau_r << tau_a); Gholizadeh, Burton, Schoenau,
    "Fluid bulk modulus: a literature survey", Int. J. Fluid Power 12 (2011)."""
    name = "entrained_air"
    form = ("free air in each chamber as a STATE that dissolves slowly (absorption tau_a) and "
            "comes out fast below P_sat (release tau_r): dg/dt = (g_eq(P) - g)/tau, "
            "g(0) = alpha0, isothermal gas volume g V P_atm/P in the chamber's capacitance")

    def setup(self, model):
        model.layout.add("g1", "g2")

    def init_state(self, model, y, x0, P0):
        y[model.n_base] = y[model.n_base + 1] = self.params["alpha0"]

    def g_dot(self, g: float, P: float) -> float:
        p = self.params
        geq = p["B"] * max(p["P_sat"] - P, 0.0) / p["P_sat"]
        return (geq - g) / (p["tau_r"] if geq > g else p["tau_a"])

    def more_derivatives(self, model, t, y, dy, qs):
        i, beta = model.n_base, model.p["beta"]
        V = chamber_volumes(model, y[5])
        for k in range(2):
            P = max(y[3 + k], 1e4)
            g = y[i + k]
            gd = self.g_dot(g, P)
            dy[i + k] = gd
            C_oil = V[k] / beta
            C = C_oil + g * V[k] * P_ATM / (P * P)
            # the truth wrote dP/dt = beta Q_net / V: rescale to the capacitance with the gas,
            # and the volume the dissolving / released gas frees / takes (oil + gas fill V)
            dy[3 + k] = dy[3 + k] * (C_oil / C) + V[k] * P_ATM * gd / P / C

    def atol(self, name):
        return 1e-8


# ---- 5. line_dynamics: long rigid pipes with frequency-dependent friction on both lines ----
TRIKHA_M = (40.0, 8.1, 1.0)
TRIKHA_N = (8000.0, 200.0, 26.4)


class RigidPipesFDF(Effect):
    """Both work lines are long RIGID (steel) pipes of length L and bore radius r, one lumped
    pi-section each (half the oil volume a L at the valve port, half added to the chamber),
    fluid inertance I = rho L / a and laminar friction that depends on the frequency (Zielke's
    weighting function in Trikha's three-exponential approximation):

        I dq/dt = P_v - P_c - R q - (R/2) (y1 + y2 + y3),      R = 8 rho nu L / (pi r^4)
        dy_k/dt = -n_k (nu/r^2) y_k + m_k dq/dt,    m = (40, 8.1, 1), n = (8000, 200, 26.4)
        (a L / 2 beta) dP_v/dt = q_valve - q

    (steady flow: y_k -> 0 and the drop is Hagen-Poiseuille R q; fast changes see more
    friction). Source: Zielke, "Frequency-dependent friction in transient pipe flow", J. Basic
    Eng. 90 (1968); Trikha, "An efficient method for simulating frequency-dependent friction in
    transient liquid flow", J. Fluids Eng. 97 (1975); Merritt (1967) ch. 4 (line dynamics)."""
    name = "line_dynamics"
    form = ("long RIGID pipes on BOTH lines (length L, radius r), lumped pi-sections, inertance "
            "rho L/a, Hagen-Poiseuille R plus FREQUENCY-DEPENDENT (Zielke/Trikha) unsteady "
            "friction (R/2) sum y_k, dy_k/dt = -n_k nu/r^2 y_k + m_k dq/dt")

    def __init__(self, **params):
        super().__init__(**params)
        p = self.params
        a = math.pi * p["r"] ** 2
        self.a = a
        self.V = a * p["L"]
        self.I = p["rho"] * p["L"] / a
        self.R = 8.0 * p["rho"] * p["nu"] * p["L"] / (math.pi * p["r"] ** 4)
        self.rate = p["nu"] / p["r"] ** 2

    def setup(self, model):
        for h in "AB":
            model.layout.add(f"Pp{h}", f"qp{h}", *[f"yf{h}{k}" for k in range(3)])

    def init_state(self, model, y, x0, P0):
        i = model.n_base
        y[i], y[i + 5] = y[3], y[4]

    def port_pressures(self, model, y):
        i = model.n_base
        return y[i], y[i + 5]

    def pipe_derivs(self, beta, qin, Pv, q, ys, Pc):
        """d/dt of (P_v, q, y1, y2, y3) of one pipe."""
        qd = (Pv - Pc - self.R * q - 0.5 * self.R * sum(ys)) / self.I
        out = [beta * (qin - q) / (0.5 * self.V), qd]
        out += [-n * self.rate * yk + m * qd for m, n, yk in zip(TRIKHA_M, TRIKHA_N, ys)]
        return out

    def chamber_inflows(self, model, y, qa, qb, dy):
        i, beta = model.n_base, model.p["beta"]
        for h, (qin, Pc) in enumerate(((qa, y[3]), (qb, y[4]))):
            o = i + 5 * h
            dy[o:o + 5] = self.pipe_derivs(beta, qin, y[o], y[o + 1], y[o + 2:o + 5], Pc)
        return y[i + 1], y[i + 6]

    def more_derivatives(self, model, t, y, dy, qs):
        # the pipe's cylinder-end half volume adds to each chamber's capacitance
        V = chamber_volumes(model, y[5])
        for k in range(2):
            dy[3 + k] *= V[k] / (V[k] + 0.5 * self.V)

    def atol(self, name):
        return 10.0 if name.startswith("Pp") else (1e-9 if name.startswith("qp") else 1e-9)


# ---- 6. valve_overlap: an UNDERLAPPED (open-centre) spool ----------------------------------
class UnderlapSpool(Effect):
    """Negative overlap U [% of the stroke]: at null all four metering edges are open by U and
    oil flows from supply to tank through both work ports. The edge openings are

        P->A: (U + x)+,  A->T: (U - x)+,  P->B: (U - x)+,  B->T: (U + x)+   [%],

    each an orifice Kv (opening/100) f(dp) (beyond |x| > U the spool meters like a critical-centre
    one shifted by U; the pressure gain is lower and the flow gain doubled near null).
    Source: Merritt (1967) sec. 5.3-5.4 (the underlapped / open-centre four-way spool valve);
    Manring (2005) ch. 6 (valve with negative overlap)."""
    name = "valve_overlap"
    form = ("UNDERLAPPED spool (negative overlap U): all four edges open by U at null, "
            "P->A (U + x)+, A->T (U - x)+, P->B (U - x)+, B->T (U + x)+; a supply-to-tank "
            "leak flow through both ports around null")
    custom_valve = True

    def valve_flows(self, model, xv, Ps, y):
        p, U = model.p, self.params["U"]
        PA, PB = ports(model, y)
        Kv, Pd, dl = p["Kv"], p["Pd"], p["dp_lam"]
        pa = Kv * max(U + xv, 0.0) / 100.0
        at = Kv * max(U - xv, 0.0) / 100.0
        q_pa = pa * flow_law(Ps - PA, dl)
        q_pb = at * flow_law(Ps - PB, dl)          # P->B opens with A->T
        qa = q_pa - at * flow_law(PA - Pd, dl)
        qb = q_pb - pa * flow_law(PB - Pd, dl)     # B->T opens with P->A
        return _centre_leak(p, Ps, PA, PB, qa, qb, q_pa + q_pb)


# ---- 7. input_delay: a jittering network delay ----------------------------------------------
def _unit(seed: int, k: int) -> float:
    """A number in [-1, 1) fixed by (seed, k) (a counter-based draw: the same wherever the
    integrator asks for it)."""
    h = hashlib.blake2b(f"{int(seed)}|{int(k)}".encode(), digest_size=8).digest()
    return 2.0 * int.from_bytes(h, "big") / 2.0 ** 64 - 1.0


class JitterDelay(Effect):
    """The command reaches the valve over a network whose latency JITTERS: a new latency is
    drawn for every packet (period T_p = T_d), d_k = T_d (1 + j r_k), r_k uniform in [-1, 1)
    from a seeded counter-based generator, and the delay varies linearly between packets
    (a variable transport delay; |dd/dt| <= 2 j < 1, so the valve never sees time run back):

        u_valve(t) = u(t - d(t)),   du_valve/dt = u'(t - d) (1 - d'(t))

    Source: Nilsson, Bernhardsson, Wittenmark, "Stochastic analysis and control of real-time
    systems with random time delays", Automatica 34 (1998); Zhang, Branicky, Phillips,
    "Stability of networked control systems", IEEE Control Syst. Mag. 21 (2001)."""
    name = "input_delay"
    form = ("NETWORK delay that JITTERS: per packet (period T_d) a latency T_d (1 + j r_k), r_k "
            "uniform in [-1, 1) (seeded), linear between packets: u_valve(t) = u(t - d(t))")

    def __init__(self, **params):
        super().__init__(**params)
        self._r = {}

    def draw(self, k: int) -> float:
        r = self._r.get(k)
        if r is None:
            r = self._r[k] = _unit(self.params["seed"], k)
        return r

    def delay_and_rate(self, t: float) -> tuple[float, float]:
        p = self.params
        Td = p["T_d"]
        if Td <= 0.0:
            return 0.0, 0.0
        s = t / Td
        k = math.floor(s)
        a = s - k
        r0, r1 = self.draw(k), self.draw(k + 1)
        j = p["j"]
        return Td * (1.0 + j * (r0 + a * (r1 - r0))), j * (r1 - r0)

    def command(self, model, t, y, u, du):
        d, dd = self.delay_and_rate(t)
        if d == 0.0:
            return u, du
        raw = getattr(model.inputs, "raw", model.inputs)
        ud, dud = raw.u_and_slope(t - d)
        return ud, dud * (1.0 - dd)


# ---- 8. sensor_lag: pressure transducers with a lightly damped mechanical resonance ---------
class ResonantPressureSensor(Effect):
    """Each pressure transducer, mounted on a test-point hose (the oil column in the hose and the
    transducer's volume: a Helmholtz resonator, f_n = (c/2 pi) sqrt(a / (L V)), tens of Hz for a
    1-2 m micro-bore hose; a bare diaphragm rings at kHz) is a lightly damped second-order system
    of natural frequency f_n and damping ratio zeta, after the 1 ms lag every recording has:

        P_s'' = w^2 (P_m - P_s) - 2 zeta w P_s',   w = 2 pi f_n

    (unit static gain; a step overshoots by exp(-zeta pi / sqrt(1 - zeta^2))).
    Source: Doebelin, Measurement Systems: Application and Design (5th ed., 2004), sec. 3.3 and
    6.1 (second-order instruments; dynamics of a pressure transducer with connecting tubing)."""
    name = "sensor_lag"
    form = ("pressure transducers on test hoses with a lightly damped RESONANCE: P1, P2 measured "
            "through P_s'' = w^2 (P_m - P_s) - 2 zeta w P_s' (f_n, zeta), after the 1 ms lag")

    def setup(self, model):
        model.layout.add("P1r", "P1rd", "P2r", "P2rd")

    def init_state(self, model, y, x0, P0):
        i = model.n_base
        y[i], y[i + 2] = y[7], y[8]

    def more_derivatives(self, model, t, y, dy, qs):
        i = model.n_base
        w = 2.0 * math.pi * self.params["f_n"]
        z = self.params["zeta"]
        for k in range(2):
            o = i + 2 * k
            dy[o] = y[o + 1]
            dy[o + 1] = w * w * (y[7 + k] - y[o]) - 2.0 * z * w * y[o + 1]

    def sensor_outputs(self, model, Y, out):
        i = model.n_base
        out["P1"] = Y[i].copy()
        out["P2"] = Y[i + 2].copy()

    def atol(self, name):
        return 10.0 if name in ("P1r", "P2r") else 1e4


# ---- 9. supply_pressure_drop: a pressure-compensated pump with a flow limit ----------------
class FlowLimitedPump(Effect):
    """The recorded Ps is the pump's compensator pressure; the pump delivers what the valve
    draws as long as that is below its maximum displacement flow Q_max (displacement x speed).
    Beyond, the pressure at the valve collapses until the valve draws no more than Q_max. With
    D = Ps - P_valve the pressure deficit in the supply line's capacitance C = V_l / beta,

        Q_pump = min(Q_max, q_s + C D / tau_c),   C dD/dt = q_s - Q_pump
        i.e.   dD/dt = max(-D / tau_c, (q_s - Q_max) / C)

    (D = 0 while the pump keeps up; the compensator recovers the deficit with tau_c).
    Source: Manring, Hydraulic Control Systems (2005), ch. 8 (pressure-compensated
    variable-displacement pump, its flow limit); Merritt (1967) ch. 7 (pressure-compensated
    supplies)."""
    name = "supply_pressure_drop"
    form = ("PRESSURE-COMPENSATED PUMP with a FLOW LIMIT Q_max: the valve sees Ps - D, "
            "dD/dt = max(-D/tau_c, (q_s - Q_max)/C), C = V_l/beta (the pressure collapses only "
            "while the valve draws more than Q_max)")

    def setup(self, model):
        model.layout.add("Dps")

    def init_state(self, model, y, x0, P0):
        y[model.n_base] = 0.0

    def supply_at_valve(self, model, y, Ps):
        return Ps - y[model.n_base]

    def more_derivatives(self, model, t, y, dy, qs):
        p, i = self.params, model.n_base
        C = p["V_l"] / model.p["beta"]
        dy[i] = max(-y[i] / p["tau_c"], (qs - p["Q_max"]) / C)

    def atol(self, name):
        return 10.0


# ---- 10. structural_flexibility: a bilinear mount ---------------------------------------------
class BilinearMount(CompliantMount):
    """The cylinder body / motor housing (mass m_b) on a mount whose stiffness differs on the two
    sides of a knee: k_b on the unloading (tension) side, r k_b on the loaded (compression) side,
    the knee at the deflection d_k = -F_k / k_b where the mount carries the force F_k (F_k = 0:
    tension vs compression of a mount whose load reverses; F_k = the static load: a mount that
    is pre-compressed under the weight and stiffens / softens beyond it):

        F_m(d) = k_b d + c_b d'                      for d >= d_k
        F_m(d) = k_b d_k + r k_b (d - d_k) + c_b d'  for d <  d_k      (continuous at d_k)

    Source: Harris & Piersol, Harris' Shock and Vibration Handbook (5th ed., 2002), ch. 32-33
    (rubber isolators: different stiffness in tension and compression, bilinear / snubbed
    mounts)."""
    form = ("cylinder body / housing on a BILINEAR mount: stiffness k_b on the unloading side, "
            "r k_b on the loaded side of a knee at the mount force F_k (0: tension vs "
            "compression), F continuous at the knee, plus viscous c_b; stroke measured rod to "
            "body (as mount_linear)")

    def mount_force(self, xb, vb):
        p = self.params
        dk = -p["F_k"] / p["k_b"]
        if xb >= dk:
            F = p["k_b"] * xb
        else:
            F = p["k_b"] * dk + p["r"] * p["k_b"] * (xb - dk)
        return F + p["c_b"] * vb
