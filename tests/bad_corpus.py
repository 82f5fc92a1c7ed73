"""Generator of the hostile-input corpus: ≥ 300 bad or hostile inputs, each a command line
that must be refused with the right exit code, a located message, no traceback, and no
input destroyed. ``tests/test_bad_corpus.py`` runs every case; run this file to write the
corpus to a folder for inspection:

    python tests/bad_corpus.py /tmp/corpus      # writes the files and a manifest.json

A case is data: the files it needs (text or bytes, relative to a case folder), the command
line (``{d}`` is the case folder), the expected exit code, the file whose name (and, with
``line=True``, line number) the message must contain, and the files that must be unchanged.
Families: hostile YAML (alias bombs, nesting, size, include fan-out, self-nesting templates),
non-physical parameter values (from the component specs), initial states, output expressions
and units, file-level units, experiment files (units, types, durations, signals), recordings
(CSV headers, HDF5 unit attributes), output paths that are inputs, devices or folders, and
usage errors.
"""
from __future__ import annotations

import io
import json
import sys
from dataclasses import dataclass, field
from pathlib import Path

MACHINE = """\
name: rig
fluid: {beta: "1.5 GPa", p_tank: "1 bar"}
inputs:
  u: {unit: "%"}
  Ps: {unit: bar}
components:
  supply: {type: pressure_source, ports: {P: n_s, ref: Ps}}
  tank: {type: tank, ports: {T: n_t}}
  valve:
    type: valve_4_3
    ports: {P: n_s, T: n_t, A: a, B: b, cmd: u}
    Kv: {value: 4.68e-7, free: true, bounds: [1.0e-7, 2.0e-6]}
    tau: "4 ms"
  cyl:
    type: cylinder_double_rod
    ports: {A: a, B: b, rod: piston, body: ground}
    A: "2.0e-3 m^2"
    V_A0: 2.0e-4
    V_B0: 2.0e-4
  load:
    type: mass
    ports: {m: piston}
    m: {value: 50, free: true, bounds: [20, 300]}
  spring: {type: spring, ports: {a: piston, b: ground}, k: 1.0e5}
  damper: {type: damper, ports: {a: piston, b: ground}, c: 2.0e3}
outputs:
  P1: {expr: a.p, unit: bar}
  P2: {expr: b.p, unit: bar}
  x: {expr: piston.x, unit: mm}
initial: {piston.x: "0 mm", a.p: "20 bar", b.p: "20 bar"}
"""

CSV = "t[s],u[%],Ps[bar],P1[bar],P2[bar],x[mm]\n" + "".join(
    f"{i * 0.001:.3f},{10 if i > 20 else 0},100,20,20,0\n" for i in range(100))

EXPERIMENT = """\
name: run
data: r.csv
inputs: {u: u, Ps: Ps}
outputs: {P1: P1, P2: P2, x: x}
"""


@dataclass
class Case:
    name: str
    files: dict[str, str | bytes]
    argv: list[str]
    exit: int = 3
    where: str | None = None          # a file name the message must contain
    line: bool = False                # …followed by ":<line>"
    keep: tuple[str, ...] = ()        # files that must be unchanged afterwards
    absent: tuple[str, ...] = ()      # files that must not exist afterwards
    slow: bool = False


@dataclass
class _Builder:
    cases: list[Case] = field(default_factory=list)

    def add(self, case: Case) -> None:
        assert case.name not in {c.name for c in self.cases}, case.name
        self.cases.append(case)

    def machine(self, name: str, text: str, extra: dict | None = None, exit: int = 3, line: bool = True,
                where: str = "m.yaml", **kw):
        self.add(Case(f"machine_{name}", {"m.yaml": text, **(extra or {})}, ["check", "{d}/m.yaml"], exit,
                      where, line, **kw))

    def experiment(self, name: str, exp: str | None = None, csv: str | bytes = CSV, line: bool = True,
                   where: str = "e.yaml", extra: dict | None = None, exit: int = 3, machine: str = MACHINE):
        files = {"m.yaml": machine, "e.yaml": EXPERIMENT if exp is None else exp, "r.csv": csv, **(extra or {})}
        self.add(Case(f"experiment_{name}", files,
                      ["simulate", "{d}/m.yaml", "-e", "{d}/e.yaml", "-o", "{d}/out.h5"], exit, where, line,
                      keep=("m.yaml", "e.yaml", "r.csv"), absent=("out.h5",)))


def _replace(text: str, old: str, new: str) -> str:
    assert old in text, old
    return text.replace(old, new, 1)


# -- families ------------------------------------------------------------------------------
def hostile_yaml(b: _Builder) -> None:
    bomb = "a: &a [x, x, x, x, x, x, x, x, x]\n" + "".join(
        f"{chr(98 + i)}: &{chr(98 + i)} [" + ", ".join([f"*{chr(97 + i)}"] * 9) + "]\n" for i in range(8))
    b.machine("alias_bomb_lists", bomb + MACHINE.split("\n", 1)[1].replace("name: rig\n", ""), line=True)
    b.machine("alias_bomb_in_notes", MACHINE + "notes:\n" + "".join("  " + l + "\n" for l in bomb.splitlines()))
    mbomb = "a: &a {k1: x, k2: x, k3: x, k4: x, k5: x, k6: x, k7: x, k8: x}\n" + "".join(
        f"{chr(98 + i)}: &{chr(98 + i)} {{" + ", ".join(f"k{j}: *{chr(97 + i)}" for j in range(8)) + "}\n"
        for i in range(8))
    b.machine("alias_bomb_mappings", MACHINE + "notes:\n" + "".join("  " + l + "\n" for l in mbomb.splitlines()))
    b.machine("alias_bomb_in_component", _replace(MACHINE, "components:\n", "components:\n" + "".join(
        "  " + l + "\n" for l in ("x0: &x0 {type: volume, ports: {P: a}, V: [1, 1, 1, 1, 1, 1, 1, 1, 1, 1]}",))
        + "".join(f"  x{i}: &x{i} {{type: volume, ports: {{P: a}}, V: [{', '.join([f'*x{i - 1}'] * 10)}]}}\n"
                  for i in range(1, 7))))
    b.machine("alias_bomb_in_include", _replace(MACHINE, "name: rig\n", "name: rig\ninclude: [bomb.yaml]\n"),
              {"bomb.yaml": "notes:\n" + "".join("  " + l + "\n" for l in bomb.splitlines())}, where="bomb.yaml")
    b.machine("many_aliases", MACHINE + "notes:\n  a: &a 1\n  b: [" + ", ".join(["*a"] * 1500) + "]\n")
    b.machine("deep_flow_nesting", MACHINE + "notes: " + "[" * 5000 + "]" * 5000 + "\n")
    b.machine("deep_flow_maps", MACHINE + "notes: " + "{a: " * 300 + "1" + "}" * 300 + "\n")
    b.machine("deep_block_nesting", MACHINE + "notes:\n" + "".join("  " * (i + 1) + f"k{i}:\n" for i in range(80))
              + "  " * 81 + "v: 1\n")
    b.machine("file_over_1MB", MACHINE + "notes: |\n" + "  " + "x" * 100 + "\n" * 1 + ("  " + "y" * 100 + "\n") * 11000)
    b.machine("lines_over_1MB_of_components", "components:\n" + "".join(
        f"  c{i}: {{type: volume, ports: {{P: n{i}}}, V: 1.0e-4}}\n" for i in range(25000)))
    fan = MACHINE.replace("components:\n", "templates:\n  t:\n    ports: [P]\n    components:\n"
                          + "".join(f"      c{i}: {{template: t, ports: {{P: P}}}}\n" for i in range(10))
                          + "      v: {type: volume, ports: {P: P}, V: 1.0e-4}\ncomponents:\n  big: {template: t, ports: {P: a}}\n")
    b.machine("template_self_nesting_fan_out", fan)
    b.machine("template_instantiates_itself", MACHINE.replace("components:\n", "templates:\n  t:\n    ports: [P]\n"
              "    components:\n      again: {template: t, ports: {P: P}}\ncomponents:\n  big: {template: t, ports: {P: a}}\n"))
    b.machine("templates_instantiate_each_other", MACHINE.replace("components:\n", "templates:\n"
              "  t1:\n    ports: [P]\n    components:\n      x: {template: t2, ports: {P: P}}\n"
              "  t2:\n    ports: [P]\n    components:\n      y: {template: t1, ports: {P: P}}\n"
              "components:\n  big: {template: t1, ports: {P: a}}\n"))
    wide = MACHINE.replace("components:\n", "templates:\n" + "".join(
        f"  t{k}:\n    ports: [P]\n    components:\n" + "".join(
            f"      c{i}: {{template: t{k + 1}, ports: {{P: P}}}}\n" for i in range(8)) for k in range(6))
        + "  t6:\n    ports: [P]\n    components:\n      v: {type: volume, ports: {P: P}, V: 1.0e-4}\n"
        + "components:\n  big: {template: t0, ports: {P: a}}\n")
    b.machine("templates_component_count_explodes", wide)
    files = {f"i{k}.yaml": f"include: [i{k + 1}.yaml, i{k + 1}.yaml]\n" for k in range(25)}
    files["i25.yaml"] = "notes: leaf\n"
    b.machine("include_diamond_fan_out", _replace(MACHINE, "name: rig\n", "name: rig\ninclude: [i0.yaml]\n"), files,
              where="i23.yaml")
    b.machine("include_self", _replace(MACHINE, "name: rig\n", "name: rig\ninclude: [m.yaml]\n"))
    b.machine("include_directory", _replace(MACHINE, "name: rig\n", "name: rig\ninclude: [sub]\n"),
              {"sub/x.yaml": "notes: x\n"})
    b.machine("include_not_a_string", _replace(MACHINE, "name: rig\n", "name: rig\ninclude: [{a: 1}]\n"))
    b.machine("include_binary_file", _replace(MACHINE, "name: rig\n", "name: rig\ninclude: [blob.yaml]\n"),
              {"blob.yaml": bytes(range(256)) * 4}, where="blob.yaml", line=False)
    b.machine("python_object_tag", MACHINE + "notes: !!python/object/apply:os.system ['echo hi']\n")
    b.machine("custom_tag", _replace(MACHINE, "k: 1.0e5", "k: !eval 1.0e5"))
    b.machine("binary_garbage", bytes(range(256)) * 8, line=False)
    b.machine("nul_bytes", MACHINE.replace("tank: {", "tank: \x00{"), line=False)
    b.machine("utf16_file", MACHINE.encode("utf-16"), line=False)
    b.machine("duplicate_component_from_template", MACHINE.replace("components:\n", "templates:\n  t:\n"
              "    ports: [P]\n    components:\n      valve: {type: volume, ports: {P: P}, V: 1.0e-4}\n"
              "components:\n  outer: {template: t, ports: {P: a}}\n  outer.valve: {type: volume, ports: {P: b}, V: 1.0e-4}\n"))


def non_physical(b: _Builder) -> None:
    """Every positive or bounded parameter of the base machine, with values outside its range."""
    from hydrocli.components import registry
    comps = {"valve": "valve_4_3", "cyl": "cylinder_double_rod", "load": "mass", "spring": "spring",
             "damper": "damper"}
    for comp, type_name in comps.items():
        cls = registry.get(type_name)
        for spec in cls.parameters:
            if spec.vector or spec.structural:
                continue
            bad = [".nan", ".inf", "-.inf", "1.0e300"]
            if spec.positive:
                bad += ["0", "-1.0"]
            elif spec.min is not None and spec.min >= 0:
                bad += ["-1.0"]
            for v in bad:
                tag = v.replace(".", "p").replace("-", "neg")
                b.machine(f"{comp}_{spec.name}_{tag}", with_param(MACHINE, comp, spec.name, v))
    for v in ("-1.5 GPa", "0 Pa", ".nan", ".inf", "1e300"):
        b.machine(f"fluid_beta_{v.replace(' ', '_').replace('.', 'p')}",
                  _replace(MACHINE, 'beta: "1.5 GPa"', f"beta: {_q(v)}"))
    for text, tag in (("{value: 50, free: true, bounds: [-300, 300]}", "mass_bounds_negative"),
                      ("{value: 500, free: true, bounds: [20, 300]}", "mass_start_above_bounds"),
                      ("{value: 5, free: true, bounds: [20, 300]}", "mass_start_below_bounds"),
                      ("{value: 50, free: true, bounds: [20, .inf]}", "mass_bounds_infinite"),
                      ("{value: 50, free: true, bounds: [.nan, 300]}", "mass_bounds_nan"),
                      ("{value: 50, free: true, bounds: [300, 20]}", "mass_bounds_inverted"),
                      ("{value: 50, free: yes please, bounds: [20, 300]}", "mass_free_not_boolean"),
                      ("{value: 50, free: true, bounds: [20]}", "mass_bounds_one_value"),
                      ("{value: 50, free: true, bounds: 20}", "mass_bounds_scalar"),
                      ("{value: 50, unit: bar}", "mass_unit_wrong_dimension"),
                      ("{value: 50, unit: furlong}", "mass_unit_unknown"),
                      ("{value: 50, log: maybe}", "mass_log_not_boolean"),
                      ("{vale: 50}", "mass_misspelt_value"),
                      ("true", "mass_boolean"), ("[1, 2]", "mass_list"), ('"heavy"', "mass_word"),
                      ('"50 bar"', "mass_pressure"), ('"50 kg/m"', "mass_wrong_unit"), ("{}", "mass_empty_map")):
        b.machine(tag, _replace(MACHINE, "m: {value: 50, free: true, bounds: [20, 300]}", f"m: {text}"))
    for text, tag in (('"2 bar"', "volume_in_bar"), ('"-0.2 L"', "volume_negative_litres"),
                      ("1.0e300", "volume_huge"), ('"1e3 m^3"', "volume_thousand_m3")):
        b.machine(f"cyl_V_A0_{tag}", _replace(MACHINE, "V_A0: 2.0e-4", f"V_A0: {text}"))


def with_param(text: str, comp: str, pname: str, value: str) -> str:
    """``text`` with parameter ``pname`` of component ``comp`` set to ``value`` (a YAML scalar)."""
    lines = text.splitlines(keepends=True)
    head = next(i for i, l in enumerate(lines) if l.startswith(f"  {comp}:"))
    if "{" in lines[head]:                                     # flow style: turn it into a block
        body = lines[head].split(":", 1)[1].strip()[1:-1]
        type_part, rest = body.split(",", 1)
        ports, _, params = rest.strip().partition("}, ")
        block = [f"  {comp}:\n", f"    {type_part.strip()}\n", f"    {ports.strip()}}}\n"]
        block += [f"    {kv.strip()}\n" for kv in params.split(",") if kv.strip()]
        lines[head:head + 1] = block
    end = next((i for i in range(head + 1, len(lines)) if not lines[i].startswith("    ")), len(lines))
    lines = [l for i, l in enumerate(lines) if not (head < i < end and l.startswith(f"    {pname}:"))]
    lines.insert(head + 1, f"    {pname}: {value}\n")
    return "".join(lines)


def _q(v: str) -> str:
    return f'"{v}"' if " " in v else v


def initial_states(b: _Builder) -> None:
    for state in ("a.p", "b.p", "piston.x", "piston.v"):
        for v in (".nan", ".inf", "-.inf", "1.0e400", '"nan bar"', "true", "[1]"):
            if state.endswith(".v") and v in ('"nan bar"',):
                continue
            tag = v.strip('"').replace(".", "p").replace("-", "neg").replace(" ", "_").replace("[", "").replace("]", "")
            b.machine(f"initial_{state.replace('.', '_')}_{tag}",
                      _replace(MACHINE, "initial: {piston.x: \"0 mm\", a.p: \"20 bar\", b.p: \"20 bar\"}",
                               f"initial: {{{state}: {v}}}"))
    for state, v in (("a.p", '"-5000 bar"'), ("b.p", "-1.0"), ("a.p", '"20 mm"'), ("piston.x", '"3 bar"'),
                     ("piston.x", '"1e9 km"'), ("nowhere.p", '"1 bar"'), ("a.q", "1")):
        tag = v.strip('"').replace(" ", "_").replace("-", "neg").replace(".", "p")
        b.machine(f"initial_{state.replace('.', '_')}_{tag}",
                  _replace(MACHINE, "initial: {piston.x: \"0 mm\", a.p: \"20 bar\", b.p: \"20 bar\"}",
                           f"initial: {{{state}: {v}}}"))


def outputs(b: _Builder) -> None:
    exprs = {"sqrt_two_args": "sqrt(a.p, 2)", "div_zero": "a.p/0", "exp_1000": "exp(1000)",
             "log_negative": "log(-1)", "nested_minus": "-" * 5000 + "a.p", "nested_parens": "(" * 3000 + "a.p" + ")" * 3000,
             "empty": "", "dangling_plus": "a.p +", "unknown_function": "foo(a.p)", "unknown_node": "nowhere.p",
             "unknown_quantity": "a.q", "python_code": "__import__('os').system('x')", "attribute": "a.p.real",
             "lambda": "lambda: 1", "string": "'abc'", "list": "[1, 2]", "huge_number": "1e999 * a.p",
             "pow_overflow": "10.0 ** 1000", "sqrt_negative": "sqrt(-4)", "min_no_args": "min()"}
    for tag, e in exprs.items():
        b.machine(f"output_{tag}", _replace(MACHINE, "P2: {expr: b.p, unit: bar}", f"P2: {{expr: {json.dumps(e)}, unit: bar}}"))
    for unit in ("mm", "kg", "furlong", "s", "N", "m^3", "5", "%", "bar bar", "m/s"):
        b.machine(f"output_P2_unit_{unit.replace('^', '').replace('/', '_per_').replace(' ', '_').replace('%', 'pct')}",
                  _replace(MACHINE, "P2: {expr: b.p, unit: bar}", f"P2: {{expr: b.p, unit: \"{unit}\"}}"))
    for unit in ("bar", "kg", "s"):
        b.machine(f"output_x_unit_{unit}", _replace(MACHINE, "x: {expr: piston.x, unit: mm}", f"x: {{expr: piston.x, unit: {unit}}}"))
    b.machine("output_dp_unit_kN", _replace(MACHINE, "P2: {expr: b.p, unit: bar}", "P2: {expr: a.p - b.p, unit: kN}"))
    b.machine("output_product_unit_bar", _replace(MACHINE, "P2: {expr: b.p, unit: bar}", "P2: {expr: a.p * piston.x, unit: bar}"))
    b.machine("output_not_mapping", _replace(MACHINE, "P2: {expr: b.p, unit: bar}", "P2: [b.p]"))
    b.machine("output_unknown_key", _replace(MACHINE, "P2: {expr: b.p, unit: bar}", "P2: {expr: b.p, units: bar}"))


def file_units(b: _Builder) -> None:
    for cat, unit in (("pressure", "mm"), ("pressure", "5"), ("pressure", "kg"), ("pressure", "true"),
                      ("length", "bar"), ("mass", "furlong"), ("time", "m"), ("volume", "L/min"),
                      ("flow", "L"), ("force", "kg"), ("presure", "bar"), ("pressure", "[bar]"),
                      ("pressure", "''"), ("angle", "m")):
        tag = f"{cat}_{unit}".replace("/", "_per_").replace("[", "").replace("]", "").replace("'", "q")
        b.machine(f"units_{tag}", _replace(MACHINE, "name: rig\n", f"name: rig\nunits: {{{cat}: {unit}}}\n"))
    b.machine("units_not_mapping", _replace(MACHINE, "name: rig\n", "name: rig\nunits: bar\n"))
    b.machine("input_unit_unknown", _replace(MACHINE, "Ps: {unit: bar}", "Ps: {unit: furlongz}"))
    b.machine("input_hold_unknown", _replace(MACHINE, "Ps: {unit: bar}", "Ps: {unit: bar, hold: cubic}"))


def experiments(b: _Builder) -> None:
    for header, tag in (("P1[kg]", "P1_kg"), ("P1[furlong]", "P1_furlong"), ("Ps[mm]", "Ps_mm"), ("u[bar]", "u_bar"),
                        ("x[bar]", "x_bar"), ("P2[m/s]", "P2_speed"), ("t[m]", "t_metres"), ("t[bar]", "t_bar"),
                        ("P1[]]", "P1_bracket"), ("P1[bar", "P1_unclosed")):
        col = header.split("[")[0]
        new = CSV.replace(f"{col}[{_unit_of(col)}]", header, 1)
        b.experiment(f"csv_header_{tag}", where="r.csv", csv=new)
    for spec, tag in (("{column: P1, unit: kg}", "column_unit_kg"), ("{column: P1, unit: furlong}", "column_unit_unknown"),
                      ("{column: P1, scale: '0.02 m/V'}", "scale_wrong_dimension"), ("{column: P1, scale: .nan}", "scale_nan"),
                      ("{column: P1, scale: heavy}", "scale_word"), ("{column: P1, offset: '5 mm'}", "offset_wrong_dimension"),
                      ("{column: P1, offset: .nan}", "offset_nan"), ("{column: P1, scale: .inf}", "scale_inf"),
                      ("{column: nope}", "unknown_column"), ("{column: 5}", "column_number"), ("[P1]", "list"),
                      ("{column: P1, unit: bar, extra: 1}", "unknown_key")):
        b.experiment(f"output_{tag}", _replace(EXPERIMENT, "outputs: {P1: P1,", f"outputs: {{P1: {spec},"))
    for spec, tag in (("{column: Ps, unit: mm}", "Ps_unit_mm"), ("{column: u, unit: N}", "u_unit_newton"),
                      ("{step: {at: .nan, to: 5}}", "step_at_nan"), ("{step: {at: 0.01, to: .inf}}", "step_to_inf"),
                      ("{step: {at: '1 bar', to: 5}}", "step_at_pressure"), ("{sine: {amplitude: 1, frequency: .inf}}", "sine_inf"),
                      ("{sine: {amplitude: .nan, frequency: 5 Hz}}", "sine_amplitude_nan"), ("{ramp: {}}", "ramp_empty"),
                      ("{chirp: {amplitude: 1, f0: 1 Hz, f1: .inf, duration: 1 s}}", "chirp_inf"),
                      ("{table: {t: [0, 1], y: [1]}}", "table_ragged"), ("{table: {t: [1, 0], y: [1, 2]}}", "table_time_backwards"),
                      ("{foo: 1}", "unknown_signal")):
        b.experiment(f"input_{tag}", _replace(EXPERIMENT, "inputs: {u: u, Ps: Ps}", f"inputs: {{u: u, Ps: {spec}}}"
                                              if tag[:2] != "u_" else f"inputs: {{u: {spec}, Ps: Ps}}"))
    b.experiment("input_unknown_machine_input", _replace(EXPERIMENT, "inputs: {u: u, Ps: Ps}", "inputs: {u: u, Ps: Ps, Fext: u}"))
    b.experiment("output_unknown_machine_output", _replace(EXPERIMENT, "outputs: {P1: P1,", "outputs: {Q9: P1, P1: P1,"))
    for key, value, tag in (("weights", "{P1: heavy}", "weights_word"), ("weights", "[P1]", "weights_list"),
                            ("weights", "{P1: -1}", "weights_negative"), ("weights", "{P1: .nan}", "weights_nan"),
                            ("weights", "{Q: 1}", "weights_unknown_output"), ("mask", "[P1]", "mask_list"),
                            ("mask", "{P1: 5}", "mask_number"), ("mask", "{P1: {above: heavy}}", "mask_above_word"),
                            ("mask", "{P1: {times: [[.nan, 1]]}}", "mask_times_nan"), ("mask", "{Q: {nan: ignore}}", "mask_unknown_output"),
                            ("fit", "5", "fit_number"), ("fit", "[nope]", "fit_unknown"), ("fit", "{a: 1}", "fit_mapping"),
                            ("fit", "[]", "fit_empty"), ("window", "5", "window_number"), ("window", "[a, b]", "window_words"),
                            ("window", "[0.08 s, 0.02 s]", "window_inverted"), ("window", "[.nan, 0.05]", "window_nan"),
                            ("window", "[5 s, 6 s]", "window_outside_data"), ("window", "[0 bar, 1 bar]", "window_pressure"),
                            ("initial", "5", "initial_number"), ("initial", "guess", "initial_word"),
                            ("initial", "{a.p: .nan}", "initial_state_nan"), ("initial", "{a.p: '-5000 bar'}", "initial_negative_pressure"),
                            ("initial", "{nowhere.p: 1}", "initial_unknown_state"), ("settle", "-1 s", "settle_negative"),
                            ("preprocess", "5", "preprocess_number"), ("preprocess", "{lowpass: {cutoff: -5 Hz}}", "lowpass_negative"),
                            ("preprocess", "{lowpass: {cutoff: .nan}}", "lowpass_nan"), ("preprocess", "{lowpass: {cutoff: 900 Hz}}", "lowpass_above_nyquist"),
                            ("preprocess", "{lowpass: {order: -2, cutoff: 10 Hz}}", "lowpass_order_negative"),
                            ("preprocess", "{resample: 0 Hz}", "resample_zero"), ("preprocess", "{resample: -1 kHz}", "resample_negative"),
                            ("preprocess", "{resample: .nan}", "resample_nan"), ("preprocess", "{resample: 1e12 Hz}", "resample_huge"),
                            ("preprocess", "{remove_offset: {P1: {samples: -1}}}", "offset_samples_negative"),
                            ("preprocess", "{remove_offset: {P1: heavy}}", "offset_word"), ("preprocess", "{smooth: 1}", "unknown_step"),
                            ("thresholds", "{P1: -5}", "threshold_negative"), ("thresholds", "{P1: heavy}", "threshold_word"),
                            ("thresholds", "{Q: 5}", "threshold_unknown_output"), ("time", "{column: t, unit: bar}", "time_unit_pressure"),
                            ("name", "[a]", "name_list")):
        b.experiment(f"{tag}", EXPERIMENT + f"{key}: {value}\n")
    b.experiment("time_unknown_column", EXPERIMENT + "time: nope\n", where="r.csv")
    designed = "name: designed\ninputs: {u: {step: {at: 0.01 s, to: 10}}, Ps: {step: {at: 0, to: 100}}}\n"
    for dur, rate, tag in (("0 s", "1 kHz", "duration_zero"), ("-1 s", "1 kHz", "duration_negative"),
                           (".nan", "1 kHz", "duration_nan"), (".inf", "1 kHz", "duration_inf"),
                           ("1e6 s", "1 kHz", "duration_huge"), ("1 s", "0 Hz", "rate_zero"), ("1 s", "-1 kHz", "rate_negative"),
                           ("1 s", ".nan", "rate_nan"), ("1 s", "1e12 Hz", "rate_huge"), ("5 m", "1 kHz", "duration_metres"),
                           ("1 s", "5 bar", "rate_pressure"), ("heavy", "1 kHz", "duration_word")):
        b.experiment(f"designed_{tag}", designed + f"duration: {dur}\nrate: {rate}\n")
    b.experiment("designed_no_duration", designed)
    b.experiment("alias_bomb", EXPERIMENT + "description: &a [x, x, x, x, x, x, x, x, x]\nnotes:\n" + "".join(
        f"  {chr(98 + i)}: &{chr(98 + i)} [" + ", ".join([f"*{chr(97 + i) if i else 'a'}"] * 9) + "]\n" for i in range(8)))
    b.experiment("yaml_over_1MB", EXPERIMENT + "description: '" + "x" * 1_100_000 + "'\n", line=True)
    b.experiment("experiments_empty_list", EXPERIMENT + "experiments: []\n")
    b.experiment("experiments_not_mappings", EXPERIMENT + "experiments: [1, 2]\n")
    b.experiment("data_missing", _replace(EXPERIMENT, "data: r.csv", "data: nope.csv"))
    b.experiment("data_directory", _replace(EXPERIMENT, "data: r.csv", "data: sub"), extra={"sub/x": "x"},
                 where="sub", line=False)
    b.experiment("data_unknown_format", _replace(EXPERIMENT, "data: r.csv", "data: r.txt"), extra={"r.txt": CSV},
                 where="r.txt", line=False)
    b.experiment("data_number", _replace(EXPERIMENT, "data: r.csv", "data: 5"))
    for bad, tag in ((CSV.replace("0.005,", "0.004,", 1), "time_duplicate"), (CSV.replace(",100,", ",nan,", 1), "nan_input"),
                     (CSV.replace(",100,", ",inf,", 1), "inf_input"), (CSV.replace(",100,", ",1e400,", 1), "overflow_input"),
                     (CSV.replace(",100,", ",abc,", 1), "word"), (CSV.replace(",100,", ",100,7,", 1), "ragged"),
                     (CSV.split("\n")[0] + "\n", "header_only"), ("", "empty"), ("\x00\x01\x02", "binary"),
                     (CSV.replace("t[s]", "t[s],t[s]", 1), "duplicate_header")):
        b.experiment(f"csv_{tag}", where="r.csv", csv=bad, line=tag not in ("empty", "binary", "header_only"))


def _unit_of(col: str) -> str:
    return {"t": "s", "u": "%", "Ps": "bar", "P1": "bar", "P2": "bar", "x": "mm"}[col]


def hdf5_recordings(b: _Builder) -> None:
    import h5py
    import numpy as np

    def h5(units: dict[str, str], nan: bool = False) -> bytes:
        buf = io.BytesIO()
        t = np.arange(100) * 1e-3
        with h5py.File(buf, "w") as h:
            for name, unit in units.items():
                data = t if name == "t" else np.full(100, 20.0)
                if nan and name == "P1":
                    data = data.copy()
                    data[5] = np.nan
                h.create_dataset(name, data=data).attrs["unit"] = unit
        return buf.getvalue()

    ok = {"t": "s", "u": "%", "Ps": "bar", "P1": "bar", "P2": "bar", "x": "mm"}
    exp = _replace(EXPERIMENT, "data: r.csv", "data: r.h5")
    for col, unit in (("P1", "kg"), ("P1", "furlong"), ("Ps", "mm"), ("t", "m"), ("x", "bar"), ("u", "N")):
        b.experiment(f"hdf5_{col}_unit_{unit}", exp, where="r.h5", line=False, extra={"r.h5": h5({**ok, col: unit})})
    b.experiment("hdf5_nan_sample", exp, where="r.h5", line=False, extra={"r.h5": h5(ok, nan=True)})
    b.experiment("hdf5_not_hdf5", exp, where="r.h5", line=False, extra={"r.h5": b"not an hdf5 file" * 10})
    b.experiment("hdf5_no_time", exp, where="r.h5", line=False, extra={"r.h5": h5({k: v for k, v in ok.items() if k != "t"})})


def output_paths(b: _Builder) -> None:
    base = {"m.yaml": MACHINE, "e.yaml": EXPERIMENT, "r.csv": CSV}
    keep = ("m.yaml", "e.yaml", "r.csv")
    sim = ["simulate", "{d}/m.yaml", "-e", "{d}/e.yaml", "-o"]
    for target in ("m.yaml", "e.yaml", "r.csv"):
        b.add(Case(f"output_simulate_over_{target.replace('.', '_')}", base, sim + ["{d}/" + target], 2, target, keep=keep))
    b.add(Case("output_simulate_over_direct_recording", base, ["simulate", "{d}/m.yaml", "-e", "{d}/r.csv", "-o", "{d}/r.csv"],
               2, "r.csv", keep=keep))
    b.add(Case("output_simulate_over_symlink_to_machine", base, sim + ["{d}/link.h5"], 2, "link.h5", keep=keep))
    b.add(Case("output_simulate_into_directory", {**base, "dir/x": ""}, sim + ["{d}/dir"], 2, "dir", keep=keep))
    b.add(Case("output_simulate_to_device", base, sim + ["/dev/null"], 2, "/dev/null", keep=keep))
    b.add(Case("output_simulate_parent_is_file", base, sim + ["{d}/m.yaml/out.h5"], 2, "m.yaml", keep=keep))
    b.add(Case("output_identify_over_machine", base, ["identify", "{d}/m.yaml", "-e", "{d}/e.yaml", "-o", "{d}/m.yaml"],
               2, "m.yaml", keep=keep))
    b.add(Case("output_identify_results_over_recording", base, ["identify", "{d}/m.yaml", "-e", "{d}/e.yaml", "-o",
               "{d}/id.yaml", "--results", "{d}/r.csv"], 2, "r.csv", keep=keep, absent=("id.yaml",)))
    b.add(Case("output_identify_over_experiment", base, ["identify", "{d}/m.yaml", "-e", "{d}/e.yaml", "-o", "{d}/e.yaml"],
               2, "e.yaml", keep=keep))
    b.add(Case("output_report_over_its_input", {**base, "res.h5": b"x"}, ["report", "{d}/res.h5", "-o", "{d}/res.h5"],
               2, "res.h5", keep=keep + ("res.h5",)))
    b.add(Case("output_validate_junit_over_machine", base, ["validate", "{d}/m.yaml", "-e", "{d}/e.yaml", "--junit",
               "{d}/m.yaml"], 2, "m.yaml", keep=keep))
    b.add(Case("output_validate_markdown_over_recording", base, ["validate", "{d}/m.yaml", "-e", "{d}/e.yaml",
               "--markdown", "{d}/r.csv"], 2, "r.csv", keep=keep))
    b.add(Case("output_diagnose_into_existing_file", {**base, "diag": "keep me"}, ["diagnose", "{d}/m.yaml", "--train",
               "{d}/e.yaml", "--validate", "{d}/e.yaml", "-o", "{d}/diag"], 2, "diag", keep=keep + ("diag",)))
    b.add(Case("output_diagnose_json_over_input", {**base, "out/diagnosis.json": "{}"}, ["diagnose", "{d}/m.yaml",
               "--train", "{d}/out/diagnosis.json", "--validate", "{d}/e.yaml", "-o", "{d}/out"], 2, "diagnosis.json",
               keep=keep + ("out/diagnosis.json",)))
    b.add(Case("output_schema_into_directory", {"dir/x": ""}, ["schema", "-o", "{d}/dir"], 2, "dir"))


def usage(b: _Builder) -> None:
    base = {"m.yaml": MACHINE, "e.yaml": EXPERIMENT, "r.csv": CSV}
    sim = ["simulate", "{d}/m.yaml", "-e", "{d}/e.yaml", "-o", "{d}/out.h5"]
    ident = ["identify", "{d}/m.yaml", "-e", "{d}/e.yaml", "-o", "{d}/id.yaml"]
    for tag, extra in (("set_no_value", ["--set", "valve.tau"]), ("set_empty", ["--set", "=1"]),
                       ("set_unknown_component", ["--set", "valv.tau=1"]), ("set_unknown_param", ["--set", "valve.tauu=1"]),
                       ("set_wrong_unit", ["--set", "valve.tau=5 bar"]), ("set_negative_mass", ["--set", "load.m=-5"]),
                       ("set_nan", ["--set", "load.m=nan"]), ("backend_fortran", ["--backend", "fortran"]),
                       ("rtol_zero", ["--rtol", "0"]), ("rtol_negative", ["--rtol", "-1e-6"]), ("rtol_nan", ["--rtol", "nan"]),
                       ("rtol_one", ["--rtol", "1"]), ("rtol_word", ["--rtol", "tight"]), ("unknown_option", ["--fast"])):
        b.add(Case(f"usage_simulate_{tag}", base, sim + extra, 2, absent=("out.h5",)))
    for tag, extra in (("method_lm", ["--method", "lm"]), ("cost_foo", ["--cost", "foo"]), ("mode_x", ["--mode", "x"]),
                       ("max_evals_zero", ["--max-evals", "0"]), ("max_evals_negative", ["--max-evals", "-5"]),
                       ("workers_zero", ["--workers", "0"]), ("jobs_zero", ["--jobs", "0"]), ("rtol_zero", ["--rtol", "0"]),
                       ("set_no_value", ["--set", "valve.tau"])):
        b.add(Case(f"usage_identify_{tag}", base, ident + extra, 2, absent=("id.yaml",)))
    b.add(Case("usage_identify_no_out", base, ident[:-2], 2))
    masked = {**base, "e.yaml": EXPERIMENT + "mask: {all: {times: [[0 s, 1 s]]}}\n"}
    b.add(Case("experiment_identify_every_sample_masked", masked, ident, 3, "e.yaml", keep=("m.yaml",), absent=("id.yaml",)))
    b.add(Case("experiment_identify_fit_output_all_nan", {**base, "e.yaml": EXPERIMENT + "fit: [P1]\nmask: {P1: {above: 0 bar}}\n"},
               ident, 3, "e.yaml", absent=("id.yaml",)))
    b.add(Case("usage_identify_two_modes", {**base, "s.yaml": "stages: []\n"}, ident + ["--stages", "{d}/s.yaml"], 2))
    b.add(Case("usage_identify_nothing_free", {**base, "m.yaml": MACHINE.replace("free: true", "free: false")}, ident, 2))
    for name in ("cylinder_doble", "valve43", "../etc/passwd"):
        b.add(Case(f"usage_components_{name.strip('./').replace('/', '_') or 'empty'}", {}, ["components", name], 2))
    b.add(Case("usage_check_set_bad", base, ["check", "{d}/m.yaml", "--set", "valve.tau"], 2))
    b.add(Case("usage_validate_backend", base, ["validate", "{d}/m.yaml", "-e", "{d}/e.yaml", "--backend", "fortran"], 2))
    b.add(Case("usage_diagnose_jobs_zero", base, ["diagnose", "{d}/m.yaml", "--train", "{d}/e.yaml", "--validate",
               "{d}/e.yaml", "--jobs", "0"], 2))
    b.add(Case("usage_debug_after_command_unknown_option", base, ["check", "{d}/m.yaml", "--debug", "--nope"], 2))


def all_cases() -> list[Case]:
    b = _Builder()
    for family in (hostile_yaml, non_physical, initial_states, outputs, file_units, experiments, hdf5_recordings,
                   output_paths, usage):
        family(b)
    return b.cases


def materialise(case: Case, folder: Path) -> list[str]:
    """Write the case's files into ``folder``; return its command line."""
    import os
    folder.mkdir(parents=True, exist_ok=True)
    for rel, content in case.files.items():
        p = folder / rel
        p.parent.mkdir(parents=True, exist_ok=True)
        if isinstance(content, bytes):
            p.write_bytes(content)
        else:
            p.write_text(content, encoding="utf-8")
    if case.name == "output_simulate_over_symlink_to_machine":
        os.symlink(folder / "m.yaml", folder / "link.h5")
    return [a.replace("{d}", str(folder)) for a in case.argv]


if __name__ == "__main__":  # pragma: no cover
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "bad_corpus")
    cases = all_cases()
    for c in cases:
        materialise(c, out / c.name)
    (out / "manifest.json").write_text(json.dumps([{"name": c.name, "argv": c.argv, "exit": c.exit, "where": c.where,
                                                    "line": c.line} for c in cases], indent=1))
    print(f"{len(cases)} cases → {out}")
