"""bondgraph: bond graphs and linear graphs in RON, in Python.

Load a model file (a bond graph ``Model(...)`` or a linear graph ``LinearGraph(...)``),
derive its state equations with symbolic entries, simulate it exactly through its mode
changes, and compare it with measured data: the ``bondgraph`` command line's commands as
functions and methods that return Python objects. Every result carries the command's JSON
document (``.document``), field for field; matrices of numbers are numpy arrays and
symbolic matrices are numpy arrays of strings.

In a notebook, three lines derive, simulate and plot::

    import bondgraph
    msd = bondgraph.load("models/examples/mass_spring_damper.ron")
    msd.equations()                      # shown as LaTeX
    msd.simulate("models/scenarios/...") # shown as a plot, the modes shaded

Problems with a file raise :class:`BondGraphError`, whose ``diagnostics`` name the file,
line, column and element of each problem.
"""

from __future__ import annotations

import json
import os
from typing import Any, Dict, Iterable, List, Optional, Sequence, Union

import numpy as np

from . import _native
from ._native import BondGraphError, Diagnostic

__all__ = [
    "Analysis",
    "BondGraphError",
    "Diagnostic",
    "Document",
    "Equations",
    "Model",
    "Simulation",
    "Svg",
    "calibrate",
    "discover",
    "load",
    "loads",
    "reproduce",
]

__version__ = _native.__version__

# Raised by the bindings, an error always has its diagnostics; one made by hand has none.
BondGraphError.diagnostics = ()

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


class Equations:
    """The state equations of one mode, ``bondgraph equations --format json``.

    A linear mode has ``A``, ``B``, ``c`` (symbolic: arrays of strings) and ``A_value``,
    ``B_value``, ``c_value`` (float arrays), ``E`` and ``E_value`` where input derivatives
    enter, and with outputs ``C``, ``D``, ``d`` (and ``F``) with their ``_value`` twins. A
    nonlinear mode has ``f`` (one string per state) and, at an operating point, its
    Jacobians ``A``, ``B``. ``c`` and ``d`` are column vectors. Any other field of the
    document reads as an attribute too (``states``, ``inputs``, ``mode``, ...).
    """

    def __init__(self, native: Any) -> None:
        self.document: Document = _parse(native.json)
        self.latex: str = native.latex
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
    document's fields. A notebook shows the plot of ``bondgraph simulate --plot``.
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

    def plot(self) -> Svg:
        """The outputs against time with the modes shaded (``simulate --plot``)."""
        return Svg(self._native.plot_svg())

    def _repr_svg_(self) -> str:
        return self._native.plot_svg()

    def __repr__(self) -> str:
        return (
            f"<Simulation of {self.document.get('model', '?')}: {len(self.t)} samples, "
            f"{len(self.events)} events>"
        )


class Analysis:
    """One linear mode analysed, ``bondgraph analyze --format json``.

    The document's fields read as attributes: ``eigenvalues`` (``[{re, im, time_constant,
    natural_frequency, damping_ratio}]`` in ``eigen_scales``), ``characteristic_polynomial``, ``transfer_function``
    (``{input, output, numerator, denominator}``, coefficients highest power of ``s``
    first, denominator monic), ``poles``, ``zeros``, ``dc_gain`` (``None`` for an
    integrator), ``step`` (rise and settling time, overshoot, final value, from the exact
    modal solution) and ``notes``. ``poles_complex`` and friends give numpy arrays.
    A notebook shows the step response; ``bode()`` and ``step()`` give the plots.
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

    def step(self) -> Optional[Svg]:
        """The exact step response (``analyze --step``), or ``None`` without a transfer
        function."""
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
        """
        if isinstance(outputs, str):
            outputs = [outputs]
        if isinstance(at, dict):
            at = ",".join(f"{k}={v!r}" for k, v in at.items())
        return Equations(self._native.equations(mode, states, list(outputs), at))

    def diagram(self, mode: Optional[str] = None) -> Svg:
        """``bondgraph graph --format svg``: a bond graph with its half-arrows, causal
        strokes and bond numbers, or a linear graph with its normal tree."""
        return Svg(self._native.graph_svg(mode))

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
        if isinstance(at, dict):
            at = ",".join(f"{k}={v!r}" for k, v in at.items())
        return Analysis(self._native.analyze(mode, input, output, at, equilibrium))

    def dot(self, mode: Optional[str] = None) -> Optional[str]:
        """``bondgraph graph --format dot`` of a bond graph, with its causal strokes."""
        return self._native.graph_dot(mode)

    def _repr_svg_(self) -> Optional[str]:
        return self._native.graph_svg(None)

    def simulate(self, scenario: PathLike) -> Simulation:
        """``bondgraph simulate``: runs a scenario, given as a file path or as RON text."""
        if isinstance(scenario, os.PathLike) or not _looks_like_ron(scenario):
            return Simulation(self._native.simulate_file(os.fspath(scenario)))
        return Simulation(self._native.simulate_text(scenario, "<scenario>"))

    def __repr__(self) -> str:
        kind = "linear graph" if self.is_linear_graph else "bond graph"
        return f"<Model {self.name!r} ({kind}) from {self.file}>"


def _looks_like_ron(text: str) -> bool:
    stripped = text.lstrip()
    return "\n" in text or stripped.startswith(("Scenario", "(", "//", "Model", "LinearGraph"))


def load(path: PathLike) -> Model:
    """Reads and checks a model file (a bond graph or a linear graph)."""
    return Model(_native.NativeModel.load(os.fspath(path)))


def loads(text: str, name: str = "<string>") -> Model:
    """Checks a model given as RON text; ``name`` is the file name diagnostics give."""
    return Model(_native.NativeModel.loads(text, name))


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
) -> Document:
    """``bondgraph discover --format json``: what ``model`` gets wrong on the measured
    ``data`` (one CSV file or several), and which candidate extension explains it.

    ``experiment`` defaults to ``experiment.ron`` beside the model, ``extensions`` to the
    folder ``extensions/`` beside it. The document has ``observed``, ``noise`` (``None``
    when the data cannot estimate it), ``noise_source`` (where it came from),
    ``pure_error``, ``lack_of_fit``, ``baseline``, ``ranking`` (best first), ``selected``,
    ``indistinguishable`` and ``gain``, as the command line prints them.
    """
    return _parse(
        _native.discover(
            os.fspath(model),
            _paths(data),
            None if experiment is None else os.fspath(experiment),
            None if extensions is None else os.fspath(extensions),
        )
    )
