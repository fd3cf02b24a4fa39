"""Side by side with the authors' published NEURON code (ModelDB 266732; 267184 holds the same mechanisms),
measured on the machine it runs on.  The published code is not part of this repository.

Run from the repository root:
    python docs/validation/compare_published.py PATH [--units 20] [--duration-ms 5000] [--no-reference]
PATH: a folder holding the authors' module1_2.mod, module3.mod and Xm.mod, or a checkout of ModelDB 266732
(its fig*/ folders hold identical copies; the first is used).  The mod files are copied into a temporary folder,
changed only where NEURON >= 9 requires it (a FUNCTION name listed in RANGE is dropped from the list, as the
ModelDB maintainers did in 267184), and compiled there with nrnivmodl; input files the published INITIAL block
reads (267184's co-simulation variant) are created holding 0 (no earlier spikes, the length from the clamp).

Three protocols, each with --units identically driven units in one process, --duration-ms at dt 0.025 ms, CT09
at -8 mm (the published code fixes its reference lengths and the phi breakpoint at -8 mm): a twitch at 500 ms,
10 Hz and 40 Hz from 500 ms to the end.  The published units run in a process of their own per protocol
(published_worker.py: two mechanism libraries in one NEURON process must not clash in any name, and a fresh
process keeps the published code's state and timing apart); this package's units (MuscleUnit + Simulator)
receive the spike times the published code stored.  Every published parameter with a CT09 counterpart is set to
the CT09 value.  Prints Markdown: wall and CPU time per simulated unit-second, twitch and plateau of the first
unit of each against each other (and SciPy's, same spike times), and the spread across the identically driven
units.  Units: N, ms, s.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import platform
import re
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from neuromuscle import MuscleUnit, ParameterSet, Simulator, load_parameters
from neuromuscle.analysis.metrics import plateau, twitch_metrics
from neuromuscle.protocols import constant_rate
from neuromuscle.reference import reference_simulate
from neuromuscle.reports.markdown import table

WORKER = Path(__file__).with_name("published_worker.py")
DT_MS = 0.025
LENGTH_MM = -8.0
ONSET_MS = 500.0
PLATEAU_MS = (1300.0, 1500.0)  # the accuracy table's window
PROTOCOLS = {"twitch": None, "10 Hz": 10.0, "40 Hz": 40.0}
MOD_FILES = ("module1_2.mod", "module3.mod", "Xm.mod")
#: published name -> CT09 name: RANGE parameters of CaSP (Modules 1-2) and fHill (Module 3), then GLOBALs
PUBLISHED_RANGE = {
    "CaSP": {"k1": "K1", "k2": "K2", "k3": "K3", "k4": "K4", "k5i": "K5i", "k6i": "K6i", "k": "K",
             "Rmax": "Rmax", "Umax": "Umax", "t1": "tau1", "t2": "tau2", "phi1": "phi1", "phi2": "phi2",
             "phi3": "phi3", "phi4": "phi4", "c1": "C1", "c2": "C2", "c3": "C3", "c4": "C4", "c5": "C5",
             "alpha": "alpha"},
    "fHill": {"a0": "a0", "b0": "b0", "c0": "c0", "d0": "d0", "p0": "P0", "g1": "g1", "g2": "g2", "Kse": "KSE"},
}
PUBLISHED_GLOBALS = {"CS0_CaSP": "CS0", "B0_CaSP": "B0", "T0_CaSP": "T0"}


def find_published(path: Path) -> Path:
    """The folder holding MOD_FILES: ``path`` itself or its first subfolder (by name) that does."""
    if not path.is_dir():
        raise SystemExit(f"{path} is not a folder (get ModelDB 266732: https://github.com/ModelDBRepository/266732)")
    for folder in [path] + sorted(p for p in path.iterdir() if p.is_dir()):
        if all((folder / f).is_file() for f in MOD_FILES):
            return folder
    raise SystemExit(f"{path}: no folder with {', '.join(MOD_FILES)} here or one level down "
                     "(get ModelDB 266732: https://github.com/ModelDBRepository/266732)")


def neuron9_fix(text: str) -> tuple[str, list[str]]:
    """Drop from RANGE statements every name the file also declares as FUNCTION (NEURON >= 9 refuses a name
    used as both); returns the text and the dropped names."""
    functions = set(re.findall(r"^\s*FUNCTION\s+(\w+)", text, flags=re.M))
    dropped: list[str] = []

    def fix(m: re.Match) -> str:
        names = [n.strip() for n in m.group(2).split(",")]
        dropped.extend(n for n in names if n in functions)
        return m.group(1) + ", ".join(n for n in names if n not in functions)

    return re.sub(r"^(\s*RANGE\s+)([\w\s,]+?)\s*$", fix, text, flags=re.M), dropped


def compile_published(folder: Path, work: Path) -> tuple[Path, list[str], list[str]]:
    """Copy, fix and compile the published mod files under ``work``; returns the library, the changes made and
    the input files the published INITIAL reads (created, holding 0, in the worker's folder)."""
    build = work / "mod"
    build.mkdir()
    changes, inputs = [], []
    for name in MOD_FILES:
        text, dropped = neuron9_fix((folder / name).read_text(errors="replace"))
        if dropped:
            changes.append(f"{name}: {', '.join(dropped)} dropped from RANGE")
        inputs += re.findall(r'fopen\("([^"]+)",\s*"r', text)
        (build / name).write_text(text)
    nrnivmodl = shutil.which("nrnivmodl", path=f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}")
    if nrnivmodl is None:
        raise SystemExit("nrnivmodl not found: install NEURON (pip install neuron)")
    done = subprocess.run([nrnivmodl], cwd=build, capture_output=True, text=True)
    libs = sorted(build.glob("*/libnrnmech.*"))
    if done.returncode != 0 or not libs:
        raise SystemExit(f"nrnivmodl failed on the published mod files:\n{done.stdout[-3000:]}{done.stderr[-3000:]}")
    return libs[0], changes, sorted(set(inputs))


def pulses(protocol: str, duration_ms: float) -> np.ndarray:
    """Pulse onsets (ms): one at 500 ms for the twitch, else the rate from 500 ms to the end."""
    rate = PROTOCOLS[protocol]
    if rate is None:
        return np.array([ONSET_MS])
    return constant_rate(rate, duration_ms - ONSET_MS, start_ms=ONSET_MS)


@dataclass
class Run:
    """One protocol on n identically driven units: t (ms), force (N, units x samples), wall and CPU time of the
    integration (s)."""

    t_ms: np.ndarray
    force_N: np.ndarray
    wall_s: float
    cpu_s: float
    duration_ms: float

    def per_unit_second(self, seconds: float) -> float:
        """``seconds`` (s) per simulated unit-second."""
        return seconds / (self.force_N.shape[0] * self.duration_ms / 1000.0)

    def measures(self, protocol: str, stimulus_ms: float) -> dict[str, np.ndarray]:
        """Per unit: twitch peak (N), time to peak and half-relaxation (ms) for the twitch; else the plateau
        mean over PLATEAU_MS (N) and the largest force of the run (N)."""
        if protocol == "twitch":
            m = [twitch_metrics(self.t_ms, f, stimulus_ms) for f in self.force_N]
            return {"twitch peak (N)": np.array([x.peak_N for x in m]),
                    "twitch time to peak (ms)": np.array([x.time_to_peak_ms for x in m]),
                    "twitch half-relaxation (ms)": np.array([x.half_relaxation_ms for x in m])}
        return {f"{protocol} plateau, mean {PLATEAU_MS[0]:g}-{PLATEAU_MS[1]:g} ms (N)":
                np.array([plateau(self.t_ms, f, *PLATEAU_MS)[0] for f in self.force_N]),
                f"{protocol} largest force of the run (N)": self.force_N.max(axis=1)}


@dataclass
class Protocol:
    """Both runs of one protocol, the spike times (ms) and the published per-unit release ratio (1 = correct)."""

    package: Run
    published: Run
    spikes_ms: np.ndarray
    release_over_own: np.ndarray


def run_published(library: Path, inputs: list[str], work: Path, protocol: str, units: int,
                  duration_ms: float) -> tuple[Run, np.ndarray, np.ndarray, dict]:
    """The published units in a subprocess; returns the run, the spike times it stored (ms), the release ratio
    of each unit and the published defaults of the parameters set."""
    p = load_parameters("CT09")
    rundir = Path(tempfile.mkdtemp(dir=work))
    for name in inputs:
        (rundir / name).write_text("0\n")
    spec = {"library": str(library), "units": units, "duration_ms": duration_ms, "dt_ms": DT_MS,
            "length_mm": LENGTH_MM, "pulses_ms": pulses(protocol, duration_ms).tolist(),
            "range": {m: {k: p[v] for k, v in names.items()} for m, names in PUBLISHED_RANGE.items()},
            "globals": {k: p[v] for k, v in PUBLISHED_GLOBALS.items()}}
    (rundir / "spec.json").write_text(json.dumps(spec))
    done = subprocess.run([sys.executable, str(WORKER), "spec.json", "out.npz"], cwd=rundir, capture_output=True,
                          text=True)
    if done.returncode != 0:
        raise SystemExit(f"the published run ({protocol}) failed:\n{done.stderr[-3000:]}")
    out = np.load(rundir / "out.npz")
    spikes = out["spikes_ms"]
    if not np.all(out["spike_counts"] == spikes.size) or spikes.size != len(spec["pulses_ms"]):
        raise SystemExit(f"published {protocol}: spike counts {out['spike_counts']} for {len(spec['pulses_ms'])} "
                         "pulses")
    run = Run(out["t_ms"], out["force_N"], float(out["wall_s"]), float(out["cpu_s"]), duration_ms)
    shutil.rmtree(rundir)  # 267184's variant writes two text files every step
    return run, spikes, out["release_over_own"], json.loads(str(out["defaults"]))


def run_package(spikes_ms: np.ndarray, units: int, duration_ms: float) -> Run:
    """``units`` MuscleUnits (CT09, -8 mm) in this process, each receiving spikes_ms (ms)."""
    from neuron import h

    p = load_parameters("CT09")
    # the published code starts from the initial state of Kim et al. 2015: so does the package here
    made = [MuscleUnit(p, name=f"pkg{i}", initial_state="published") for i in range(units)]
    try:
        forces = []
        for u in made:
            u.length.xm = LENGTH_MM
            u.add_spike_times(spikes_ms)
            forces.append(h.Vector().record(u.ref("force.F")))
        tvec = h.Vector().record(h._ref_t)
        start_cpu = time.process_time()
        wall = Simulator(method="fixed", dt_ms=DT_MS).run(duration_ms, units=made)
        cpu = time.process_time() - start_cpu
        if any(int(u["ca"].obj.nspike) != spikes_ms.size for u in made):
            raise SystemExit("package: a unit did not receive every spike")
        return Run(np.array(tvec), np.array([np.array(f) for f in forces]), wall, cpu, duration_ms)
    finally:
        for u in made:
            u.destroy()


def _pct(a: float, b: float) -> str:
    return f"{100 * (a / b - 1):+.2g} %"


def _range(values: np.ndarray, digits: int = 4) -> str:
    return f"{values.min():.{digits}f} - {values.max():.{digits}f}"


def compare(published: Path, units: int, duration_ms: float, reference: bool) -> str:
    """Run everything and return the Markdown block pasted into docs/validation/published.md."""
    if duration_ms < PLATEAU_MS[1]:
        raise SystemExit(f"--duration-ms must be at least {PLATEAU_MS[1]:g} ms (the plateau window ends there)")
    folder = find_published(published)
    load = f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores at the start"
    with tempfile.TemporaryDirectory(prefix="published-") as tmp:
        library, changes, inputs = compile_published(folder, Path(tmp))
        runs = {}
        for name in PROTOCOLS:
            pub, spikes, ratio, defaults = run_published(library, inputs, Path(tmp), name, units, duration_ms)
            runs[name] = Protocol(run_package(spikes, units, duration_ms), pub, spikes, ratio)
    p = load_parameters("CT09")
    differing = {k: v for k, v in defaults.items() if v != p[_ct09_name(k)]}
    lines = [f"Published code: {folder} (module1_2.mod sha256 {_digest(folder / MOD_FILES[0])}); changes to the "
             f"copies: {'; '.join(changes) or 'none'}; input files created: {', '.join(inputs) or 'none'}; "
             f"published defaults differing from CT09: {differing or 'none'}.",
             f"{_versions()}; {load}; {units} units per process, {duration_ms:g} ms at dt {DT_MS} ms, CT09 at "
             f"{LENGTH_MM:g} mm; spike times as the published code stored them: twitch "
             f"{runs['twitch'].spikes_ms[0]:g} ms, trains from {runs['10 Hz'].spikes_ms[0]:g} ms.", ""]
    lines += table(["s per simulated unit-second", "package wall", "published wall", "published / package",
                    "package CPU", "published CPU", "published / package (CPU)"],
                   [_speed_row(name, pr) for name, pr in runs.items()]) + [""]
    lines += table(["protocol", "largest gap between the first units' traces before the first spike, and "
                    "from it on (% of the published peak)",
                    f"published release / its own eq 3, units 1..{units} (last step)"],
                   [_gap_row(name, pr) for name, pr in runs.items()]) + [""]
    rows, spread = [], []
    for name, pr in runs.items():
        mine = pr.package.measures(name, pr.spikes_ms[0])
        theirs = pr.published.measures(name, pr.spikes_ms[0])
        ref = _reference(name, pr.spikes_ms, p) if reference else {}
        for measure in mine:
            a, b = mine[measure][0], theirs[measure][0]
            scipy = f"{ref[measure]:.4f}" if measure in ref else "n/a"
            rows.append((measure, f"{a:.4f}", f"{b:.4f}", scipy, _pct(a, b)))
            spread.append((measure, _range(mine[measure]), _range(theirs[measure])))
    lines += table(["first unit of each", "package", "published", "SciPy (same spikes)", "package vs published"],
                   rows) + [""]
    lines += table([f"across {units} identically driven units (min - max)", "package", "published"], spread)
    return "\n".join(lines)


def _speed_row(name: str, pr: Protocol) -> tuple[str, ...]:
    cells = []
    for what in ("wall_s", "cpu_s"):
        ours = pr.package.per_unit_second(getattr(pr.package, what))
        theirs = pr.published.per_unit_second(getattr(pr.published, what))
        cells += [f"{ours:.4f}", f"{theirs:.3f}", f"{theirs / ours:.1f}x"]
    return (name, *cells)


def _gap_row(name: str, pr: Protocol) -> tuple[str, ...]:
    gap = 100 * np.abs(pr.package.force_N[0] - pr.published.force_N[0]) / pr.published.force_N[0].max()
    after = pr.published.t_ms >= pr.spikes_ms[0]
    ratios = pr.release_over_own
    shown = ", ".join(f"{r:.3f}" for r in ratios) if ratios.size <= 3 else \
        f"{ratios[0]:.3f}, {ratios[1]:.3f}, ..., {ratios[-1]:.3f}"
    return name, f"{gap[~after].max():.2g}, {gap[after].max():.2g}", shown


def _reference(name: str, spikes_ms: np.ndarray, p: ParameterSet) -> dict[str, float]:
    """SciPy's measures for the same spike times: the twitch's, or the train's plateau mean."""
    end = spikes_ms[0] + 280.0 if name == "twitch" else PLATEAU_MS[1]
    ref = reference_simulate(p, spikes_ms[spikes_ms < end], LENGTH_MM, end, record_dt_ms=DT_MS)
    run = Run(ref.t_ms, ref.force_N[None, :], float("nan"), float("nan"), end)
    measures = run.measures(name, spikes_ms[0])
    return {k: float(v[0]) for k, v in measures.items() if "largest" not in k}


def _ct09_name(published_key: str) -> str:
    mech, _, name = published_key.partition(".")
    return PUBLISHED_RANGE[mech][name] if name else PUBLISHED_GLOBALS[published_key]


def _digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()[:16]


def _versions() -> str:
    from neuron import __version__ as neuron_version

    cxx = subprocess.run(["c++", "--version"], capture_output=True, text=True).stdout.splitlines()[:1]
    return f"NEURON {neuron_version}, {cxx[0] if cxx else 'c++ (version unknown)'}, Python {platform.python_version()}"


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("published", type=Path, help="folder with the authors' module1_2.mod and module3.mod")
    parser.add_argument("--units", type=int, default=20, help="identically driven units per process (20)")
    parser.add_argument("--duration-ms", type=float, default=5000.0, help="simulated time per run, ms (5000)")
    parser.add_argument("--no-reference", action="store_true", help="skip the SciPy integration (faster)")
    args = parser.parse_args(argv)
    if args.units < 1:
        raise SystemExit("--units must be at least 1")
    print(compare(args.published, args.units, args.duration_ms, not args.no_reference))


if __name__ == "__main__":
    main()
