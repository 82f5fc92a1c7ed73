"""Excitation and closed-loop bench for one experiment (any machine type of the family).

Setpoint: minimum-jerk moves (fast excursions, slow moves, small reversals) with random holds;
a continuous PI position controller with velocity feed-forward and a multi-sine dither
(0.5-18 Hz) drives the valve; supply with ripple, slow variation and flow droop; for the EHA
bench an external force (AM sine + band-limited random) as in experiments/concealed. The loop
runs on the truth WITH the effect; the applied inputs are then replayed open loop.
"""
from __future__ import annotations

import bisect
import math

import numpy as np
from scipy.integrate import solve_ivp

from experiments.concealed.truth.eha import Inputs


#: peak / mean speed of a min-jerk move (30/16): a move of distance d at peak speed w takes
#: MIN_JERK_PEAK * d / w
MIN_JERK_PEAK = 1.875


def min_jerk(s):
    s = min(max(s, 0.0), 1.0)
    return s ** 3 * (10 - 15 * s + 6 * s * s), 30 * s * s * (1 - s) ** 2


def reach(segs: list[tuple], setpoint_max: float, duration: float = float("inf"),
          max_speed: float = float("inf")) -> list[tuple]:
    """Moves (t0, T, from, to) with every target clipped at ``setpoint_max`` and the highest
    move's target set to it: an end-stop case must touch its stop in EVERY experiment, or the
    effect is absent from the training recording and no diagnosis fitted to it can name it
    (before this, an EHA case's training stayed 16 mm short of the stop).

    The move raised is the highest of those that END inside the recording (``duration``), at
    a min-jerk peak speed no higher than ``max_speed`` (its duration stretched, the later moves
    shifted by as much): lift dev seed 162's highest move began 0.64 s before the end of the
    recording, so the piston was still 7 cm below the stop when it ended (effect ESR 0 in
    training and held out), whatever the setpoint."""
    segs = [(t0, T, min(a, setpoint_max), min(b, setpoint_max)) for t0, T, a, b in segs]
    if not segs or any(b >= setpoint_max and t0 + T <= duration for t0, T, _, b in segs):
        return segs

    def stretched(k):
        t0, T, a, _ = segs[k]
        return max(T, MIN_JERK_PEAK * abs(setpoint_max - a) / max_speed)

    ends = [k for k in range(len(segs)) if segs[k][0] + stretched(k) <= duration]
    i = max(ends or range(len(segs)), key=lambda k: segs[k][3])
    t0, T, a, _ = segs[i]
    T_new = stretched(i)
    segs[i] = (t0, T_new, a, setpoint_max)
    if i + 1 < len(segs):
        t1, T1, _, b1 = segs[i + 1]
        segs[i + 1] = (t1, T1, setpoint_max, b1)
    return segs[:i + 1] + [(t + T_new - T, *rest) for t, *rest in segs[i + 1:]]


class Excitation:
    """Setpoint, dither, supply and external force of one experiment (seeded)."""

    def __init__(self, bench: dict, seed_seq, duration: float, fs: float, preroll: float,
                 setpoint_max: float | None = None):
        rng = np.random.default_rng(seed_seq)
        self.B, self.duration, self.fs, self.preroll = bench, duration, fs, preroll
        self.setpoint_max = setpoint_max
        lo, hi = bench["setpoint_range"]
        segs, t, x = [], 0.0, bench["x_home"]
        while t < duration:
            kind = rng.choice(["big", "big", "slow", "small", "small"])
            if kind == "big":
                tgt = float(rng.uniform(lo, hi))
                T = abs(tgt - x) / rng.uniform(*bench["speed_big"]) * MIN_JERK_PEAK
            elif kind == "slow":
                tgt = float(np.clip(x + rng.choice([-1, 1]) * rng.uniform(*bench["step_slow"]), lo, hi))
                T = abs(tgt - x) / rng.uniform(*bench["speed_slow"]) * MIN_JERK_PEAK
            else:
                tgt = float(np.clip(x + rng.choice([-1, 1]) * rng.uniform(*bench["step_small"]), lo, hi))
                T = rng.uniform(0.3, 0.8)
            T = max(T, bench.get("T_min", 0.2))     # shortest move [s] (the winch: 0.6)
            segs.append((t, T, x, tgt))
            t += T + float(rng.uniform(0.2, 0.8))
            x = tgt
        if setpoint_max is not None:
            segs = reach(segs, setpoint_max, duration, bench["speed_big"][1])
        self.segs, self.seg_tl = segs, [s[0] for s in segs]
        nd = 7
        f = np.exp(rng.uniform(math.log(0.5), math.log(18.0), nd))
        a = rng.uniform(0.4, 1.0, nd) * bench["dither_amp"] / math.sqrt(nd)
        ph = rng.uniform(0, 2 * math.pi, nd)
        self.dither_freqs = [float(v) for v in f]
        self._dl = [(float(a_), 2 * math.pi * float(f_), float(p_)) for a_, f_, p_ in zip(a, f, ph)]
        self.f_F = float(rng.uniform(1.2, 2.0))
        self.F_amp = bench["Fext_amp"] * float(rng.uniform(0.85, 1.15))
        self.F_ph = float(rng.uniform(0, 2 * math.pi))
        self.F_mod_f = float(rng.uniform(0.03, 0.08))
        dt = 1.0 / fs
        n = int(round((duration + preroll) * fs)) + 1
        w = rng.standard_normal(n)
        al = math.exp(-2 * math.pi * 2.0 * dt)
        from scipy.signal import lfilter
        for _ in range(2):
            w = lfilter([1 - al], [1, -al], w)
        self.F_rand = (0.17 * bench["Fext_amp"]) * w / max(np.std(w), 1e-12)
        self.Ps_ph = float(rng.uniform(0, 2 * math.pi))
        self.Ps_slow = (float(rng.uniform(0.05, 0.2)), float(rng.uniform(0, 2 * math.pi)))
        self.t_grid = -preroll + dt * np.arange(n)

    def setpoint(self, t):
        if t <= 0.0:
            return self.B["x_home"], 0.0
        k = bisect.bisect_right(self.seg_tl, t) - 1
        t0, T, x0, x1 = self.segs[k]
        s, ds = min_jerk((t - t0) / T)
        return x0 + (x1 - x0) * s, (x1 - x0) * ds / T if (t - t0) < T else 0.0

    def dither(self, t):
        if t <= 0.0:
            return 0.0
        return min(t / 0.5, 1.0) * sum(a * math.sin(w * t + ph) for a, w, ph in self._dl)

    def force(self, t, k):
        if self.B["Fext_amp"] == 0.0:
            return 0.0
        on = 0.5 * (1 - math.cos(math.pi * min(max((t + self.preroll) / 1.0, 0.0), 1.0)))
        mod = 0.65 + 0.35 * math.sin(2 * math.pi * self.F_mod_f * max(t, 0.0))
        return on * (self.F_amp * mod * math.sin(2 * math.pi * self.f_F * t + self.F_ph)
                     + self.F_rand[k])

    def Ps_open(self, t):
        B = self.B
        a, ph = self.Ps_slow
        return (B["Ps0"] + B["ripple_amp"] * math.sin(2 * math.pi * B["ripple_freq"] * t + self.Ps_ph)
                + B["slow_amp"] * math.sin(2 * math.pi * a * t + ph))


class _Live:
    """Inputs set by the controller before each rhs call; keeps the command's history so a
    delayed command u(t - T_d) is available in closed loop too."""
    u = Ps = F = 0.0

    def __init__(self):
        self.th, self.uh = [], []

    def push(self, t, u):
        while self.th and self.th[-1] >= t:      # the integrator stepped back: forget
            self.th.pop()
            self.uh.pop()
        self.th.append(t)
        self.uh.append(u)

    def at(self, t):
        return self.u, self.Ps, self.F

    def u_and_slope(self, t):
        if not self.th or t >= self.th[-1]:
            return self.u, 0.0
        k = bisect.bisect_right(self.th, t)
        if k == 0:
            return self.uh[0], 0.0
        t0, t1 = self.th[k - 1], self.th[k]
        a = (t - t0) / (t1 - t0) if t1 > t0 else 1.0
        return self.uh[k - 1] + a * (self.uh[k] - self.uh[k - 1]), 0.0


def closed_loop(model, exc: Excitation, y0, Kq: float):
    """Run the bench in closed loop on ``model``; returns the applied (u, Ps, Fext) samples."""
    B = exc.B
    live = _Live()
    model.inputs = live
    n = len(y0)
    tg = exc.t_grid
    dt = 1.0 / exc.fs
    sp = [exc.setpoint(t) for t in tg]
    ext = Inputs(tg[0], dt, [a[0] for a in sp], [exc.Ps_open(t) for t in tg],
                 [exc.force(t, k) for k, t in enumerate(tg)])
    ffd = Inputs(tg[0], dt, [a[1] / Kq + exc.dither(t) for a, t in zip(sp, tg)],
                 [0.0] * len(tg), [0.0] * len(tg))
    Kp, Ki, umax = B["ctrl_Kp"], B["ctrl_Ki"], B["u_max"]

    def ctrl(t, y):
        r, Pso, F = ext.at(t)
        u = Kp * (r - y[5]) + Ki * y[n] + ffd.at(t)[0]
        return min(max(u, -umax), umax), r, Pso, F

    def rhs(t, y):
        u, r, Pso, F = ctrl(t, y)
        live.u, live.Ps, live.F = u, Pso - y[n + 1], F
        live.push(t, u)
        dy = model.rhs(t, y[:n])
        _, _, qs = model.valve_flows(y[1], live.Ps, *model_ports(model, y))
        zdot = r - y[5]
        uu = Kp * (r - y[5]) + Ki * y[n]
        if abs(uu) > umax and zdot * uu > 0:
            zdot = 0.0
        dy.append(zdot)
        dy.append((B["droop_gain"] * max(qs, 0.0) - y[n + 1]) / B["droop_tau"])
        return dy

    Y0 = np.concatenate([y0, [0.0, 0.0]])
    atol = np.concatenate([model.default_atol(), [1e-6, 10.0]])
    sol = solve_ivp(rhs, (tg[0], tg[-1]), Y0, method="LSODA", t_eval=tg, rtol=1e-4, atol=atol,
                    max_step=2e-3)
    if not sol.success:
        raise RuntimeError(f"closed loop failed: {sol.message}")
    out = np.array([ctrl(t, sol.y[:, i]) for i, t in enumerate(sol.t)])
    return out[:, 0], out[:, 2] - sol.y[n + 1], out[:, 3], sol


def model_ports(model, y):
    return model.ports(y) if hasattr(model, "ports") else (y[3], y[4])
