"""The teaching commands (explain, compare, graph, the equations' text and LaTeX): the
bindings against what the command line prints, byte for byte."""

import json

import pytest

import bondgraph
from conftest import EVERSION, EXAMPLES, ROOT, rel

TEACHING = ROOT / "models" / "teaching"
ANSWERS = TEACHING / "answers"

# Bond graphs and linear graphs, linear and nonlinear, and the teaching folder's models.
MODELS = (
    sorted(EXAMPLES.glob("*.ron"))
    + sorted((EXAMPLES / "nonlinear").glob("*.ron"))
    + sorted(TEACHING.glob("*.ron"))
)
LINEAR_GRAPHS = [p for p in MODELS if p.name.endswith(".lg.ron")]

# (model, answer) as models/teaching/commands.txt pairs them, and the exit code it expects.
ANSWERED = [
    ("mass_spring_damper.ron", "msd_correct.ron", 0),
    ("mass_spring_damper.ron", "msd_coenergy.ron", 0),
    ("mass_spring_damper.ron", "msd_sign_error.ron", 1),
    ("quarter_car.ron", "quarter_car_deflections.ron", 0),
    ("dc_motor.ron", "dc_motor_coenergy.ron", 0),
]


@pytest.mark.parametrize("path", MODELS, ids=lambda p: p.name)
@pytest.mark.parametrize("format", ["text", "markdown"])
def test_explanation_is_the_command_lines(cli, path, format):
    ours = bondgraph.load(rel(path)).explain(format=format)
    assert ours.text == cli.run("explain", rel(path), "--format", format).stdout
    assert ours.format == format
    assert (ours._repr_markdown_() is not None) == (format == "markdown")


def test_every_flagship_mode_is_explained_as_the_command_line_does(cli):
    path = rel(EVERSION / "robot.ron")
    model = bondgraph.load(path)
    specs = [m["spec"] for m in model.modes()["modes"]]
    assert len(specs) == 18
    for spec in specs:
        ours = model.explain(mode=spec)
        assert ours.text == cli.run("explain", path, "--mode", spec).stdout, spec


@pytest.mark.parametrize("model,answer,code", ANSWERED, ids=lambda x: str(x))
def test_comparison_is_the_command_lines(cli, model, answer, code):
    model_path, answer_path = rel(TEACHING / model), rel(ANSWERS / answer)
    ours = bondgraph.load(model_path).compare(answer_path)
    text = cli.run("compare", model_path, answer_path, ok=False)
    document = cli.run("compare", model_path, answer_path, "--format", "json", ok=False)
    assert text.returncode == document.returncode == code
    assert ours.text == text.stdout
    assert ours.document == json.loads(document.stdout)
    assert ours.agrees == (code == 0)
    assert ours.verdict == ours.document["verdict"]
    assert str(ours) == ours.text


def test_a_sign_error_is_found_where_the_answer_says_plus_k():
    # msd_sign_error.ron writes dv/dt = +k/m x - b/m v: the spring pushes the mass away.
    # The model's m dv/dt = -k x - b v + F differs from it in A's (v, x) entry and nowhere
    # else, so that entry is named and the verdict is "different".
    result = bondgraph.compare(
        rel(TEACHING / "mass_spring_damper.ron"), rel(ANSWERS / "msd_sign_error.ron")
    )
    assert result.verdict == "different" and not result.agrees
    # Row 2 (dv/dt) and column 1 (x) in the answer's states (x_spring, v_mass).
    assert result.first_difference.startswith("A[2][1]")
    assert "k/m in the answer, -k/m in the model" in result.first_difference


def test_a_path_is_never_read_as_ron(tmp_path, monkeypatch):
    # A relative path that opens like a RON value is still a path when the file exists.
    monkeypatch.chdir(tmp_path)
    folder = tmp_path / "Answer(1)"
    folder.mkdir()
    (folder / "a.ron").write_text((ANSWERS / "msd_correct.ron").read_text())
    model = bondgraph.load(TEACHING / "mass_spring_damper.ron")
    assert model.compare("Answer(1)/a.ron").verdict == "equal"


def test_an_answer_as_text_is_compared_like_a_file(cli):
    # The mass-spring-damper in the program's own states, p = m v and q:
    # dp/dt = -(b/m) p - k q + F, dq/dt = p/m. It is the model, entry for entry.
    model = bondgraph.load(rel(TEACHING / "mass_spring_damper.ron"))
    answer = (
        'Answer(\n    states: ["p_mass", "q_spring"],\n'
        '    A: [["-b/m", "-k"], ["1/m", "0"]],\n    B: [["1"], ["0"]],\n)\n'
    )
    ours = model.compare(answer)
    assert ours.verdict == "equal" and ours.agrees
    assert ours.document == model.compare(rel(ANSWERS / "msd_correct.ron")).document


@pytest.mark.parametrize("path", MODELS, ids=lambda p: p.name)
@pytest.mark.parametrize("format", ["text", "dot", "svg"])
def test_graph_is_the_command_lines(cli, path, format):
    model = bondgraph.load(rel(path))
    ours = model.graph(format=format)
    assert ours == cli.run("graph", rel(path), "--format", format).stdout
    if format == "svg":
        assert model.diagram().text == ours and model._repr_svg_() == ours
    if format == "dot":
        assert model.dot() == ours


def test_every_flagship_mode_is_drawn_as_the_command_line_does(cli):
    path = rel(EVERSION / "robot.lg.ron")
    model = bondgraph.load(path)
    for spec in [m["spec"] for m in model.modes()["modes"]]:
        for format in ("text", "dot", "svg"):
            theirs = cli.run("graph", path, "--mode", spec, "--format", format).stdout
            assert model.graph(mode=spec, format=format) == theirs, (spec, format)


@pytest.mark.parametrize("path", MODELS, ids=lambda p: p.name)
def test_equations_text_and_latex_are_the_command_lines(cli, path):
    eq = bondgraph.load(rel(path)).equations()
    assert eq.text == cli.run("equations", rel(path)).stdout
    assert str(eq) == eq.text
    printed = cli.run("equations", rel(path), "--format", "latex").stdout
    assert eq.latex_document == printed
    # The notebook renders the equations without the comment about amsmath.
    assert printed.endswith(eq.latex) and printed[: -len(eq.latex)].startswith("%")


def test_outputs_and_guards_are_in_the_text(cli):
    path = rel(EXAMPLES / "belt_friction.ron")
    eq = bondgraph.load(path).equations(mode="friction=stuck", outputs=["effort:spring"])
    theirs = cli.run(
        "equations", path, "--mode", "friction=stuck", "--output", "effort:spring"
    ).stdout
    assert eq.text == theirs
    assert "\noutputs:\n" in eq.text and "\nguards:\n" in eq.text


def test_a_nonlinear_equilibrium_is_the_command_lines(cli):
    # The pendulum hangs at rest at its equilibrium: the angle and the momentum are zero.
    path = rel(EXAMPLES / "nonlinear" / "pendulum.ron")
    ours = bondgraph.load(path).equations(equilibrium=True)
    assert ours.document == cli.json("equations", path, "--equilibrium")
    assert ours.text == cli.run("equations", path, "--equilibrium").stdout
    assert "equilibrium: f = 0" in ours.text


def test_a_linear_model_has_no_equilibrium_to_search():
    model = bondgraph.load(rel(EXAMPLES / "mass_spring_damper.ron"))
    with pytest.raises(bondgraph.BondGraphError, match="--equilibrium is for nonlinear"):
        model.equations(equilibrium=True)
