"""Helpers for tests that start `pice` or `mpiexec` in a subprocess, or depend on the MPI job pytest
itself runs in (not a test module).

Every test folder imports this as ``launch`` (tests/conftest.py puts tests/ on sys.path).
"""

from __future__ import annotations

import contextlib
import os
import pathlib
import shutil
import signal
import subprocess
import sys
import time

from pice.parallel.comm import without_launcher

BIN = pathlib.Path(sys.executable).parent  # the venv's bin: pice, mpiexec
MPIEXEC = BIN / "mpiexec"


def clean_env(**extra: str) -> dict:
    """This environment without the MPI launcher's variables (so a child `mpiexec` starts its own
    job even when pytest itself runs under mpiexec), with the venv's bin first on PATH, plus ``extra``."""
    env = without_launcher()
    env["PATH"] = f"{BIN}{os.pathsep}{env.get('PATH', '')}"
    env.update(extra)
    return env


def on_ranks(ranks: int, cmd: list) -> list[str]:
    """``cmd`` under the venv's `mpiexec -n ranks` (as it is on one rank)."""
    cmd = [str(c) for c in cmd]
    return [str(MPIEXEC), "-n", str(ranks), *cmd] if ranks > 1 else cmd


def pice_run(job, out, ranks: int = 1, *extra) -> list[str]:
    """The command line of `pice run JOB -o OUT [extra]` on ``ranks`` ranks."""
    return on_ranks(ranks, [BIN / "pice", "run", job, "-o", out, *extra])


def run_cmd(cmd: list, *, expect: int = 0, timeout: float = 600, **env: str) -> subprocess.CompletedProcess:
    """Run ``cmd`` in the clean environment (plus ``env``); its exit status must be ``expect``."""
    res = subprocess.run(cmd, env=clean_env(**env), capture_output=True, text=True, timeout=timeout)
    assert res.returncode == expect, (res.returncode, res.stderr[-3000:])
    return res


def start(cmd: list) -> subprocess.Popen:
    """Start ``cmd`` in the clean environment; stderr is kept (text), stdout dropped."""
    return subprocess.Popen(cmd, env=clean_env(), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)


def descendants(pid: int) -> list[int]:
    """Every process below ``pid`` (mpiexec -> hydra proxy -> ranks), from /proc."""
    children: dict[int, list[int]] = {}
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                stat = pathlib.Path(f"/proc/{entry}/stat").read_text()
            except OSError:
                continue
            ppid = int(stat.rsplit(")", 1)[1].split()[1])
            children.setdefault(ppid, []).append(int(entry))
    out, todo = [], [pid]
    while todo:
        for child in children.get(todo.pop(), []):
            out.append(child)
            todo.append(child)
    return out


def kill9_if(proc: subprocess.Popen, condition) -> bool:
    """SIGKILL a started run if ``condition()`` holds while every process of it is stopped (SIGSTOP).

    A run checked and then killed can pass the state looked for in between (a checkpoint written
    after the check, say: seen in CI on a loaded machine). Stopped, it cannot: the files the
    condition reads stay as they were when it held. Returns whether the run was killed; if not, it
    continues (SIGCONT)."""
    pids = [proc.pid, *descendants(proc.pid)]
    for pid in pids:  # the launcher first, so that it does not react to its children stopping
        try:
            os.kill(pid, signal.SIGSTOP)
        except ProcessLookupError:
            continue
    if condition():
        kill9(proc)
        return True
    for pid in reversed(pids):
        try:
            os.kill(pid, signal.SIGCONT)
        except ProcessLookupError:
            continue
    return False


def alive(pid: int) -> bool:
    """Has the process a thread that is not yet dead (a zombie leader may have live threads)?"""
    try:
        tasks = os.listdir(f"/proc/{pid}/task")
    except OSError:
        return False
    for tid in tasks:
        try:
            state = pathlib.Path(f"/proc/{pid}/task/{tid}/stat").read_text().rsplit(")", 1)[1].split()[0]
        except OSError:
            continue
        if state not in "ZX":
            return True
    return False


def kill9(proc: subprocess.Popen) -> None:
    """SIGKILL a started run: every rank, the proxy and the launcher at once (a crashed node)."""
    pids = [*descendants(proc.pid), proc.pid]
    for pid in pids:
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:  # already gone: nothing to kill
            continue
    proc.wait(timeout=30)
    deadline = time.monotonic() + 30
    while any(alive(pid) for pid in pids) and time.monotonic() < deadline:
        time.sleep(0.01)  # the ranks are not our children: wait until every thread is gone (and its file locks)


# -- the MPI job pytest itself runs in ---------------------------------------------------------------

def need_two_ranks(*, mpio: bool = False):
    """COMM_WORLD of the MPI job this test runs in; skip unless it has 2 ranks (and, with ``mpio``,
    unless h5py was built with MPI)."""
    import pytest

    from pice.io.mpio import h5py_has_mpi
    from pice.parallel.comm import world

    comm = world()
    if comm.size < 2:
        pytest.skip("needs 2 MPI ranks: mpiexec -n 2 python -m pytest -m io tests")
    if mpio and not h5py_has_mpi():
        pytest.skip("h5py has no MPI (h5py.get_config().mpi is False): run these in the parallel-HDF5 "
                    "environment, bash mpi/setup_parallel_hdf5.sh")
    return comm


def serial_only() -> None:
    """Skip under mpiexec: the test runs in the serial stage of mpi/run_tests.sh."""
    import pytest

    from pice.parallel.comm import world

    if world().size > 1:
        pytest.skip("serial test (it runs in the serial stage of mpi/run_tests.sh)")


@contextlib.contextmanager
def tiny_tmpfs(where: pathlib.Path, size: str):
    """A small tmpfs at ``where`` (root only), a full disk to be; skips the test where mounting is not
    allowed."""
    import pytest

    where.mkdir(parents=True, exist_ok=True)
    if os.geteuid() != 0 or not shutil.which("mount"):
        pytest.skip("a full disk is simulated with a tmpfs, which needs root and mount(8)")
    res = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(where)],
                         capture_output=True, text=True)
    if res.returncode:
        pytest.skip(f"cannot mount a tmpfs here to simulate a full disk: {res.stderr.strip()}")
    try:
        yield where
    finally:
        subprocess.run(["umount", "-l", str(where)], capture_output=True)
