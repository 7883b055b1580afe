"""A zoo of records nobody designed for the method, the peers that identify them, and the
harness that scores `hsid.identify` beside those peers (see `run.py`)."""
