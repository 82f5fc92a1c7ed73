"""Fifth truth forms of the vocabulary effects (session 64): physically different again from
every earlier form of the same effect (forms.py, third_forms.py, fourth_forms.py), written
without reading the diagnosis, so that a probe of its generality can be scored on forms nobody
tuned it on.

Each class is an ``experiments.concealed.truth.effects.Effect`` (same hooks as forms.py), so it
runs on the EHA truth (FamilyEHATruth) and on the lift / rotary / winch truth (ActuatorTruth).
Hooks that carry no state read the state the truth stored for this right-hand-side call
(``model._y``). Nominal parameters and machines: catalogue.FIFTH. Every form vanishes at its
"off" value (a zero coefficient, clearance, window or gain).

Two forms depend on time within a record: the oil WARMS from the start of each record (t = 0,
the end of the generator's 2 s pre-roll; before it the oil stays at its cold temperature):

    dT(t) = dT_max (1 - exp(-t / tau_T))   for t >= 0,   0 before,

carried as a state (``_Warming``: d(dT)/dt = (dT_max - dT)/tau_T from t = 0), so every record,
its closed loop and its replays alike, starts cold.
"""
from __future__ import annotations

import bisect
import math

import numpy as np
from scipy.optimize import brentq

from experiments.concealed.truth import effects as C

from .forms import ports

Effect = C.Effect
P_REF = 1e5          # [Pa] the pressure at which a gas pocket's volume is given


# ---- 1. external_leakage: a shaft / rod seal whose film thickens with the sliding speed ------
def film_factor(v: float, v_ref: float, v_eps: float) -> float:
    """(|v|/v_ref)^(1/2), exact for |v| >= v_eps; below it sqrt(v_eps/v_ref) (1.75 r^2 - 0.75 r^4),
    r = |v|/v_eps (value and slope continuous at v_eps, zero with zero slope at standstill, so
    the right-hand side stays differentiable)."""
    a = abs(v)
    if a >= v_eps:
        return math.sqrt(a / v_ref)
    r2 = (a / v_eps) ** 2
    return math.sqrt(v_eps / v_ref) * (1.75 * r2 - 0.75 * r2 * r2)


class FilmDragLeakage(Effect):
    """A reciprocating rod seal (rotary / winch: the shaft seals) runs on a hydrodynamic film
    whose thickness grows with the sliding speed (inverse hydrodynamic lubrication,
    h ~ sqrt(mu v / w_max), w_max the pressure gradient under the lip): at standstill the lip
    seals, in motion the film lets oil out to drain in proportion to its thickness and to the
    sealed pressure:

        q_ei = c (|v| / v_ref)^(1/2) (P_i - Pd)

    from the rod-side chamber 2 of a single-rod cylinder (``both = 0``); from BOTH chambers on
    the double-rod EHA cylinder, the vane's and the motor's two shaft seals (``both = 1``), each
    at its own pressure. Below v_eps (<< the recorded speeds) the square root is rounded off
    (``film_factor``). Source: Mueller & Nau, Fluid Sealing Technology (1998), ch. on
    reciprocating seals (film thickness ~ sqrt(mu v / p), leakage carried out with the rod);
    Nikas, "Elastohydrodynamics and mechanics of rectangular elastomeric seals for reciprocating
    piston rods", J. Tribology 125 (2003)."""
    name = "external_leakage"
    form = ("rod / shaft seal LEAKING THROUGH ITS HYDRODYNAMIC FILM, which thickens with the "
            "sliding speed: q_e = c (|v|/v_ref)^(1/2) (P_rod - Pd), nothing at standstill; the "
            "rod side of a single-rod cylinder, both seals of a double-rod cylinder / vane / motor")

    def drain(self, v: float, P: float, Pd: float) -> float:
        p = self.params
        if p["c"] == 0.0:
            return 0.0
        return p["c"] * film_factor(v, p["v_ref"], p["v_eps"]) * (P - Pd)

    def leakages(self, model, P1, P2):
        v, Pd = model._y[6], model.p["Pd"]
        q1 = self.drain(v, P1, Pd) if self.params["both"] else 0.0
        return 0.0, q1, self.drain(v, P2, Pd)


# ---- shared: the oil warming over a record --------------------------------------------------
class _Warming(Effect):
    """An oil temperature rise dT as a state: 0 until t = 0, then first order towards dT_max
    with tau_T (the closed form is module docstring's dT(t))."""

    def setup(self, model):
        model.layout.add("dT")

    def init_state(self, model, y, x0, P0):
        y[model.n_base] = 0.0

    def warming(self, model) -> float:
        return model._y[model.n_base]

    def more_derivatives(self, model, t, y, dy, qs):
        p, i = self.params, model.n_base
        dy[i] = (p["dT_max"] - y[i]) / p["tau_T"] if t >= 0.0 else 0.0

    def atol(self, name):
        return 1e-6


# ---- 2. internal_leakage: a laminar bypass whose oil thins as it warms ----------------------
class WarmingBypassLeakage(_Warming):
    """Laminar (Poiseuille) leakage across the piston (vane, motor) through a clearance of fixed
    height, q = pi d h^3 dp / (12 mu L): its conductance is inversely proportional to the oil's
    viscosity, which falls as the oil warms during the record (the exponential, Reynolds, form
    of the viscosity-temperature law, a local fit of Walther's ASTM D341 / ISO 3448 curve:
    mu = mu_0 exp(-k_T dT), k_T ~ 0.03 /K for a mineral HLP oil):

        q = c0 exp(k_T dT(t)) (P1 - P2),    dT(t) = dT_max (1 - exp(-t/tau_T)), t >= 0

    (the record starts cold: c0 at t = 0, c0 exp(k_T dT_max) once warm).
    Source: Manring, Hydraulic Control Systems (2005), ch. 3 (laminar leakage through an annular
    clearance); Walther (1931) / ASTM D341 and ISO 3448 (viscosity-temperature relation of
    mineral oils); Totten, Handbook of Hydraulic Fluid Technology (2000), ch. 3."""
    name = "internal_leakage"
    form = ("laminar cross-piston leak through a clearance whose OIL WARMS during the record: "
            "q = c0 exp(k_T dT(t)) (P1 - P2), dT = dT_max (1 - exp(-t/tau_T)) from a cold start "
            "at t = 0 (viscosity mu0 exp(-k_T dT))")
    base_overrides = {"c_il": 0.0}

    def factor(self, dT: float) -> float:
        return math.exp(self.params["k_T"] * dT)

    def leakages(self, model, P1, P2):
        return self.params["c0"] * self.factor(self.warming(model)) * (P1 - P2), 0.0, 0.0


# ---- 3. viscous_friction: a viscous coefficient that falls as the oil warms ------------------
class WarmingViscous(_Warming):
    """The viscous part of the seal and guide friction is shear of an oil film,
    F = mu (A_w / h) v: proportional to the oil's viscosity, which falls as the oil warms
    during the record (exponential viscosity-temperature law as in ``WarmingBypassLeakage``):

        F = b0 exp(-k_T dT(t)) v,    dT(t) = dT_max (1 - exp(-t/tau_T)), t >= 0

    (b0 at the cold start, b0 exp(-k_T dT_max) once warm). The truth base has no viscous term.
    Source: Armstrong-Helouvry, Dupont, Canudas de Wit, Automatica 30 (1994), sec. 2 (viscous
    friction of a lubricated contact, its temperature dependence through the viscosity);
    Walther (1931) / ASTM D341, ISO 3448 (viscosity-temperature relation)."""
    name = "viscous_friction"
    form = ("truth base has NO viscous term; viscous friction whose OIL WARMS during the record: "
            "F = b0 exp(-k_T dT(t)) v, dT = dT_max (1 - exp(-t/tau_T)) from a cold start at t = 0")
    base_overrides = {"kv_p": 0.0, "kv_m": 0.0}

    def factor(self, dT: float) -> float:
        return math.exp(-self.params["k_T"] * dT)

    def extra_friction(self, model, v, P1, P2):
        return self.params["b0"] * self.factor(self.warming(model)) * v


# ---- 4. entrained_air: a gas pocket in a dead-end branch behind a small restriction ---------
class BranchGasPocket(Effect):
    """A free-gas pocket trapped in a dead-end branch of each chamber (a gauge port, a bleed
    screw's bore, a high point of the line), connected to the chamber through a small laminar
    restriction R (the branch's bore). The gas is isothermal, of volume V_g at P_ref = 1 bar
    (V_g(P) = V_g P_ref / P), its pressure P_g a state:

        q_g = (P_chamber - P_g) / R,    C_g(P_g) = V_g P_ref / P_g^2,    dP_g/dt = q_g / C_g

    and q_g leaves the chamber (an RC side branch: the chamber sees the gas's compliance only
    below the corner frequency 1 / (2 pi R C_g); far above it, the restriction isolates it).
    Chamber A's pocket (V_gA, R_A) and chamber B's (V_gB, R_B) are separate. (The generator's size
    scales the gas volumes and the bores' conductances together, catalogue.FIFTH: the corner stays.)
    Source: Merritt, Hydraulic Control Systems (1967), ch. 2 (effective bulk modulus of oil with
    entrained gas, the isothermal gas law) and its lumped capacitance / laminar resistance of a
    line (the RC side branch)."""
    name = "entrained_air"
    form = ("a GAS POCKET in a dead-end branch of each chamber BEHIND A LAMINAR RESTRICTION R: "
            "q_g = (P - P_g)/R out of the chamber, dP_g/dt = q_g P_g^2 / (V_g P_ref) "
            "(isothermal, V_g at 1 bar); the chamber sees the gas only below 1/(R C_g)")

    def setup(self, model):
        model.layout.add("PgA", "PgB")

    def init_state(self, model, y, x0, P0):
        i = model.n_base
        y[i], y[i + 1] = y[3], y[4]

    def branch_flows(self, model, y) -> tuple[float, float]:
        p, i = self.params, model.n_base
        qa = (y[3] - y[i]) / p["R_A"] if p["V_gA"] > 0.0 else 0.0
        qb = (y[4] - y[i + 1]) / p["R_B"] if p["V_gB"] > 0.0 else 0.0
        return qa, qb

    def capacitance(self, V_g: float, Pg: float) -> float:
        Pg = max(Pg, 1e4)
        return V_g * P_REF / (Pg * Pg)

    def leakages(self, model, P1, P2):
        qa, qb = self.branch_flows(model, model._y)
        return 0.0, qa, qb

    def more_derivatives(self, model, t, y, dy, qs):
        p, i = self.params, model.n_base
        qa, qb = self.branch_flows(model, y)
        dy[i] = qa / self.capacitance(p["V_gA"], y[i]) if p["V_gA"] > 0.0 else 0.0
        dy[i + 1] = qb / self.capacitance(p["V_gB"], y[i + 1]) if p["V_gB"] > 0.0 else 0.0

    def atol(self, name):
        return 10.0


# ---- 5. load_compliance: a pin / spline connection with clearance (backlash) -----------------
def softplus(z: float) -> float:
    return z + math.log1p(math.exp(-z)) if z > 0.0 else math.log1p(math.exp(z))


def logistic(z: float) -> float:
    if z >= 0.0:
        return 1.0 / (1.0 + math.exp(-z))
    e = math.exp(z)
    return e / (1.0 + e)


class ClearanceJoint(Effect):
    """The rod-load (shaft-load) connection has a clearance of total width b (a worn clevis pin,
    a spline or key with play): the piston side (mass m_p = frac_p m, friction on it) and the
    load (m_L = (1 - frac_p) m, the external / weight load on it) are coupled by a stiff spring k
    and a damper c that act only once the clearance is taken up (the dead-zone model):

        d = x_p - x_L,   D(d) = d - b/2 (d > b/2),  0 (|d| <= b/2),  d + b/2 (d < -b/2)
        F = k D(d) + c D'(d) d'

    D smoothed by softplus over w = b/20: D(d) = w [sp((d - b/2)/w) - sp((-d - b/2)/w)],
    D'(d) its slope, the contact indicator (0 inside the band, 1 in contact; b = 0: D(d) = d,
    a stiff connection). x and v are measured on the LOAD side (as cubic_split_mass); a
    pendulum's weight moment acts at the load's angle.
    Source: Nordin & Gutman, "Controlling mechanical systems with backlash - a survey",
    Automatica 38 (2002), sec. 2 (the dead-zone model, with damping in contact)."""
    name = "load_compliance"
    form = ("rod-load / shaft-load connection with CLEARANCE (backlash) of total width b: stiff "
            "spring k and damper c acting only across the dead band, F = k D(d) + c D'(d) d', "
            "D the (softplus-smoothed) dead zone; piston mass frac_p m, load mass the rest; x "
            "and v measured on the LOAD side")

    def setup(self, model):
        model.layout.add("xL", "vL")

    def init_state(self, model, y, x0, P0):
        y[model.n_base] = x0

    def dead_zone(self, d: float) -> tuple[float, float]:
        """D(d) and D'(d)."""
        b = self.params["b"]
        if b <= 0.0:
            return d, 1.0
        w, h = b / 20.0, 0.5 * b
        zp, zm = (d - h) / w, (-d - h) / w
        return w * (softplus(zp) - softplus(zm)), logistic(zp) + logistic(zm)

    def joint_force(self, d: float, dd: float) -> float:
        D, Dd = self.dead_zone(d)
        return self.params["k"] * D + self.params["c"] * Dd * dd

    def piston_accel(self, model, y, Fp, F, Ff, dy):
        p, i, m = self.params, model.n_base, model.p["m"]
        mp = p["frac_p"] * m
        xL, vL = y[i], y[i + 1]
        if hasattr(model, "load_force"):     # the EHA's load is an external force input
            F = F - model.load_force(y[5]) + model.load_force(xL)
        Fs = self.joint_force(y[5] - xL, y[6] - vL)
        dy[i] = vL
        dy[i + 1] = (Fs + F) / (m - mp)
        return (Fp - Ff - Fs) / mp

    def sensor_outputs(self, model, Y, out):
        out["x"] = Y[model.n_base].copy()
        out["v"] = Y[model.n_base + 1].copy()

    def atol(self, name):
        return 1e-9 if name == "xL" else 1e-7


# ---- 6. input_delay: a moving-average (FIR box) filter on the command ------------------------
def _integral(src, a: float, b: float, cache: dict) -> float:
    """The integral of the command ``src`` (linear between its samples) over [a, b]. An
    ``eha.Inputs`` (uniform samples, held at the first before its start and the last after its
    end): from its cumulative trapezoid sums (cached). Anything else with a history of points
    ``th``, ``uh`` (bench._Live, the closed loop's command): the trapezoid rule over the points
    in (a, b). Otherwise: a 32-panel trapezoid rule of ``u_and_slope``."""
    if hasattr(src, "u") and hasattr(src, "dt") and hasattr(src, "t0"):
        cum = cache.get(id(src))
        if cum is None or cum[0] is not src:
            u = np.asarray(src.u, dtype=float)
            c = np.concatenate([[0.0], np.cumsum(0.5 * (u[1:] + u[:-1]) * src.dt)])
            cum = cache[id(src)] = (src, u, c)
        _, u, c = cum

        def U(t):
            s = (t - src.t0) / src.dt
            if s <= 0.0:
                return u[0] * s * src.dt
            k = min(int(math.floor(s)), len(u) - 1)
            if k >= len(u) - 1:
                return c[-1] + u[-1] * (s - (len(u) - 1)) * src.dt
            f = s - k
            return c[k] + (u[k] * f + 0.5 * (u[k + 1] - u[k]) * f * f) * src.dt

        return U(b) - U(a)
    th = getattr(src, "th", None)
    if th is not None:
        lo, hi = bisect.bisect_right(th, a), bisect.bisect_left(th, b)
        ts = [a] + th[lo:hi] + [b]
    else:
        ts = list(np.linspace(a, b, 33))
    us = [src.u_and_slope(t)[0] for t in ts]
    return sum(0.5 * (us[k] + us[k + 1]) * (ts[k + 1] - ts[k]) for k in range(len(ts) - 1))


class MovingAverageDelay(Effect):
    """The controller's command reaches the valve amplifier through a MOVING-AVERAGE (box FIR)
    filter of length T (a PLC / CAN node averaging the samples of the last T to suppress noise):

        u_valve(t) = (1/T) int_{t-T}^{t} u(s) ds,     du_valve/dt = (u(t) - u(t - T)) / T

    a linear-phase delay of T/2 with the magnitude |sin(pi f T) / (pi f T)| (zeros at k/T).
    Source: Oppenheim & Schafer, Discrete-Time Signal Processing (3rd ed., 2010), ch. 2 (the
    moving-average system and its frequency response); Smith, The Scientist and Engineer's
    Guide to DSP (1997), ch. 15 (moving average filters)."""
    name = "input_delay"
    form = ("the command passes a MOVING-AVERAGE (box FIR) filter of length T: u_valve(t) = "
            "(1/T) int_{t-T}^{t} u(s) ds (linear phase, delay T/2, sinc magnitude)")

    def __init__(self, **params):
        super().__init__(**params)
        self._cache = {}

    def average(self, src, t: float) -> tuple[float, float]:
        T = self.params["T"]
        ua = src.u_and_slope(t - T)[0]
        ub = src.u_and_slope(t)[0]
        return _integral(src, t - T, t, self._cache) / T, (ub - ua) / T

    def command(self, model, t, y, u, du):
        if self.params["T"] <= 0.0:
            return u, du
        raw = getattr(model.inputs, "raw", model.inputs)
        return self.average(raw, t)


# ---- 7. sensor_lag: a velocity differenced from the position signal --------------------------
class DifferencedVelocity(Effect):
    """The recorded velocity (angular rate) is not measured: the acquisition computes it from the
    position (angle) signal as a backward difference over a window T:

        v_meas(t) = (x(t) - x(t - T)) / T

    (the mean velocity over the last T: a delay of T/2 with the magnitude |sinc(f T)|). The
    position itself and the pressures are recorded unchanged. Before the start of the record
    the position is taken as its first value. The difference is taken on the time grid the
    truth was last integrated on (``setup`` records it; x between grid points interpolated
    linearly).
    Source: Brown, Schneider, Mulligan, "Analysis of algorithms for velocity estimation from
    discrete position versus time data", IEEE Trans. Ind. Electron. 39 (1992) (the fixed-window
    backward difference); Oppenheim & Schafer, Discrete-Time Signal Processing (the first
    difference over a window: a moving average of the derivative, its frequency response)."""
    name = "sensor_lag"
    form = ("the recorded VELOCITY is DIFFERENCED from the position signal over a window T: "
            "v_meas(t) = (x(t) - x(t - T))/T (delay T/2, sinc magnitude); x and the pressures "
            "unchanged")

    def setup(self, model):
        simulate = model.simulate

        def simulate_and_keep_grid(t_eval, y0, *args, **kw):
            sol = simulate(t_eval, y0, *args, **kw)
            model._t_grid = np.asarray(sol.t, dtype=float)
            return sol

        model.simulate = simulate_and_keep_grid

    def differenced(self, t, x):
        T = self.params["T"]
        t, x = np.asarray(t, dtype=float), np.asarray(x, dtype=float)
        return (x - np.interp(t - T, t, x)) / T

    def sensor_outputs(self, model, Y, out):
        if self.params["T"] <= 0.0:
            return
        t = getattr(model, "_t_grid", None)
        if t is None or len(t) != Y.shape[1]:
            raise ValueError("DifferencedVelocity: measured() needs the trajectory of the last "
                             "simulate() (its time grid)")
        out["v"] = self.differenced(t, Y[5])


# ---- 8. supply_pressure_drop: a pressure-compensated pump whose compensator lags -------------
class CompensatorDip(Effect):
    """The supply is a pressure-compensated variable-displacement pump. Its compensator sets the
    swash plate after a flow demand with a first-order lag tau_c, so a rising demand draws the
    pressure down until the displacement has followed; there is no steady droop:

        P_valve = Ps - k (q - z),    tau_c dz/dt = q - z

    q the flow the valve draws at P_valve (solved with it: the valve's supply flow falls with
    the pressure, so the pair has one solution), z the flow the pump has followed to. A step of
    demand q dips the pressure by k q exp(-t/tau_c). The recorded Ps is the compensator's set
    pressure (its pilot line), not the valve's P port.
    Source: Manring, Hydraulic Control Systems (2005), the pressure-compensated axial-piston pump
    (its linearised pressure response to a flow demand: a transient undershoot, no steady
    error); Ivantysyn & Ivantysynova, Hydrostatic Pumps and Motors (2001), displacement controls
    (the pressure compensator)."""
    name = "supply_pressure_drop"
    form = ("PRESSURE-COMPENSATED PUMP whose COMPENSATOR LAGS: the valve sees Ps - k (q - z), "
            "tau_c dz/dt = q - z (q the valve's supply flow): a transient dip when the demand "
            "rises, no steady droop")

    def setup(self, model):
        model.layout.add("zq")

    def init_state(self, model, y, x0, P0):
        y[model.n_base] = 0.0

    def supply_flow(self, model, y, Pv: float) -> float:
        PA, PB = ports(model, y)
        return model.valve_flows(y[1], Pv, PA, PB)[2]

    def valve_pressure(self, model, y, Ps: float) -> float:
        """The root of g(P) = P - Ps + k (q(P) - z), g increasing in P."""
        k, z = self.params["k"], y[model.n_base]
        if k == 0.0:
            return Ps

        def g(P):
            return P - Ps + k * (self.supply_flow(model, y, P) - z)

        lo, hi, step = Ps - 1e6, Ps + 1e6, 1e6
        while g(lo) > 0.0:
            step *= 2.0
            lo -= step
        step = 1e6
        while g(hi) < 0.0:
            step *= 2.0
            hi += step
        return brentq(g, lo, hi, xtol=1e-3, rtol=1e-12)

    def supply_at_valve(self, model, y, Ps):
        return self.valve_pressure(model, y, Ps)

    def more_derivatives(self, model, t, y, dy, qs):
        i = model.n_base
        dy[i] = (qs - y[i]) / self.params["tau_c"]

    def atol(self, name):
        return 1e-9
