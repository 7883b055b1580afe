"""The GIL is released while identifying: another Python thread runs meanwhile."""

import threading
import time

import hsid


def test_identify_lets_other_threads_run(record):
    _, u, y = record
    ticks = []
    stop = threading.Event()

    def tick():
        while not stop.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    worker = threading.Thread(target=tick)
    worker.start()
    time.sleep(0.05)
    start = time.perf_counter()
    hsid.identify(u, y, -1.0, 1.0, refine=False, segments=14, f=30, p=30)
    end = time.perf_counter()
    stop.set()
    worker.join()
    inside = [t for t in ticks if start < t < end]
    # Held, the GIL would stop the ticking thread for the whole call (no tick inside).
    assert end - start > 0.02, "the identification was too quick to tell"
    assert len(inside) >= 5, (len(inside), end - start)
