"""Type stubs of the extension module ``bondgraph._native`` (the Rust engine).

Each function returns the command line's JSON document as text; ``bondgraph`` (the package
around it) turns them into objects and numpy arrays. Use that package, not this module.
"""

from typing import List, Optional

__version__: str

class BondGraphError(Exception):
    """A file that cannot be used, or a computation that cannot go on. ``str(error)`` is
    what the command line prints; ``diagnostics`` lists each problem."""

    diagnostics: List[Diagnostic]

class Diagnostic:
    """One problem: where it is, what it concerns, and what is wrong."""

    kind: str
    message: str
    file: Optional[str]
    line: Optional[int]
    column: Optional[int]
    element: Optional[str]
    notes: List[str]

class NativeEquations:
    json: str
    latex: str
    text: str

class NativeTrajectory:
    document: str
    times: List[float]
    values: List[float]
    sample_modes: List[int]
    def plot_svg(self) -> str: ...

class NativeAnalysis:
    json: str
    text: str
    bode_svg: Optional[str]
    step_svg: Optional[str]

class NativeModel:
    file: str
    name: str
    text: str
    is_linear_graph: bool
    is_nonlinear: bool
    @staticmethod
    def load(path: str) -> NativeModel: ...
    @staticmethod
    def loads(text: str, name: str) -> NativeModel: ...
    def check(self) -> str: ...
    def modes(self, states: Optional[str] = None) -> str: ...
    def equations(
        self,
        mode: Optional[str] = None,
        states: Optional[str] = None,
        outputs: List[str] = ...,
        at: Optional[str] = None,
    ) -> NativeEquations: ...
    def analyze(
        self,
        mode: Optional[str] = None,
        input: Optional[str] = None,
        output: Optional[str] = None,
        at: Optional[str] = None,
        equilibrium: bool = False,
    ) -> NativeAnalysis: ...
    def graph_svg(self, mode: Optional[str] = None) -> Optional[str]: ...
    def graph_dot(self, mode: Optional[str] = None) -> Optional[str]: ...
    def simulate_file(self, path: str) -> NativeTrajectory: ...
    def simulate_text(self, text: str, name: str) -> NativeTrajectory: ...

def discover(
    model: str,
    data: List[str],
    experiment: Optional[str] = None,
    extensions: Optional[str] = None,
) -> str: ...

def calibrate(
    model: str,
    data: List[str],
    experiment: Optional[str] = None,
) -> str: ...
def reproduce() -> str: ...
