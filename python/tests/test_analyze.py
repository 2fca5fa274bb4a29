"""analyze: the bindings against the command line's JSON, and against closed forms."""

import math

import numpy as np
import pytest

import bondgraph
from conftest import EXAMPLES, ROOT, rel

LINEAR = [p for p in sorted(EXAMPLES.glob("*.ron")) if "belt_friction" not in p.name]


@pytest.mark.parametrize("path", LINEAR, ids=lambda p: p.name)
def test_analysis_document_is_the_command_lines(cli, path):
    ours = bondgraph.load(rel(path)).analyze()
    assert ours.document == cli.json("analyze", rel(path))


def test_mass_spring_damper_against_its_closed_form(cli):
    # m = 2 kg, k = 200 N/m, b = 4 N s/m: s^2 + (b/m) s + k/m = s^2 + 2 s + 100, so
    # wn = 10 rad/s, zeta = 0.1, poles -1 +- j sqrt(99); F -> q_spring is 1/(m s^2 + b s + k),
    # DC gain 1/k = 0.005 m/N.
    path = rel(EXAMPLES / "mass_spring_damper.ron")
    ours = bondgraph.load(path).analyze(input="F", output="q_spring")
    # Sorted by imaginary part: the real parts agree only to rounding (-1 and -0.9999999999999999
    # from the state matrix's eigenvalues), which would decide a sort by real part first.
    poles = sorted(ours.poles_complex, key=lambda z: z.imag)
    np.testing.assert_allclose(poles, [complex(-1, -math.sqrt(99)), complex(-1, math.sqrt(99))], rtol=1e-12)
    np.testing.assert_allclose(ours.transfer_function["denominator"], [1, 2, 100], rtol=1e-12)
    assert ours.dc_gain == pytest.approx(1 / 200, rel=1e-12)
    for e in ours.eigen_scales:
        assert e["natural_frequency"] == pytest.approx(10, rel=1e-12)
        assert e["damping_ratio"] == pytest.approx(0.1, rel=1e-12)
    assert ours.document == cli.json(
        "analyze", path, "--input", "F", "--output", "q_spring"
    )


def test_plots_are_the_command_lines(cli, tmp_path):
    path = rel(EXAMPLES / "mass_spring_damper.ron")
    ours = bondgraph.load(path).analyze()
    bode, step = tmp_path / "bode.svg", tmp_path / "step.svg"
    cli.run("analyze", path, "--bode", str(bode), "--step", str(step))
    assert ours.bode().text == bode.read_text()
    assert ours.step_response().text == step.read_text()
    assert ours._repr_svg_() == ours.step_response().text
    # `step` is the document's field, the metrics of the exact step response.
    assert ours.step == cli.json("analyze", path)["step"]
    assert str(ours) == cli.run("analyze", path).stdout


def test_a_nonlinear_model_is_linearised_at_its_equilibrium(cli):
    path = rel(EXAMPLES / "nonlinear" / "pendulum.ron")
    ours = bondgraph.load(path).analyze(equilibrium=True)
    assert ours.document == cli.json("analyze", path, "--equilibrium")
    assert ours.linearised_at is not None


def test_an_unknown_input_is_a_diagnostic():
    model = bondgraph.load(rel(EXAMPLES / "mass_spring_damper.ron"))
    with pytest.raises(bondgraph.BondGraphError) as error:
        model.analyze(input="nope")
    assert "--input 'nope' is not an input" in str(error.value)
    assert error.value.diagnostics[0].kind == "UnknownName"


def test_a_bond_graph_draws_itself(cli):
    path = rel(EXAMPLES / "mass_spring_damper.ron")
    model = bondgraph.load(path)
    assert model.diagram().text == cli.run("graph", path, "--format", "svg").stdout
    assert model._repr_svg_() == model.diagram().text


@pytest.mark.parametrize("angle", [0.3, math.pi])
def test_a_nonlinear_model_is_linearised_at_a_point(cli, angle):
    # The pendulum: dp/dt = -m g l sin(q), dq/dt = p/(m l^2), m = l = 1, g = 9.81. At the
    # angle q0 the Jacobian is [[0, -g cos q0], [1, 0]]: eigenvalues +-sqrt(-g cos q0),
    # a swing at sqrt(g cos q0) rad/s hanging, a fall at e^(sqrt(g) t) upside down.
    path = rel(EXAMPLES / "nonlinear" / "pendulum.ron")
    model = bondgraph.load(path)
    names = model.equations().state_names
    theta = next(n for n in names if n.startswith("q"))
    ours = model.analyze(at={theta: angle})
    assert ours.document == cli.json("analyze", path, "--at", f"{theta}={angle!r}")
    expected = np.sqrt(complex(-9.81 * math.cos(angle)))
    np.testing.assert_allclose(
        np.sort_complex(ours.eigenvalues_complex),
        np.sort_complex([-expected, expected]),
        rtol=1e-12,
        atol=1e-12,
    )


def test_the_equilibrium_search_starts_from_the_point_given(cli):
    # Started near the top, Newton finds the upright equilibrium q = pi, whose
    # linearisation has the real pair +-sqrt(g).
    path = rel(EXAMPLES / "nonlinear" / "pendulum.ron")
    model = bondgraph.load(path)
    theta = next(n for n in model.equations().state_names if n.startswith("q"))
    ours = model.analyze(at=f"{theta}=3.0", equilibrium=True)
    assert ours.document == cli.json("analyze", path, "--at", f"{theta}=3.0", "--equilibrium")
    np.testing.assert_allclose(
        np.sort(ours.eigenvalues_complex.real), [-math.sqrt(9.81), math.sqrt(9.81)], rtol=1e-9
    )
