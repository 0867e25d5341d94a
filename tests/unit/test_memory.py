"""The memory a job needs at set-up (pice/memory.py, issue 13, case 4): the estimate made before
anything is allocated against what set-up then allocates, and the refusal of a job that does not fit
the memory available to the ranks of this machine (MemAvailable and the cgroup, here replaced)."""

from __future__ import annotations

import pytest
from bad_job_kit import BASE, BODY, PLANE, WATER, sub
from scenes import job_from_text

from pice import memory
from pice.errors import JobError
from pice.parallel.comm import SerialComm


@pytest.mark.parametrize("text", [
    BASE,                                                                             # one layer, 6 bond slots
    sub("thickness = 1.0", "thickness = 3.0", BASE),                                  # 3 HCP layers, 12 slots
    BASE + PLANE + "normal = [0.0, 0.0, 1.0]\n" + WATER + BODY,                       # a wall and a body
    sub("length = 4.0", "length = 40.0", sub("width = 3.0", "width = 17.0", BASE)),   # 760 elements
])
def test_estimate_is_what_set_up_allocates(text):
    """element_count x bytes_per_element, known before anything is allocated, is what Simulation then
    allocates for its particle arrays (what `pice check` prints as memory), to the byte."""
    from pice.simulation import Simulation

    job = job_from_text(text)
    n, need = memory.setup_bytes(job)
    d = Simulation(job, comm=SerialComm()).describe()
    assert n == d["elements"] and need == d["memory_bytes"]


def test_refusal_names_the_need_and_what_is_available(monkeypatch):
    """A sheet of 23 elements (~37 KiB) against 3/4 of that available: one JobError line naming ice.length,
    the elements, the need per rank and the fix; with 2 ranks on the machine and 60 KB available,
    each rank fits but both do not: the line names the ranks' share. Enough memory: no error."""
    job = job_from_text(sub("length = 4.0", "length = 8.0", BASE))
    n, need = memory.setup_bytes(job)
    monkeypatch.setattr(memory, "available_bytes", lambda: 0.75 * need)
    with pytest.raises(JobError) as err:
        memory.refuse_oversized(job, SerialComm())
    line = str(err.value)
    assert n == 23 and "\n" not in line
    assert line.startswith(f"job.toml: ice.length = 8: the sheet of 23 elements needs {memory._size(need)} ")
    assert "on each rank at set-up" in line and f"more than the {memory._size(0.75 * need)} available" in line
    assert "shorten the sheet" in line and "ranks on this machine" not in line
    monkeypatch.setenv("MPI_LOCALNRANKS", "2")
    monkeypatch.setattr(memory, "available_bytes", lambda: 1.5 * need)
    with pytest.raises(JobError, match="its 2 ranks on this machine need"):
        memory.refuse_oversized(job, SerialComm())
    monkeypatch.setattr(memory, "available_bytes", lambda: 2.5 * need)
    memory.refuse_oversized(job, SerialComm())


def test_available_memory_is_read_from_this_machine():
    """MemAvailable (or the cgroup's remainder) is a positive number of bytes here."""
    available = memory.available_bytes()
    assert available is not None and available > 2 ** 20
