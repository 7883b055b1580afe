"""Ctrl-C stops a long `hsid.identify` or `hsid.diagnose` within a second: the call runs its
work on a thread of its own and checks Python's signals while it waits, so the
`KeyboardInterrupt` is raised at once instead of when the work returns. Each run is a child
Python process that gets a real SIGINT."""

import signal
import subprocess
import sys
import time

import pytest

from conftest import ROOT

SERVO = ROOT / "examples" / "data" / "servo.csv"

CHILD = r"""
import faulthandler, signal, sys, time
import numpy as np
import hsid
# Ctrl-C as an interactive interpreter has it: a process started in the background by a shell
# without job control (`cmd &` in a script, as a CI runner may start the suite) inherits SIGINT
# ignored, and Python then installs no KeyboardInterrupt handler at all.
signal.signal(signal.SIGINT, signal.default_int_handler)
rows = [l for l in open(sys.argv[1]) if not l.startswith("#")][1:]
u, y = np.array([[float(x) for x in l.split(",")] for l in rows]).T
# The record eight times over (50,400 samples): the call lasts well beyond the signal on any
# machine (the servo record alone is identified and diagnosed in about a second on a fast one).
u, y = np.tile(u, 8), np.tile(y, 8)
call = sys.argv[2]
print("started", flush=True)
start = time.monotonic()
# Should the call outlive the signal by far, the Python stack goes to stderr (the test prints it).
faulthandler.dump_traceback_later(45)
try:
    if call == "identify":
        hsid.identify(u, y, umin=-1.0, umax=1.0)
    else:
        hsid.diagnose(u, y, umin=-1.0, umax=1.0)
    print("finished", time.monotonic() - start, flush=True)
except KeyboardInterrupt:
    print("interrupted", time.monotonic(), flush=True)
"""


@pytest.mark.parametrize("call", ["identify", "diagnose"])
def test_ctrl_c_raises_keyboard_interrupt_within_a_second(call):
    child = subprocess.Popen(
        [sys.executable, "-c", CHILD, str(SERVO), call],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    assert child.stdout.readline().strip() == "started"
    # Well inside the call: the default identification of the record takes many seconds.
    time.sleep(1.5)
    assert child.poll() is None, "the call ended before the signal"
    sent = time.monotonic()
    child.send_signal(signal.SIGINT)
    try:
        out, err = child.communicate(timeout=60)
    except subprocess.TimeoutExpired:
        child.kill()
        out, err = child.communicate()
        pytest.fail(f"no end within 60 s of the signal: stdout {out!r}, stderr {err!r}")
    words = out.split()
    assert words[:1] == ["interrupted"], (out, err)
    latency = float(words[1]) - sent
    assert latency < 1.0, latency
    # The process ends too: the stopped work does not keep it alive.
    assert child.returncode == 0, err
