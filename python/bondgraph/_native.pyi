"""Type stubs of the extension module ``bondgraph._native`` (the Rust engine).

Each function returns the command line's JSON document (or the text it prints) as a
string; ``bondgraph`` (the package around it) turns them into objects and numpy arrays.
Use that package, not this module.
"""

from typing import List, Optional

__version__: str

class BondGraphError(Exception):
    """A file that cannot be used, or a computation that cannot go on. ``str(error)`` is
    what the command line prints; ``diagnostics`` lists each problem; ``explanation`` is
    set by ``explain`` when the mode's equations cannot be derived."""

    diagnostics: List[Diagnostic]
    explanation: Optional[str]

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
    """``bondgraph equations``: the JSON document, the LaTeX a notebook renders, the
    ``--format latex`` output and the text."""

    json: str
    latex: str
    latex_document: str
    text: str

class NativeTrajectory:
    """``bondgraph simulate``: the document without its samples, and the samples as flat
    lists (``values`` row-major, one row per sample)."""

    document: str
    times: List[float]
    values: List[float]
    sample_modes: List[int]
    def csv(self) -> str:
        """``--format csv``."""
    def plot_svg(self, panels: List[str] = ...) -> str:
        """``--plot`` with a ``--panel`` for each entry (``"out1,out2"``)."""

class NativeAnalysis:
    """``bondgraph analyze``: the JSON document, the text and the two plots (``None``
    without a transfer function)."""

    json: str
    text: str
    bode_svg: Optional[str]
    step_svg: Optional[str]

class NativeComparison:
    """``bondgraph compare``: the JSON document, the text, and whether the answer is equal
    or similar."""

    json: str
    text: str
    agrees: bool

class NativeModel:
    """A checked model file (a bond graph or a linear graph)."""

    file: str
    name: str
    text: str
    is_linear_graph: bool
    is_nonlinear: bool
    @staticmethod
    def load(path: str) -> NativeModel:
        """Reads and checks the model file at ``path``."""
    @staticmethod
    def loads(text: str, name: str) -> NativeModel:
        """Checks the model in ``text``; ``name`` is the file name diagnostics give."""
    def check(self) -> str:
        """``bondgraph check``: the one-line summary."""
    def modes(self, states: Optional[str] = None) -> str:
        """``bondgraph modes --format json``."""
    def equations(
        self,
        mode: Optional[str] = None,
        states: Optional[str] = None,
        outputs: List[str] = ...,
        at: Optional[str] = None,
        equilibrium: bool = False,
        matrices: Optional[str] = None,
    ) -> NativeEquations:
        """``bondgraph equations``."""
    def analyze(
        self,
        mode: Optional[str] = None,
        input: Optional[str] = None,
        output: Optional[str] = None,
        at: Optional[str] = None,
        equilibrium: bool = False,
    ) -> NativeAnalysis:
        """``bondgraph analyze``."""
    def graph(self, mode: Optional[str] = None, format: str = "text") -> str:
        """``bondgraph graph --format text|dot|svg``."""
    def explain(self, mode: Optional[str] = None, format: str = "text") -> str:
        """``bondgraph explain --format text|markdown``."""
    def compare_file(self, path: str, mode: Optional[str] = None) -> NativeComparison:
        """``bondgraph compare`` with the answer file at ``path``."""
    def compare_text(
        self, text: str, name: str, mode: Optional[str] = None
    ) -> NativeComparison:
        """``bondgraph compare`` with the answer in ``text``."""
    def simulate_file(self, path: str) -> NativeTrajectory:
        """``bondgraph simulate`` with the scenario file at ``path``."""
    def simulate_text(self, text: str, name: str) -> NativeTrajectory:
        """``bondgraph simulate`` with the scenario in ``text``."""

def calibrate(
    model: str,
    data: List[str],
    experiment: Optional[str] = None,
) -> str:
    """``bondgraph calibrate --format json``."""

def discover(
    model: str,
    data: List[str],
    experiment: Optional[str] = None,
    extensions: Optional[str] = None,
    out: Optional[str] = None,
) -> str:
    """``bondgraph discover --format json`` (and ``--out``)."""

def reproduce() -> str:
    """``bondgraph reproduce --format json``; nothing is written."""
