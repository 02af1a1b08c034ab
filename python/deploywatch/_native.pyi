# The extension module deploywatch._native (python/src/lib.rs). Private:
# use the functions of `deploywatch`, which check their arguments and type
# the results.
from typing import Any, Callable, Dict, List, Optional, Tuple

import numpy as np
import numpy.typing as npt

_F = npt.NDArray[np.float64]

__version__: str

class Model:
    text: str
    source: str
    def __init__(self, text: str, source: str) -> None: ...
    def check_effects(self, arg: str, items: List[str]) -> List[str]: ...
    def implausible(self) -> List[str]: ...
    def describe(self) -> Dict[str, Any]: ...

def simulate(
    model: Model, effects: List[str], sample_hz: Optional[float] = None
) -> Tuple[_F, _F, _F, _F, float]: ...
def simulate_batch(
    mechanism_toml: str,
    source: str,
    vary: List[str],
    fail: List[str],
    params: _F,
    from_json: Optional[str] = None,
    flight: bool = False,
) -> Tuple[_F, _F, _F, _F, _F]: ...
def parameters(
    mechanism_toml: str,
    source: str,
    vary: List[str],
    fail: List[str],
    from_json: Optional[str] = None,
    flight: bool = False,
) -> List[str]: ...
def check_vary(text: str) -> Optional[str]: ...
def reliability(
    mechanism_toml: str,
    source: str,
    vary: List[str],
    fail: List[str],
    method: str,
    samples: Optional[int],
    target_cov: Optional[float],
    seed: int,
    from_json: Optional[str] = None,
    evaluate: Optional[Callable[[_F], List[List[float]]]] = None,
    corr: List[str] = ...,
    flight: bool = False,
) -> Dict[str, Any]: ...
def run_command(args: List[str], names: List[Tuple[str, str]] = ...) -> None: ...

class Monitor:
    joints: int
    def __init__(self, model: Model) -> None: ...
    def update(self, t_s: float, phi_deg: List[float], latch: List[bool]) -> Dict[str, Any]: ...
