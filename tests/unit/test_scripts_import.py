"""Every benchmark and MPI script (benchmarks/*.py, mpi/*.py) still imports: their figures are taken by
hand, not in CI, so a renamed or moved function they use would otherwise go unnoticed until the next
measurement. Each is loaded as a module (not run: each guards its main with __name__), with its own
folder on the path as when it is run (keel_half_full imports keel_step_trade beside it), and every
``from pice... import name`` in it, those inside functions too, must name something that exists."""

import ast
import importlib
import importlib.util
import pathlib
import runpy
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPTS = sorted([*ROOT.glob("benchmarks/*.py"), *ROOT.glob("mpi/*.py")])


def test_there_are_scripts_to_check():
    assert len(SCRIPTS) >= 20, [s.name for s in SCRIPTS]


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_the_script_imports(script, monkeypatch):
    monkeypatch.setattr(sys, "path", [str(script.parent), *sys.path])
    names = runpy.run_path(str(script), run_name="imported_by_test")
    assert callable(names.get("main")), f"{script.name}: no main() to run"
    missing = []
    for node in ast.walk(ast.parse(script.read_text())):
        if isinstance(node, ast.ImportFrom) and node.level == 0 and (node.module or "").split(".")[0] == "pice":
            module = importlib.import_module(node.module)
            missing += [f"{node.module}.{a.name}" for a in node.names if not hasattr(module, a.name)
                        and importlib.util.find_spec(f"{node.module}.{a.name}") is None]
    assert not missing, f"{script.name} imports what pice no longer has (inside functions too): {missing}"


@pytest.mark.parametrize("command", ["run", "study", "keel"])
def test_the_slurm_script_runs_the_pice_command_it_is_given(command):
    """mpi/slurm.sbatch outside SLURM (PICE_USE_MPIEXEC, one rank): ``study JOB ...`` runs `pice study`
    (the keel matrix's batch jobs, docs/ridge_keel.md), a bare JOB `pice run`; here each one's --help."""
    import os
    import subprocess

    env = {**os.environ, "PICE_USE_MPIEXEC": "1", "SLURM_NTASKS": "1",
           "PICE_VENV": str(pathlib.Path(sys.executable).parent.parent)}
    args = ["--help"] if command == "run" else [command, "--help"]
    out = subprocess.run(["bash", str(ROOT / "mpi/slurm.sbatch"), *args], env=env, cwd=ROOT,
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert f"usage: pice {command}" in out.stdout
    bare = subprocess.run(["bash", str(ROOT / "mpi/slurm.sbatch")], env=env, cwd=ROOT, capture_output=True,
                          text=True, timeout=60)
    assert bare.returncode != 0 and "usage: sbatch mpi/slurm.sbatch [run|study|keel]" in bare.stderr
    typo = subprocess.run(["bash", str(ROOT / "mpi/slurm.sbatch"), "stduy", "jobs/level_ice_demo.toml"], env=env,
                          cwd=ROOT, capture_output=True, text=True, timeout=60)
    assert typo.returncode == 2 and "'stduy' is neither a pice command" in typo.stderr
