"""hsid: identification of actuators with backlash or switch input nonlinearities followed by
linear dynamics (Hammerstein systems) by subspace identification, from numpy arrays (or
anything numpy reads as one: lists, pandas Series), pandas DataFrames and hsid's CSV files.

The package is a face of the host library of hsid: every function calls it, and a model is
the model file (format hsid-model/1) that ``hsid identify --json`` writes.
"""

from ._frame import CsvRecord, diagnose, from_frame, identify, read_csv
from ._hsid import (
    DataError,
    HsidError,
    IdentificationError,
    Model,
    SettingsError,
    __version__,
    excite,
    regressor,
    simulate_plant,
    solve_checkpoint,
    solve_many,
)

__all__ = [
    "CsvRecord",
    "DataError",
    "HsidError",
    "IdentificationError",
    "Model",
    "SettingsError",
    "__version__",
    "diagnose",
    "excite",
    "from_frame",
    "identify",
    "read_csv",
    "regressor",
    "simulate_plant",
    "solve_checkpoint",
    "solve_many",
]
