"""The decerebrate cat soleus stretch reflex: a ramp-and-hold stretch of the cat soleus pool
(networks/cat_soleus_pool.py) with the reflex loop intact (spindle Ia excitation, tendon organ Ib inhibition
through interneurons: neuromuscle.pool.reflex) and with the dorsal roots cut (the afferents fire, nothing reaches
the motoneurons), under the same weak tonic synaptic drive.  Compared: pool force and motoneuron discharge, and
the afferents' rates at rest, during the ramp and during the hold against their rate equations, and the afferents'
figures (rate at the ramp's peak, dynamic index, hold rate per mm of stretch) beside recorded cat figures
(``PUBLISHED``, with their sources).  Group II afferents excite the motoneurons after a longer delay
(``ReflexDefinition.ii_weight_uS``).

Stretch: from --x0-mm (default -10 mm) to --x1-mm (-4 mm) at --velocity-mm-s (30 mm/s) from 300 ms, then held
until --duration-ms (1200 ms).  The spindles measure stretch from x0.
Run: python networks/stretch_reflex.py --out DIR [--units N] [--overwrite]   (also under mpiexec -n 2)
Writes DIR/stretch_reflex.json (the numbers printed) and DIR/stretch_reflex.png.  Units: ms, mm, mm/s, N, Hz, uS.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

from neuromuscle import InputError
from neuromuscle.pool import Pool
from neuromuscle.pool.reflex import ReflexDefinition, attach_reflex
from neuromuscle.protocols.lengths import isokinetic_ramp
from neuromuscle.reports.outdir import prepare_out_dir

sys.path.insert(0, str(Path(__file__).resolve().parent))
from cat_soleus_pool import definition  # noqa: E402

FILES = ("stretch_reflex.json", "stretch_reflex.png")
STRETCH_START_MS = 300.0
#: Recorded cat afferent figures the model's are printed beside (rates in /s).
PUBLISHED = [
    {"figure": "spindle endings of the passive triceps surae stretched at 0.6 mm/s over up to 10 mm "
               "(anaesthetised cat)",
     "published": "endings signalling both stretch and its velocity (80 %): some above 70 /s during the stretch "
                  "and 30-40 /s held, others less; length-only endings at most 20-25 /s held",
     "source": "Gorbunova & Zalkind 1976, Fiziol Zh SSSR 62:878-884"},
    {"figure": "velocity dependence of the response to a ramp stretch (primary and secondary endings)",
     "published": "about v^0.3 for both, times a length term; an initial burst at the ramp's onset",
     "source": "Houk, Rymer & Crago 1981, in Muscle Receptors and Movement"},
    {"figure": "secondary endings during locomotion",
     "published": "lower, more regular and less velocity dependent than primary endings",
     "source": "Loeb, Hoffer & Pratt 1985, J Neurophysiol 54:549-564"},
    {"figure": "tendon organ threshold to active contraction, soleus",
     "published": "below 0.1 g: one or two in-series muscle fibres; 4-15 motor units drive each receptor",
     "source": "Houk & Henneman 1967, J Neurophysiol 30:466-481"},
    {"figure": "tendon organ static sensitivity to active force, soleus",
     "published": "about 314 /s per g on the receptor's capsule, some two orders of magnitude less per g at the tendon",
     "source": "Stephens & Stauffer 1975"},
]


def _rate(trains: list[np.ndarray], t0: float, t1: float) -> float:
    """Mean rate (Hz) of the trains between t0 and t1 (ms)."""
    if not trains:
        return 0.0
    return float(np.mean([np.sum((s >= t0) & (s < t1)) for s in trains]) * 1000.0 / (t1 - t0))


def _isi_rate(trains: list[np.ndarray], t0: float, t1: float) -> float:
    """Rate (Hz) from the interspike intervals that end between t0 and t1 (ms), over every train."""
    isi = [np.diff(s)[(s[1:] >= t0) & (s[1:] < t1)] for s in trains if s.size > 1]
    isi = np.concatenate(isi) if isi else np.array([])
    return float(1000.0 / isi.mean()) if isi.size else 0.0


def afferent_figures(afferents: dict, rest: tuple[float, float], ramp_end_ms: float, hold: tuple[float, float],
                     stretch_mm: float) -> dict:
    """The spindle afferents' figures of a ramp-and-hold (Hz; /s per mm): rate at the ramp's peak (its last 10 ms),
    0.5 s later, their difference (the dynamic index), the hold's rate over the rest's per mm of stretch; the
    tendon organs' rates at rest and in the hold."""
    out: dict = {}
    for kind in ("Ia", "II"):
        peak = _isi_rate(afferents[kind], ramp_end_ms - 10.0, ramp_end_ms)
        later = _isi_rate(afferents[kind], ramp_end_ms + 490.0, ramp_end_ms + 500.0)
        rest_hz, hold_hz = _rate(afferents[kind], *rest), _rate(afferents[kind], *hold)
        out[kind] = {"ramp_peak_hz": round(peak, 1), "half_second_later_hz": round(later, 1),
                     "dynamic_index_hz": round(peak - later, 1),
                     "hold_per_mm_hz": round((hold_hz - rest_hz) / abs(stretch_mm), 2)}
    out["Ib"] = {"rest_hz": round(_rate(afferents["Ib"], *rest), 1), "hold_hz": round(_rate(afferents["Ib"], *hold), 1)}
    return out


def run(n_units: int, x0: float, x1: float, velocity: float, duration: float, tonic_uS: float,
        cut: bool) -> dict:
    """One ramp-and-hold run; returns the pool result, the afferent spikes and the window times."""
    length = isokinetic_ramp(x0, x1, velocity, STRETCH_START_MS, duration)
    with Pool(definition(n_units), length=length) as pool:
        reflex = attach_reflex(pool, ReflexDefinition(n_ia=8, n_ii=4, n_ib=4, xref_mm=x0, cut_dorsal_roots=cut))
        pool.drive_synaptic([0.0, duration], [tonic_uS, tonic_uS])
        result = pool.run(duration)
        afferents = reflex.spikes()
        reflex.destroy()
    return {"result": result, "afferents": afferents}


def summarise(runs: dict, x0: float, x1: float, velocity: float, duration: float) -> dict:
    """The figures: force and discharge by condition, afferent rates by window against the equations."""
    ramp_end = STRETCH_START_MS + abs(x1 - x0) / velocity * 1000.0
    windows = {"rest": (100.0, STRETCH_START_MS), "ramp": (STRETCH_START_MS + 50.0, ramp_end),
               "hold": (ramp_end + 300.0, duration)}
    stretch = {"rest": 0.0, "ramp": None, "hold": x1 - x0}
    out: dict = {"stretch": {"from_mm": x0, "to_mm": x1, "velocity_mm_s": velocity, "ramp_end_ms": ramp_end}}
    for cond, r in runs.items():
        res = r["result"]
        t = res.t_ms
        f = res.pool_force_N
        out[cond] = {
            "force_N": {w: round(float(f[(t >= a) & (t < b)].mean()), 3) for w, (a, b) in windows.items()},
            "peak_force_N": round(float(f.max()), 3),
            "units_firing": {w: int(sum(np.any((s >= a) & (s < b)) for s in res.spikes_ms))
                             for w, (a, b) in windows.items()},
            "motoneuron_rate_hz": {w: round(_rate([s for s in res.spikes_ms if s.size], a, b), 1)
                                   for w, (a, b) in windows.items()},
        }
    intact = runs["intact"]["afferents"]
    rates = {}
    for kind in ("Ia", "II", "Ib"):
        rates[kind] = {w: round(_rate(intact[kind], a, b), 1) for w, (a, b) in windows.items()}
    # the equations' values (Prochazka & Gorassini 1998, Prochazka 1999) at the windows' stretch and velocity
    ramp_mid = 0.5 * (windows["ramp"][0] + windows["ramp"][1])
    d_ramp = (ramp_mid - STRETCH_START_MS) / 1000.0 * velocity * np.sign(x1 - x0)
    expected = {"Ia": {"rest": 82.0, "ramp": 4.3 * velocity ** 0.6 + 2.0 * d_ramp + 82.0,
                       "hold": 2.0 * stretch["hold"] + 82.0},
                "II": {"rest": 80.0, "ramp": 13.5 * d_ramp + 80.0, "hold": 13.5 * stretch["hold"] + 80.0}}
    out["afferent_rate_hz"] = rates
    out["afferent_figures"] = afferent_figures(intact, windows["rest"], ramp_end, windows["hold"], x1 - x0)
    # the equations at the slow stretch of the recorded figures (0.6 mm/s, held 10 mm beyond rest)
    out["equation_at_0_6_mm_s_and_10_mm_hz"] = {"Ia_dynamic": round(4.3 * 0.6 ** 0.6, 1),
                                                "Ia_hold": 2.0 * 10 + 82.0, "II_hold": 13.5 * 10 + 80.0}
    out["published"] = PUBLISHED
    out["equation_rate_hz"] = {k: {w: round(v, 1) for w, v in e.items()} for k, e in expected.items()}
    out["reflex_force_gain"] = round(out["intact"]["force_N"]["hold"] / max(out["cut"]["force_N"]["hold"], 1e-9), 2)
    return out


def figure(path: Path, runs: dict, title: str) -> None:
    """Pool force of both conditions, motoneuron raster (intact) and afferent rasters."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(3, 1, figsize=(8, 8), sharex=True)
    for cond, r in runs.items():
        res = r["result"]
        ax[0].plot(res.t_ms, res.pool_force_N, label=cond)
    ax[0].set_ylabel("pool force (N)")
    ax[0].legend()
    for cond, row in (("intact", 1),):
        for i, s in enumerate(runs[cond]["result"].spikes_ms):
            ax[row].plot(s, np.full(s.size, i), "|", color="k", ms=4)
    ax[1].set_ylabel("motoneuron (intact)")
    y = 0
    for kind, colour in (("Ia", "C0"), ("II", "C2"), ("Ib", "C3")):
        for s in runs["intact"]["afferents"][kind]:
            ax[2].plot(s, np.full(s.size, y), "|", color=colour, ms=3)
            y += 1
    ax[2].set_ylabel("afferents Ia / II / Ib")
    ax[2].set_xlabel("time (ms)")
    fig.suptitle(title)
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main(argv: list[str] | None = None) -> dict:
    """Command line (module docstring); returns the figures printed as JSON."""
    from neuromuscle.pool.pool import parallel_context

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", required=True, help="output folder")
    ap.add_argument("--units", type=int, default=10)
    ap.add_argument("--x0-mm", type=float, default=-10.0)
    ap.add_argument("--x1-mm", type=float, default=-4.0)
    ap.add_argument("--velocity-mm-s", type=float, default=30.0)
    ap.add_argument("--duration-ms", type=float, default=1200.0)
    ap.add_argument("--tonic-us", type=float, default=0.003, help="tonic synaptic drive (uS a cell)")
    ap.add_argument("--overwrite", action="store_true")
    a = ap.parse_args(argv)
    ramp_end = STRETCH_START_MS + abs(a.x1_mm - a.x0_mm) / a.velocity_mm_s * 1000.0
    if a.duration_ms < ramp_end + 400.0:
        raise InputError(f"--duration-ms {a.duration_ms:g}: the hold window needs the run to last at least "
                         f"{ramp_end + 400.0:g} ms (the ramp ends at {ramp_end:g} ms)")
    rank = int(parallel_context().id())
    out = prepare_out_dir(a.out, a.overwrite, FILES) if rank == 0 else Path(a.out)
    runs = {cond: run(a.units, a.x0_mm, a.x1_mm, a.velocity_mm_s, a.duration_ms, a.tonic_us, cut)
            for cond, cut in (("intact", False), ("cut", True))}
    summary = summarise(runs, a.x0_mm, a.x1_mm, a.velocity_mm_s, a.duration_ms)
    summary["ranks"] = int(parallel_context().nhost())
    if rank == 0:
        (out / FILES[0]).write_text(json.dumps(summary, indent=1))
        figure(out / FILES[1], runs, f"cat soleus stretch reflex, {a.units} units: intact vs dorsal roots cut")
        print(json.dumps(summary))
    return summary


if __name__ == "__main__":
    from neuromuscle.pool.mpi import finish_mpi, init_mpi, launcher_size

    if launcher_size() is None:
        main()
    else:
        init_mpi()          # NEURON joins the launcher's ranks before anything else uses it
        main()
        finish_mpi(0)
