"""Every ```bash, ```python and ```hoc block of README.md runs as written, in order, in one fresh folder.

The folder holds a copy of mod/ (the README's commands run in a checkout).  python blocks run as script files
with this interpreter (the venv's: the fit snippet's ``__main__`` guard and its 2 workers are exercised), bash
blocks with bash and this venv's bin/ first on PATH (its ``neuromuscle``, ``nrnivmodl``), hoc blocks with nrniv in
the folder after ``nrnivmodl mod`` (which a bash block of the README runs).  A block right after the line
``SKIP_MARK`` is not run: those are the setup commands CI itself runs; command 1's own work (after the set-up) is
run twice in a row.  The README's Python fit and its ``neuromuscle fit`` command print the same estimates, within
1 % of the example file's true values.
"""

import os
import re
import shutil
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

from neuromuscle.measured.example import TRUE_VALUES
from neuromuscle.model import mechanisms

pytestmark = pytest.mark.heavy(cost_s=80)

README = Path(__file__).resolve().parents[2] / "README.md"
SKIP_MARK = "<!-- readme-test: skip (CI runs these) -->"
LANGUAGES = ("bash", "python", "hoc")
SETUP_STEPS = ("python3 -m venv ", ". .venv/bin/activate", "pip install ")
SUFFIX = {"bash": "sh", "python": "py", "hoc": "hoc"}
HOC_DONE = "readme-hoc-block-ran-to-the-end"
TIMEOUT_S = 600


@dataclass(frozen=True)
class Block:
    language: str
    line: int  # of the opening fence, 1-based
    code: str
    skipped: bool

    @property
    def name(self) -> str:
        return f"README.md:{self.line} {self.language}"


def readme_blocks(text: str) -> list[Block]:
    """The fenced bash/python/hoc blocks of ``text``, each marked skipped when SKIP_MARK is the line before it."""
    lines = text.splitlines()
    blocks, i = [], 0
    while i < len(lines):
        m = re.fullmatch(r"```(\w*)\s*", lines[i])
        if not m:
            i += 1
            continue
        end = next(j for j in range(i + 1, len(lines)) if lines[j].strip() == "```")
        if m.group(1) in LANGUAGES:
            blocks.append(Block(m.group(1), i + 1, "\n".join(lines[i + 1:end]) + "\n",
                                i > 0 and lines[i - 1].strip() == SKIP_MARK))
        i = end + 1
    return blocks


BLOCKS = readme_blocks(README.read_text())


def _env() -> dict[str, str]:
    env = dict(os.environ)
    env["PATH"] = str(Path(sys.executable).parent) + os.pathsep + env.get("PATH", "")
    env.setdefault("MPLBACKEND", "Agg")
    return env


def _compiled(folder: Path) -> None:
    """``nrnivmodl mod`` in ``folder`` unless a README block already compiled there."""
    if not any((folder / arch).is_dir() for arch in ("x86_64", "arm64", "aarch64")):
        subprocess.run(["nrnivmodl", "mod"], cwd=folder, env=_env(), check=True, capture_output=True)


def _run_block(block: Block, folder: Path) -> subprocess.CompletedProcess:
    script = folder / f"readme_block_{block.line}.{SUFFIX[block.language]}"
    if block.language == "hoc":
        _compiled(folder)
        script.write_text(block.code + f'\nprint "{HOC_DONE}"\n')
        cmd = ["nrniv", "-nobanner", script.name]
    else:
        script.write_text(block.code)
        cmd = ["bash", "-e", script.name] if block.language == "bash" else [sys.executable, script.name]
    return subprocess.run(cmd, cwd=folder, env=_env(), stdin=subprocess.DEVNULL, capture_output=True, text=True,
                          timeout=TIMEOUT_S)


def _fresh_folder(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("readme")
    (folder / "mod").mkdir()
    for f in mechanisms.mod_files():
        shutil.copyfile(f, folder / "mod" / f.name)
    return folder


@pytest.fixture(scope="module")
def readme_folder(tmp_path_factory) -> Path:
    return _fresh_folder(tmp_path_factory)


@pytest.fixture(scope="module")
def readme_runs(readme_folder) -> dict[Block, subprocess.CompletedProcess]:
    """Each block that is not skipped, run in README order in one fresh folder (``readme_folder``)."""
    return {b: _run_block(b, readme_folder) for b in BLOCKS if not b.skipped}


@pytest.mark.parametrize("block", BLOCKS, ids=[b.name for b in BLOCKS])
def test_readme_block_runs_as_written(block, readme_runs):
    if block.skipped:
        pytest.skip(f"{block.name}: marked '{SKIP_MARK}'")
    out = readme_runs[block]
    assert out.returncode == 0, \
        f"{block.name} failed:\n{block.code}\n--- stdout\n{out.stdout}\n--- stderr\n{out.stderr}"
    if block.language == "hoc":
        assert HOC_DONE in out.stdout, out.stdout + out.stderr


def test_the_hoc_route_makes_the_force_python_makes(readme_folder, readme_runs, ct09):
    """The README's hoc unit, as written, in the folder where the README ran ``nrnivmodl mod`` (plain nrnivmodl, not
    the package's cache), given one spike at 100 ms: its twitch peak at -8 mm is ``simulate``'s within 0.2 %.  (One
    compiled folder and one copy of the wiring: the README's.)"""
    assert readme_runs, "the README's blocks ran"
    _compiled(readme_folder)
    (hoc_block,) = [b for b in BLOCKS if b.language == "hoc"]
    twitch = ("objref nc, nil, fih, fv\nnc = new NetCon(nil, ca)\nnc.weight = 1\n"
              "fih = new FInitializeHandler(\"nc.event(100)\")\ndt = 0.025\nload_file(\"stdrun.hoc\")\n"
              "tstop = 300\nfv = new Vector()\nfv.record(&frc.F, 0.1)\nfinitialize()\ncontinuerun(300)\n"
              "printf(\"PEAK %g\\n\", fv.max())\n")
    (readme_folder / "peak.hoc").write_text(hoc_block.code + twitch)
    code = "from neuron import h; h.load_file('peak.hoc')"
    out = subprocess.run([sys.executable, "-c", code], cwd=readme_folder, env=_env(), capture_output=True,
                         text=True, timeout=TIMEOUT_S)
    peak = [float(ln.split()[1]) for ln in out.stdout.splitlines() if ln.startswith("PEAK")]
    from neuromuscle import simulate

    expected = simulate(ct09, [100.0], -8.0, 300.0).force_N.max()
    assert peak and abs(peak[0] / expected - 1) < 0.002, out.stdout + out.stderr


def test_only_the_setup_commands_are_skipped():
    """The skip mark hides nothing but set-up lines that CI runs (each command line starts by making the venv)."""
    skipped = [b for b in BLOCKS if b.skipped]
    assert [b.language for b in skipped] == ["bash"], [b.name for b in skipped]
    commands = [ln for ln in skipped[0].code.splitlines() if ln.strip() and not ln.startswith("#")]
    assert len(commands) == 2 and all(c.startswith(SETUP_STEPS[0]) for c in commands), commands


def test_command_1_works_twice_in_a_row(tmp_path_factory):
    """README command 1 after its set-up (the venv is this one): run twice, the second replaces the output."""
    setup = next(b for b in BLOCKS if b.skipped)
    command_1 = next(ln for ln in setup.code.splitlines() if ln.startswith(SETUP_STEPS[0]))
    work = " && ".join(s for s in command_1.split(" && ") if not s.startswith(SETUP_STEPS))
    assert work.startswith("neuromuscle "), command_1
    folder = _fresh_folder(tmp_path_factory)
    for attempt in (1, 2):
        out = subprocess.run(["bash", "-e", "-c", work], cwd=folder, env=_env(), stdin=subprocess.DEVNULL,
                             capture_output=True, text=True, timeout=TIMEOUT_S)
        assert out.returncode == 0, f"run {attempt} of: {work}\n{out.stdout}\n{out.stderr}"
    assert (folder / "out" / "example.h5").is_file()


ESTIMATE = re.compile(r"^\s*(\w+)\s+= (\S+) .*95% \[(\S+), (\S+)\]", re.M)


def _printed_estimates(text: str) -> dict[str, tuple[str, str, str]]:
    """name -> (estimate, lower, upper) as printed."""
    return {m.group(1): m.group(2, 3, 4) for m in ESTIMATE.finditer(text)}


def test_python_fit_and_fit_command_print_the_same_estimates(readme_runs):
    python_fit = [out for b, out in readme_runs.items() if b.language == "python" and "fit(problem" in b.code]
    cli_fit = [out for b, out in readme_runs.items() if b.language == "bash" and "neuromuscle fit " in b.code]
    assert len(python_fit) == len(cli_fit) == 1, "the README has one Python fit and one `neuromuscle fit` block"
    from_python, from_cli = _printed_estimates(python_fit[0].stdout), _printed_estimates(cli_fit[0].stdout)
    assert set(from_cli) == set(TRUE_VALUES), cli_fit[0].stdout
    assert from_python == from_cli, f"Python:\n{python_fit[0].stdout}\nCLI:\n{cli_fit[0].stdout}"
    for name, (estimate, _, _) in from_cli.items():  # and they find the example's true values
        assert float(estimate) == pytest.approx(TRUE_VALUES[name], rel=0.01), name


def test_ci_runs_command_2_as_written():
    """.ci/run runs the README's command 2 verbatim: whatever CI checks runs inside that command."""
    setup = next(b for b in BLOCKS if b.skipped)
    command_2 = [ln for ln in setup.code.splitlines() if ln.startswith(SETUP_STEPS[0])][1]
    assert "[test,mpi,docs]" in command_2 and command_2.endswith("python -m pytest -q"), command_2
    assert command_2 in (README.parent / ".ci" / "run").read_text().splitlines()
