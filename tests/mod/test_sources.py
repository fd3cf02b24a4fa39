"""The NMODL sources as NEURON writes its own: a TITLE in every file, the file named after its mechanism (where the
registration order allows), and each equation written once: the fused mechanisms INCLUDE the modules' .inc files
instead of restating them, and the two fused Kim units share one .inc file."""

import re

from neuromuscle.model import mechanisms

#: Files named for the order NEURON must advance them in (Module 1, 2, 3; the muscle after what drives or reads
#: it), not after their mechanism.
ORDERED = {"kim_m1_calcium.mod": "KimCa", "kim_m2_activation.mod": "KimAct", "kim_m3_force.mod": "KimForce",
           "kim_unit.mod": "KimUnit"}

#: The fused unit for the fixed step alone, registered where KimUnit is.
FIXED_UNIT = {"kim_unit_fixed.mod": "KimUnitFixed"}

#: The benchmark of the published integration scheme: the same equations written the authors' way on purpose.
INDEPENDENT = {"KimPublished.mod"}


def _mods():
    return [f for f in mechanisms.mod_files() if f.suffix == ".mod"]


def _mechanism(text):
    return re.search(r"^\s*(?:SUFFIX|POINT_PROCESS|ARTIFICIAL_CELL)\s+(\w+)", text, re.M).group(1)


def test_every_mod_file_starts_with_a_title():
    for f in _mods():
        first = f.read_text().splitlines()[0]
        assert re.match(r"TITLE \S.{10,}", first), f.name


def test_each_file_is_named_after_its_mechanism():
    for f in _mods():
        name = _mechanism(f.read_text())
        assert {**ORDERED, **FIXED_UNIT}.get(f.name, f.stem) == name, f"{f.name} defines {name}"


def test_the_modules_and_what_they_read_register_in_order_in_any_locale():
    """nrnivmodl registers files in name order (the package builds in the C locale; a hoc user's locale may sort
    case-insensitively): Module 1 before 2 before 3, and the extensions and Hatze's excitation, which feed the
    modules' ports and KimForce, before them; the fused KimUnit where the three are, relative to every other
    mechanism (so what drives or reads the muscle sees the same step of it in both forms)."""
    names = [f.name for f in _mods()]
    for order in (sorted(names), sorted(names, key=str.lower)):
        pos = {n: order.index(n) for n in names}
        m1, m2, m3, fused = (pos[n] for n in ORDERED)
        assert m1 < m2 < m3
        feeders = [n for n in names if n.startswith(("Ext", "Hatze"))]
        assert feeders and all(pos[n] < m1 and pos[n] < fused for n in feeders)
        others = [n for n in names if n not in ORDERED and n not in FIXED_UNIT]
        for unit in (fused, *(pos[n] for n in FIXED_UNIT)):
            assert all((pos[n] < m1) == (pos[n] < unit) and (pos[n] < m3) == (pos[n] < unit) for n in others)


def _equations(text):
    """The file's assignments that compute something (an operator or a call on the right), comments, parameter
    defaults and state-derivative lines (the form a state is handed to the integrator in) left out."""
    text = re.sub(r"COMMENT.*?ENDCOMMENT", "", text, flags=re.S)
    out = []
    for line in text.splitlines():
        code = re.sub(r"\s+", "", line.split(":")[0])
        m = re.match(r"^[A-Za-z_]\w*=(.+)$", code)
        if m and re.search(r"[-+*/^(]", m.group(1)) and not re.fullmatch(r"[-+0-9.e]+\([^)]*\)", m.group(1)):
            out.append(code)
    return out


def test_the_fixed_step_only_mechanisms_are_the_fixed_files():
    """Every *_fixed.mod is a fixed-step form the Simulator refuses under CVODE (by POINT_PROCESS or density)."""
    fixed = {_mechanism(f.read_text()) for f in _mods() if f.stem.endswith("_fixed")}
    assert fixed == set(mechanisms.fixed_step_only_mechanisms()) | set(mechanisms.FIXED_STEP_ONLY_CHANNELS)
    assert fixed == {"KimUnitFixed", "mn_soma_fixed", "mn_pic_fixed"}


def test_no_equation_is_written_twice():
    """No run of three consecutive computing statements appears in two files: a fused mechanism that restated its
    modules (KimUnit, mn_soma, mn_pic) would fail here."""
    seen: dict[tuple[str, ...], str] = {}
    for f in mechanisms.mod_files():
        if f.name in INDEPENDENT:
            continue
        eqs = _equations(f.read_text())
        for i in range(len(eqs) - 2):
            run = tuple(eqs[i:i + 3])
            assert seen.setdefault(run, f.name) == f.name, f"{f.name} restates {seen[run]}: {run}"


def test_the_fused_mechanisms_include_their_modules_equations():
    includes = {f.name: set(re.findall(r'^INCLUDE "([\w.]+)"', f.read_text(), re.M)) for f in _mods()}
    # fixed_step.inc: the step count every mechanism that advances its own states shares (secondorder)
    # both fused units: their declarations, initial state and fixed step once, in kim_unit.inc
    assert includes["kim_unit.mod"] == includes["kim_unit_fixed.mod"] == {"kim_unit.inc"}
    shared = set(re.findall(r'^INCLUDE "([\w.]+)"', (mechanisms.mod_dir() / "kim_unit.inc").read_text(), re.M))
    assert shared == {"kim_m1_calcium.inc", "kim_m2_activation.inc", "kim_m3_force.inc", "fixed_step.inc"}
    # the fused channels and their fixed-step forms: one .inc each; mn_ohmic.inc: the leak and the synaptic
    # conductance the fused cell carries instead of pas and mn_syn
    inc = {name: set(re.findall(r'^INCLUDE "([\w.]+)"', (mechanisms.mod_dir() / f"{name}.inc").read_text(), re.M))
           for name in ("mn_soma", "mn_pic")}
    for name in ("mn_soma", "mn_pic"):
        assert includes[f"{name}.mod"] == includes[f"{name}_fixed.mod"] == {f"{name}.inc"}
    assert inc["mn_soma"] == {"mn_naf.inc", "mn_kdr.inc", "mn_can.inc", "mn_cadyn.inc", "mn_kca.inc",
                              "mn_ohmic.inc", "fixed_step.inc"}
    assert inc["mn_pic"] == {"mn_cal.inc", "mn_ohmic.inc", "fixed_step.inc"}
    assert "mn_ohmic.inc" in includes["mn_syn.mod"]
    for advancing in ("kim_m1_calcium", "kim_m2_activation", "kim_m3_force", "HatzeExc", "HatzeMTC"):
        assert "fixed_step.inc" in includes[f"{advancing}.mod"], advancing
    for module in ("kim_m1_calcium", "kim_m2_activation", "kim_m3_force", "mn_naf", "mn_kdr", "mn_can", "mn_cadyn",
                   "mn_kca", "mn_cal"):
        assert f"{module}.inc" in includes[f"{module}.mod"], module
