"""hsid: identification of actuators with backlash or switch input nonlinearities followed by
linear dynamics (Hammerstein systems) by subspace identification, from numpy arrays.

The package is a face of the host library of hsid: every function calls it, and a model is
the model file (format hsid-model/1) that ``hsid identify --json`` writes.
"""

from ._hsid import (
    DataError,
    HsidError,
    IdentificationError,
    Model,
    SettingsError,
    diagnose,
    excite,
    identify,
    simulate_plant,
    solve_checkpoint,
    solve_many,
)

__all__ = [
    "DataError",
    "HsidError",
    "IdentificationError",
    "Model",
    "SettingsError",
    "diagnose",
    "excite",
    "identify",
    "simulate_plant",
    "solve_checkpoint",
    "solve_many",
]
