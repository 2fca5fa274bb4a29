"""bondgraph: bond graphs and linear graphs in RON, in Python.

Load a model file (a bond graph ``Model(...)`` or a linear graph ``LinearGraph(...)``),
derive its state equations with symbolic entries, simulate it exactly through its mode
changes, and compare it with measured data: the ``bondgraph`` command line's commands as
functions and methods that return Python objects. Every result carries the command's JSON
document (``.document``), field for field; matrices of numbers are numpy arrays and
symbolic matrices are numpy arrays of strings.

In a notebook, three lines derive, simulate and plot::

    import bondgraph
    belt = bondgraph.load("models/examples/belt_friction.ron")
    display(belt.equations(), belt.simulate("models/scenarios/belt_stick_slip.ron"))

The equations show as LaTeX, the simulation as the plot of ``bondgraph simulate --plot``
with the modes shaded. For teaching, :meth:`Model.explain` words the derivation,
:meth:`Model.analyze` gives poles, transfer function and Bode plot, and :meth:`Model.compare`
(or :func:`compare`) checks a student's ``A`` and ``B``.

Problems with a file raise :class:`BondGraphError`, whose ``diagnostics`` name the file,
line, column and element of each problem.
"""

from __future__ import annotations

import json
import os
import re
from typing import Any, Dict, Iterable, List, Optional, Sequence, Union

import numpy as np

from . import _native
from ._native import BondGraphError, Diagnostic

__all__ = [
    "Analysis",
    "BondGraphError",
    "Comparison",
    "Diagnostic",
    "Document",
    "Equations",
    "Explanation",
    "Model",
    "Simulation",
    "SparseMatrix",
    "Svg",
    "calibrate",
    "compare",
    "discover",
    "load",
    "loads",
    "reproduce",
]

__version__ = _native.__version__

# Raised by the bindings, an error always has its diagnostics; one made by hand has none.
BondGraphError.diagnostics = ()
# Set only by Model.explain, when the mode's equations cannot be derived: the explanation as
# far as it got.
BondGraphError.explanation = None

PathLike = Union[str, "os.PathLike[str]"]


class Document(dict):
    """A JSON document of the command line, as a dict whose keys also read as attributes
    (``doc.ranking[0].id`` for ``doc["ranking"][0]["id"]``)."""

    def __getattr__(self, name: str) -> Any:
        try:
            return self[name]
        except KeyError:
            raise AttributeError(name) from None

    @staticmethod
    def of(value: Any) -> Any:
        """``value`` with every dict made a :class:`Document`, recursively."""
        if isinstance(value, dict):
            return Document({k: Document.of(v) for k, v in value.items()})
        if isinstance(value, list):
            return [Document.of(v) for v in value]
        return value


def _parse(text: str) -> Document:
    return Document.of(json.loads(text))


def _numbers(rows: Any) -> np.ndarray:
    """Rows of numbers (``null`` for a value that is not finite) as a float array."""
    array = np.array(
        [[np.nan if x is None else x for x in row] for row in rows], dtype=float
    )
    return array.reshape(len(rows), -1) if len(rows) else np.zeros((0, 0))


def _symbols(rows: Any) -> np.ndarray:
    """Rows of symbolic strings as an array of Python strings."""
    array = np.empty((len(rows), len(rows[0]) if rows else 0), dtype=object)
    for i, row in enumerate(rows):
        for j, entry in enumerate(row):
            array[i, j] = entry
    return array


class SparseMatrix:
    """A large mode's matrix as its non-zero entries (``--matrices sparse``, the default
    above 500 states): entry ``k`` is ``data[k]`` at ``(row[k], col[k])``, as
    ``scipy.sparse.coo_array((data, (row, col)), shape)`` takes them.

    ``data`` is a float array for the ``_value`` matrices and an array of Python strings
    for the symbolic ones. ``to_scipy()`` builds the scipy array (scipy is not a
    dependency of this package: install it to use this), ``toarray()`` the dense numpy
    array (zeros filled in; beware the memory of a large model).
    """

    def __init__(self, document: Dict[str, Any], numeric: bool) -> None:
        self.shape = tuple(document["shape"])
        self.row = np.asarray(document["row"], dtype=np.int64)
        self.col = np.asarray(document["col"], dtype=np.int64)
        if numeric:
            self.data = np.array(
                [np.nan if x is None else x for x in document["data"]], dtype=float
            )
        else:
            self.data = np.empty(len(document["data"]), dtype=object)
            for k, entry in enumerate(document["data"]):
                self.data[k] = entry
        self.numeric = numeric

    @property
    def nnz(self) -> int:
        """How many entries are stored."""
        return len(self.data)

    def toarray(self) -> np.ndarray:
        """The dense array: ``0.0`` (or ``"0"``) where no entry is stored."""
        if self.numeric:
            dense = np.zeros(self.shape)
        else:
            dense = np.full(self.shape, "0", dtype=object)
        dense[self.row, self.col] = self.data
        return dense

    def to_scipy(self) -> Any:
        """A ``scipy.sparse.coo_array`` of the numeric entries."""
        if not self.numeric:
            raise TypeError("symbolic entries are strings; take the _value matrix")
        try:
            from scipy import sparse
        except ImportError as error:
            raise ImportError("to_scipy() needs scipy: pip install scipy") from error
        return sparse.coo_array((self.data, (self.row, self.col)), shape=self.shape)

    def __repr__(self) -> str:
        kind = "numbers" if self.numeric else "symbols"
        return f"<SparseMatrix {self.shape[0]}x{self.shape[1]}: {self.nnz} {kind}>"


class Svg:
    """An SVG drawing; a notebook shows it (``_repr_svg_``)."""

    def __init__(self, text: str) -> None:
        self.text = text

    def _repr_svg_(self) -> str:
        return self.text

    def save(self, path: PathLike) -> None:
        """Writes the drawing to ``path``."""
        with open(path, "w", encoding="utf-8") as f:
            f.write(self.text)

    def __str__(self) -> str:
        return self.text

    def __repr__(self) -> str:
        return f"<Svg: {len(self.text)} characters>"


class Equations:
    """The state equations of one mode, ``bondgraph equations --format json``.

    A linear mode has ``A``, ``B``, ``c`` (symbolic: arrays of strings) and ``A_value``,
    ``B_value``, ``c_value`` (float arrays; above 500 states, or with
    ``matrices="sparse"``, ``A``, ``B`` and ``E`` are :class:`SparseMatrix`), ``E`` and ``E_value`` where input derivatives
    enter, and with outputs ``C``, ``D``, ``d`` (and ``F``) with their ``_value`` twins. A
    nonlinear mode has ``f`` (one string per state) and, at an operating point, its
    Jacobians ``A``, ``B``. ``c`` and ``d`` are column vectors. Any other field of the
    document reads as an attribute too (``states``, ``inputs``, ``mode``, ...).

    ``text`` is what ``bondgraph equations`` prints (with the outputs, the guards and the
    conventions), ``latex`` the equations a notebook renders and ``latex_document`` what
    ``--format latex`` prints (the same after a comment saying it needs amsmath).
    """

    def __init__(self, native: Any) -> None:
        self.document: Document = _parse(native.json)
        self.latex: str = native.latex
        self.latex_document: str = native.latex_document
        self.text: str = native.text

    def __getattr__(self, name: str) -> Any:
        document = self.__dict__.get("document", {})
        base, numeric = (name[:-6], True) if name.endswith("_value") else (name, False)
        if base in ("C", "D", "F", "d") and base not in document:
            # The output equations' rows, stacked: y = C x + D u + F du/dt + d.
            outputs = document.get("outputs", [])
            if not any(name in o for o in outputs):
                raise AttributeError(name)
            rows = [o[name] if base != "d" else [o[name]] for o in outputs]
            return _numbers(rows) if numeric else _symbols(rows)
        if name not in document:
            raise AttributeError(name)
        value = document[name]
        if isinstance(value, dict) and "row" in value and "col" in value:
            return SparseMatrix(value, numeric)
        if isinstance(value, list) and value and isinstance(value[0], list):
            return _numbers(value) if numeric else _symbols(value)
        if isinstance(value, list) and base == "c":
            rows = [[x] for x in value]
            return _numbers(rows) if numeric else _symbols(rows)
        return value

    @property
    def state_names(self) -> List[str]:
        """The states' names, in order (``p_mass``, ``q_spring``)."""
        return [s["name"] for s in self.document["states"]]

    def _repr_latex_(self) -> str:
        return self.latex

    def __str__(self) -> str:
        return self.text

    def __repr__(self) -> str:
        return f"<Equations of {self.document.get('model', '?')}: {len(self.state_names)} states>"


class Simulation:
    """A simulated trajectory, ``bondgraph simulate --format json``.

    ``t`` holds the sample times (s), ``values`` the recorded outputs (one column per name
    in ``output_names``, ``outputs[name]`` one of them), ``mode`` the index into ``modes``
    of the mode at each sample; ``events``, ``final``, ``intervals`` and ``stats`` are the
    document's fields. A notebook shows the plot of ``bondgraph simulate --plot``;
    :meth:`plot` groups outputs into panels, :meth:`to_csv` gives ``--format csv``.
    """

    def __init__(self, native: Any) -> None:
        self._native = native
        self.document: Document = _parse(native.document)
        self.t: np.ndarray = np.array(native.times, dtype=float)
        names = list(self.document["outputs"])
        self.output_names: List[str] = names
        self.values: np.ndarray = np.array(native.values, dtype=float).reshape(
            len(self.t), len(names)
        )
        self.mode: np.ndarray = np.array(native.sample_modes, dtype=np.int64)

    @property
    def outputs(self) -> Dict[str, np.ndarray]:
        """Each recorded output's samples, by name."""
        return {name: self.values[:, j] for j, name in enumerate(self.output_names)}

    @property
    def modes(self) -> List[str]:
        """The specifications of the modes visited, in order of first visit."""
        return list(self.document["modes"])

    @property
    def events(self) -> List[Document]:
        """The mode changes: ``{t, from, to, element, reason}``."""
        return list(self.document["events"])

    @property
    def event_times(self) -> np.ndarray:
        """The times of the mode changes, in seconds."""
        return np.array([e["t"] for e in self.document["events"]], dtype=float)

    @property
    def final(self) -> Document:
        """``{t, mode, states: {name: value}}`` at the end."""
        return self.document["final"]

    @property
    def intervals(self) -> List[Document]:
        """The time spent in each mode: ``{start, end, mode}``."""
        return list(self.document["intervals"])

    @property
    def stats(self) -> Document:
        """``{segments, events, modes}``: the work the run took."""
        return self.document["stats"]

    def plot(self, panels: Optional[Sequence[Union[str, Sequence[str]]]] = None) -> Svg:
        """The outputs against time with the modes shaded (``simulate --plot``), each axis
        labelled with what its output is and its unit.

        Args:
            panels: one entry per panel, top to bottom (``simulate --panel``): a list of
                recorded outputs, or one string of them separated by commas; default one
                panel per output.
        """
        texts = [p if isinstance(p, str) else ",".join(p) for p in (panels or [])]
        return Svg(self._native.plot_svg(texts))

    def to_csv(self) -> str:
        """``simulate --format csv``: a header ``t,mode,<outputs>``, then one row per
        sample, every number in full precision."""
        return self._native.csv()

    def _repr_svg_(self) -> str:
        return self._native.plot_svg([])

    def __repr__(self) -> str:
        return (
            f"<Simulation of {self.document.get('model', '?')}: {len(self.t)} samples, "
            f"{len(self.events)} events>"
        )


class Analysis:
    """One linear mode (or a nonlinear mode's linearisation) analysed, ``bondgraph
    analyze --format json``.

    The document's fields read as attributes: ``eigenvalues`` (``[{re, im}]``, with
    ``time_constant``, ``natural_frequency`` and ``damping_ratio`` in ``eigen_scales``),
    ``characteristic_polynomial``, ``transfer_function`` (``{input, output, numerator,
    denominator}``, coefficients highest power of ``s`` first, denominator monic),
    ``poles``, ``zeros``, ``dc_gain`` (``None`` for an integrator), ``step`` (rise and
    settling time, overshoot, final value, from the exact modal solution),
    ``linearised_at`` and ``notes``. ``poles_complex`` and friends give numpy arrays.
    A notebook shows the step response; :meth:`bode` and :meth:`step_response` give the
    plots.
    """

    def __init__(self, native: Any) -> None:
        self._native = native
        self.document: Document = _parse(native.json)
        self.text: str = native.text

    def __getattr__(self, name: str) -> Any:
        document = self.__dict__.get("document", {})
        if name not in document:
            raise AttributeError(name)
        return document[name]

    @staticmethod
    def _complex(values: List[Any]) -> np.ndarray:
        return np.array([complex(v["re"], v["im"]) for v in values], dtype=complex)

    @property
    def eigenvalues_complex(self) -> np.ndarray:
        """The eigenvalues of ``A`` as a complex array."""
        return self._complex(self.document["eigenvalues"])

    @property
    def poles_complex(self) -> np.ndarray:
        """The transfer function's poles as a complex array."""
        return self._complex(self.document["poles"])

    @property
    def zeros_complex(self) -> np.ndarray:
        """The transfer function's zeros as a complex array."""
        return self._complex(self.document["zeros"])

    def bode(self) -> Optional[Svg]:
        """The Bode plot (``analyze --bode``), or ``None`` without a transfer function."""
        svg = self._native.bode_svg
        return None if svg is None else Svg(svg)

    def step_response(self) -> Optional[Svg]:
        """The exact step response (``analyze --step``), or ``None`` without a transfer
        function. (``step`` is the document's step metrics.)"""
        svg = self._native.step_svg
        return None if svg is None else Svg(svg)

    def _repr_svg_(self) -> Optional[str]:
        return self._native.step_svg

    def __str__(self) -> str:
        return self.text

    def __repr__(self) -> str:
        return (
            f"<Analysis of {self.document.get('model', '?')}: "
            f"{len(self.document.get('eigenvalues', []))} eigenvalues>"
        )


class Explanation:
    """The derivation of one mode in words (``bondgraph explain``): for a bond graph the
    causality assignment step by step and what the derivation then did, for a linear graph
    the normal tree, its primary and secondary variables, the cut-set and loop equations.

    ``text`` is what the command prints; in Markdown (``format="markdown"``) a notebook
    renders it.
    """

    def __init__(self, text: str, format: str) -> None:
        self.text = text
        self.format = format

    def _repr_markdown_(self) -> Optional[str]:
        return self.text if self.format == "markdown" else None

    def _repr_pretty_(self, printer: Any, cycle: bool) -> None:
        printer.text(self.text)

    def __str__(self) -> str:
        return self.text

    def __repr__(self) -> str:
        first = self.text.splitlines()[0] if self.text else ""
        return f"<Explanation ({self.format}): {first}>"


class Comparison:
    """A student's ``A`` and ``B`` checked against a model (``bondgraph compare``).

    ``verdict`` is ``"equal"``, ``"similar"`` (equal up to a change of state variables,
    ``changes`` says which) or ``"different"`` (``first_difference`` says where);
    ``agrees`` is whether it is equal or similar (the command's exit code 0). ``text`` is
    what the command prints, ``document`` its ``--format json``; the document's fields
    (``transformation``, ``characteristic_polynomial``, ``notes``, ...) read as attributes.
    """

    def __init__(self, native: Any) -> None:
        self.document: Document = _parse(native.json)
        self.text: str = native.text
        self.agrees: bool = native.agrees

    @property
    def verdict(self) -> str:
        """``"equal"``, ``"similar"`` or ``"different"``."""
        return self.document["verdict"]

    def __getattr__(self, name: str) -> Any:
        document = self.__dict__.get("document", {})
        if name not in document:
            raise AttributeError(name)
        return document[name]

    def _repr_pretty_(self, printer: Any, cycle: bool) -> None:
        printer.text(self.text)

    def __str__(self) -> str:
        return self.text

    def __repr__(self) -> str:
        return f"<Comparison: {self.verdict}>"


class Model:
    """A checked model: a bond graph or a linear graph (use :func:`load` or :func:`loads`).

    In a notebook it shows its drawing (``_repr_svg_``): a bond graph with its causal
    strokes, a linear graph with its normal tree.
    """

    def __init__(self, native: Any) -> None:
        self._native = native

    @property
    def name(self) -> str:
        """The model's name."""
        return self._native.name

    @property
    def file(self) -> str:
        """The file name its diagnostics give."""
        return self._native.file

    @property
    def is_linear_graph(self) -> bool:
        """Whether the file is a linear graph."""
        return self._native.is_linear_graph

    @property
    def is_nonlinear(self) -> bool:
        """Whether some law makes the model nonlinear."""
        return self._native.is_nonlinear

    def check(self) -> str:
        """``bondgraph check``: the one-line summary (raises on any problem)."""
        return self._native.check()

    def modes(self, states: Optional[str] = None) -> Document:
        """``bondgraph modes --format json``: every mode reachable from the initial one,
        ``modes`` (``[{spec, states, guards}]``), each guard ``{element, expression,
        leaves_to}``. ``states``: as for :meth:`equations`."""
        return _parse(self._native.modes(states))

    def equations(
        self,
        mode: Optional[str] = None,
        states: Optional[str] = None,
        outputs: Sequence[str] = (),
        at: Optional[Union[str, Dict[str, float]]] = None,
        equilibrium: bool = False,
        matrices: Optional[str] = None,
    ) -> Equations:
        """``bondgraph equations``: the state equations of one mode.

        Args:
            mode: ``"fr_ge=slip+,fr_ct=stuck"``; default the initial mode.
            states: ``"energy"`` (momenta, displacements) or ``"coenergy"`` (velocities,
                forces); default energy for a bond graph, co-energy for a linear graph, as
                the command line.
            outputs: output equations to add: ``"effort:damper"``, ``"flow:mass"``,
                ``"across:spring"``, ``"integral:flow:mass"``, ...
            at: an operating point, ``"x=1,F=2"`` or ``{"x": 1, "F": 2}``: a nonlinear
                mode's Jacobians are evaluated there.
            equilibrium: search a nonlinear mode's equilibrium ``f(x, u) = 0`` (the inputs
                as ``at`` gives them, starting from its states) and linearise there.
            matrices: ``"dense"`` (numpy arrays), ``"sparse"`` (:class:`SparseMatrix`) or
                ``"auto"``, the default: dense up to 500 states.
        """
        if isinstance(outputs, str):
            outputs = [outputs]
        return Equations(
            self._native.equations(
                mode, states, list(outputs), _point(at), equilibrium, matrices
            )
        )

    def graph(self, mode: Optional[str] = None, format: str = "text") -> str:
        """``bondgraph graph``: the graph of one mode as ``"text"`` (elements, bonds and
        causality; a linear graph's nodes, branches and normal tree), ``"dot"`` (Graphviz)
        or ``"svg"``."""
        return self._native.graph(mode, format)

    def diagram(self, mode: Optional[str] = None) -> Svg:
        """``bondgraph graph --format svg``: a bond graph with its half-arrows, causal
        strokes and bond numbers, or a linear graph with its normal tree."""
        return Svg(self._native.graph(mode, "svg"))

    def explain(self, mode: Optional[str] = None, format: str = "text") -> Explanation:
        """``bondgraph explain``: the derivation of one mode in words, as a teacher would do
        it on the board, as ``"text"`` or ``"markdown"`` (rendered by a notebook).

        Where the mode's causality can be assigned but its equations cannot be derived,
        raises :class:`BondGraphError` saying why, with the explanation as far as it got
        in the error's ``explanation``.
        """
        return Explanation(self._native.explain(mode, format), format)

    def compare(self, answer: PathLike, mode: Optional[str] = None) -> Comparison:
        """``bondgraph compare``: checks an answer's ``A`` and ``B`` (an answer file's path,
        or its RON text ``Answer(states: [...], A: [[...]], B: [[...]])``) against this
        model's equations of ``mode`` (default the initial one)."""
        if isinstance(answer, os.PathLike) or not _looks_like_ron(answer):
            return Comparison(self._native.compare_file(os.fspath(answer), mode))
        return Comparison(self._native.compare_text(answer, "<answer>", mode))

    def analyze(
        self,
        mode: Optional[str] = None,
        input: Optional[str] = None,
        output: Optional[str] = None,
        at: Optional[Union[str, Dict[str, float]]] = None,
        equilibrium: bool = False,
    ) -> Analysis:
        """``bondgraph analyze``: eigenvalues and time scales of one linear mode, the
        transfer function from ``input`` to ``output`` (default: the first input and the
        first state), its poles, zeros, DC gain and step metrics.

        Args:
            mode: as for :meth:`equations`.
            input: an input's name.
            output: a state's name or an output, ``"flow:mass"``, ``"effort:damper"``, ...
            at: a nonlinear model's operating point (``"x=1,F=2"`` or a dict): it is
                linearised there.
            equilibrium: search the equilibrium (from ``at``, or from zero) and linearise
                there.
        """
        return Analysis(self._native.analyze(mode, input, output, _point(at), equilibrium))

    def dot(self, mode: Optional[str] = None) -> str:
        """``bondgraph graph --format dot``: a bond graph with its causal strokes, a linear
        graph with its normal tree (bold) and links (dashed)."""
        return self._native.graph(mode, "dot")

    def _repr_svg_(self) -> str:
        return self._native.graph(None, "svg")

    def simulate(self, scenario: PathLike) -> Simulation:
        """``bondgraph simulate``: runs a scenario, given as a file path or as RON text."""
        if isinstance(scenario, os.PathLike) or not _looks_like_ron(scenario):
            return Simulation(self._native.simulate_file(os.fspath(scenario)))
        return Simulation(self._native.simulate_text(scenario, "<scenario>"))

    def __repr__(self) -> str:
        kind = "linear graph" if self.is_linear_graph else "bond graph"
        return f"<Model {self.name!r} ({kind}) from {self.file}>"


def _point(at: Optional[Union[str, Dict[str, float]]]) -> Optional[str]:
    """An operating point as ``--at`` takes it: ``"x=1,F=2"`` from ``{"x": 1, "F": 2}``."""
    if isinstance(at, dict):
        return ",".join(f"{k}={v!r}" for k, v in at.items())
    return at


def _looks_like_ron(text: str) -> bool:
    """Whether ``text`` is RON rather than a file's path: not an existing file, and either
    several lines or a RON value's opening (``Scenario(``, ``Answer(``, ``(``, ``//``)."""
    if os.path.exists(text):
        return False
    return "\n" in text or re.match(r"\s*(//|/\*|\(|[A-Za-z_]\w*\s*\()", text) is not None


def load(path: PathLike) -> Model:
    """Reads and checks a model file (a bond graph or a linear graph)."""
    return Model(_native.NativeModel.load(os.fspath(path)))


def loads(text: str, name: str = "<string>") -> Model:
    """Checks a model given as RON text; ``name`` is the file name diagnostics give."""
    return Model(_native.NativeModel.loads(text, name))


def compare(model: Union["Model", PathLike], answer: PathLike, mode: Optional[str] = None) -> Comparison:
    """``bondgraph compare MODEL ANSWER``: :meth:`Model.compare` of ``model`` (a
    :class:`Model` or a model file's path)."""
    if not isinstance(model, Model):
        model = load(model)
    return model.compare(answer, mode)


def _paths(data: Union[PathLike, Iterable[PathLike]]) -> List[str]:
    if isinstance(data, (str, os.PathLike)):
        data = [data]
    return [os.fspath(d) for d in data]


def calibrate(
    model: PathLike,
    data: Union[PathLike, Iterable[PathLike]],
    experiment: Optional[PathLike] = None,
) -> Document:
    """``bondgraph calibrate --format json``: the experiment's ``fitted`` parameters fitted
    to the measured ``data`` (one CSV file or several), with their standard errors, the
    residuals by regime and by condition. ``experiment`` defaults to ``experiment.ron``
    beside the model."""
    return _parse(
        _native.calibrate(
            os.fspath(model),
            _paths(data),
            None if experiment is None else os.fspath(experiment),
        )
    )


def reproduce() -> Document:
    """``bondgraph reproduce --format json``: the flagship's tables (``table3``,
    ``table6``), Fig. 6 (``fig6``) and what the refitted model still gets wrong on Table III
    (``discrepancy``, as :func:`discover`). Nothing is written."""
    return _parse(_native.reproduce())


def discover(
    model: PathLike,
    data: Union[PathLike, Iterable[PathLike]],
    experiment: Optional[PathLike] = None,
    extensions: Optional[PathLike] = None,
    out: Optional[PathLike] = None,
) -> Document:
    """``bondgraph discover --format json``: what ``model`` gets wrong on the measured
    ``data`` (one CSV file or several), and which candidate extension explains it.

    ``experiment`` defaults to ``experiment.ron`` beside the model, ``extensions`` to the
    folder ``extensions/`` beside it; several data files are joined (time series: one run
    each, held out one at a time). With ``out``, the report, the JSON, the selected
    extended model and the residual plots are written there too (``discover --out``).

    The document has ``observed``, ``noise`` (``None`` when the data cannot estimate it),
    ``noise_source`` (where it came from), ``pure_error``, ``lack_of_fit``, ``baseline``
    (with the ``evaluations`` its fits took), ``ranking`` (best first; each with its
    ``verdict`` and ``evaluations``), ``selected``, ``indistinguishable`` and ``gain``, as
    the command line prints them.
    """
    return _parse(
        _native.discover(
            os.fspath(model),
            _paths(data),
            None if experiment is None else os.fspath(experiment),
            None if extensions is None else os.fspath(extensions),
            None if out is None else os.fspath(out),
        )
    )
