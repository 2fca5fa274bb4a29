"""Equations, modes and check: the bindings against the command line's JSON, and against
matrices derived by hand."""

import numpy as np
import pytest

import bondgraph
from conftest import EVERSION, EXAMPLES, rel

MODELS = (
    sorted(EXAMPLES.glob("*.ron"))
    + sorted((EXAMPLES / "nonlinear").glob("*.ron"))
    # Models built from parts: the bindings read sub-model files as the command line does.
    + sorted((EXAMPLES / "composed").glob("*.ron"))
)


@pytest.mark.parametrize("path", MODELS, ids=lambda p: p.name)
def test_equations_document_is_the_command_lines(cli, path):
    model = bondgraph.load(rel(path))
    assert model.equations().document == cli.json("equations", rel(path))


@pytest.mark.parametrize("path", MODELS, ids=lambda p: p.name)
def test_modes_document_is_the_command_lines(cli, path):
    model = bondgraph.load(rel(path))
    assert model.modes() == cli.json("modes", rel(path))


@pytest.mark.parametrize("path", MODELS, ids=lambda p: p.name)
def test_check_summary_is_the_command_lines(cli, path):
    model = bondgraph.load(rel(path))
    assert model.check() == cli.run("check", rel(path)).stdout.strip()


def test_every_mode_of_the_flagship_matches_the_command_line(cli):
    path = rel(EVERSION / "robot.ron")
    model = bondgraph.load(path)
    specs = [m["spec"] for m in model.modes()["modes"]]
    assert len(specs) > 1
    for spec in specs:
        ours = model.equations(mode=spec, states="coenergy", outputs=["flow:pressure"])
        theirs = cli.json(
            "equations", path, "--mode", spec, "--states", "coenergy", "--output", "flow:pressure"
        )
        assert ours.document == theirs, spec
        np.testing.assert_array_equal(ours.A_value, np.array(theirs["A_value"], dtype=float))


def test_mass_spring_damper_matrices_by_hand():
    # m = 2 kg, k = 200 N/m, b = 4 N s/m; states p (momentum) and q (spring displacement):
    # dp/dt = -b/m p - k q + F, dq/dt = p/m; the damper's force is b v = b/m p.
    eq = bondgraph.load(rel(EXAMPLES / "mass_spring_damper.ron")).equations(
        outputs=["effort:damper"]
    )
    assert eq.state_names == ["p_mass", "q_spring"]
    assert eq.A.tolist() == [["-b/m", "-k"], ["1/m", "0"]]
    np.testing.assert_allclose(eq.A_value, [[-4 / 2, -200], [1 / 2, 0]], rtol=0, atol=0)
    np.testing.assert_allclose(eq.B_value, [[1], [0]])
    np.testing.assert_allclose(eq.c_value, [[0], [0]])
    assert eq.C.tolist() == [["b/m", "0"]]
    np.testing.assert_allclose(eq.C_value, [[4 / 2, 0]])
    np.testing.assert_allclose(eq.D_value, [[0]])
    assert eq.A_value.dtype == float and eq.A.dtype == object


def test_sparse_matrices_are_the_dense_ones_entry_by_entry():
    # The same mass-spring-damper asked for its non-zero entries: A has three (-b/m, -k,
    # 1/m), B one; expanded, they are the dense matrices above.
    model = bondgraph.load(rel(EXAMPLES / "mass_spring_damper.ron"))
    sparse = model.equations(matrices="sparse")
    assert sparse.matrices == "sparse"
    assert isinstance(sparse.A_value, bondgraph.SparseMatrix)
    assert sparse.A_value.shape == (2, 2) and sparse.A_value.nnz == 3
    assert sparse.A.row.tolist() == [0, 0, 1] and sparse.A.col.tolist() == [0, 1, 0]
    assert sparse.A.data.tolist() == ["-b/m", "-k", "1/m"]
    np.testing.assert_array_equal(sparse.A_value.toarray(), [[-2, -200], [0.5, 0]])
    assert sparse.A.toarray().tolist() == [["-b/m", "-k"], ["1/m", "0"]]
    dense = model.equations(matrices="dense")
    np.testing.assert_array_equal(sparse.B_value.toarray(), dense.B_value)
    with pytest.raises(bondgraph.BondGraphError, match="matrices"):
        model.equations(matrices="triangular")


def test_coenergy_and_linear_graph_defaults():
    # A linear graph is read in co-energy variables by default (Rowell & Wormley's states):
    # the series RLC's capacitor voltage and inductor current.
    eq = bondgraph.load(rel(EXAMPLES / "rlc.lg.ron")).equations()
    assert eq.variables == "coenergy"
    assert eq.A.tolist() == [["-R/L", "-1/L"], ["1/C", "0"]]
    energy = bondgraph.load(rel(EXAMPLES / "mass_spring_damper.ron")).equations(states="coenergy")
    # v = p/m, f = k q: dv/dt = -b/m v - f/m + F/m, df/dt = k v.
    assert energy.A.tolist() == [["-b/m", "-1/m"], ["k", "0"]]


def test_latex_is_the_command_lines(cli):
    path = rel(EXAMPLES / "two_masses.ron")
    eq = bondgraph.load(path).equations()
    printed = cli.run("equations", path, "--format", "latex").stdout
    # The command line opens with `%` comments saying what a LaTeX document needs; a
    # notebook renders the equations alone.
    body = "".join(line for line in printed.splitlines(keepends=True) if not line.startswith("%"))
    assert printed.startswith("% State equations of 'two_masses'")
    assert eq._repr_latex_() == body


def test_nonlinear_jacobians_at_a_point_match_the_command_line(cli):
    path = rel(EXAMPLES / "nonlinear" / "pendulum.ron")
    model = bondgraph.load(path)
    names = model.equations().state_names
    point = {names[0]: 0.3}
    ours = model.equations(at=point)
    theirs = cli.json("equations", path, "--at", f"{names[0]}=0.3")
    assert ours.document == theirs
    assert len(ours.f) == len(names)
    np.testing.assert_array_equal(ours.A_value, np.array(theirs["A_value"], dtype=float))


def test_loads_reads_text_like_a_file():
    text = (EXAMPLES / "mass_spring_damper.ron").read_text()
    from_text = bondgraph.loads(text, "msd.ron")
    assert from_text.file == "msd.ron"
    assert from_text.equations().document == bondgraph.load(
        rel(EXAMPLES / "mass_spring_damper.ron")
    ).equations().document
