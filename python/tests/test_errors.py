"""Bad input raises BondGraphError with the diagnostics the command line prints; it never
crashes the interpreter nor raises anything else."""

import re

import pytest

import bondgraph
from conftest import EXAMPLES, rel

BAD_ELEMENT = """Model(
    name: "bad",
    parameters: { "m": (value: 2.0) },
    inputs: {},
    elements: {
        "mass": Q(inertance: "m"),
    },
    bonds: [],
)
"""


def cli_locations(stderr: str):
    return [(f, int(l), int(c)) for f, l, c in re.findall(r"--> (\S+?):(\d+):(\d+)", stderr)]


def test_diagnostics_carry_file_line_column_element(cli, tmp_path):
    path = tmp_path / "bad.ron"
    path.write_text(BAD_ELEMENT)
    with pytest.raises(bondgraph.BondGraphError) as caught:
        bondgraph.load(path)
    (diagnostic,) = caught.value.diagnostics
    # Line 6, column 17: the `Q` of `"mass": Q(...)`.
    assert (diagnostic.file, diagnostic.line, diagnostic.column) == (str(path), 6, 17)
    assert diagnostic.element == "mass"
    assert "unknown element kind 'Q'" in diagnostic.message
    done = cli.run("check", str(path), ok=False)
    assert done.returncode != 0
    assert cli_locations(done.stderr) == [(str(path), 6, 17)]
    # The message is the command line's rendering, snippet and caret included.
    assert str(caught.value) == done.stderr.strip()


def test_every_problem_is_listed(cli, tmp_path):
    text = (EXAMPLES / "mass_spring_damper.ron").read_text()
    broken = text.replace('I(inertance: "m")', 'I(inertance: "mm")').replace(
        'C(stiffness: "k")', 'C(stiffness: "kk")'
    )
    assert broken != text
    path = tmp_path / "two.ron"
    path.write_text(broken)
    with pytest.raises(bondgraph.BondGraphError) as caught:
        bondgraph.load(path)
    ours = [(d.file, d.line, d.column) for d in caught.value.diagnostics]
    assert ours == cli_locations(cli.run("check", str(path), ok=False).stderr)
    assert len(ours) >= 1


def test_scenario_problems_point_into_the_scenario():
    model = bondgraph.load(rel(EXAMPLES / "mass_spring_damper.ron"))
    text = 'Scenario(\n    name: "s",\n    inputs: {"G": Constant(1.0)},\n    duration: 1.0,\n    record: [],\n)\n'
    with pytest.raises(bondgraph.BondGraphError) as caught:
        model.simulate(text)
    files = {d.file for d in caught.value.diagnostics}
    assert "<scenario>" in files
    assert any(d.line == 3 for d in caught.value.diagnostics)


@pytest.mark.parametrize(
    "call",
    [
        lambda m: m.equations(mode="nonsense=stuck"),
        lambda m: m.equations(states="momentum"),
        lambda m: m.equations(outputs=["effort:nobody"]),
        lambda m: m.equations(at="x=1"),
        lambda m: m.simulate("no/such/scenario.ron"),
        lambda m: m.modes(states="neither"),
    ],
)
def test_bad_arguments_raise(call):
    model = bondgraph.load(rel(EXAMPLES / "mass_spring_damper.ron"))
    with pytest.raises(bondgraph.BondGraphError) as caught:
        call(model)
    assert caught.value.diagnostics and all(d.message for d in caught.value.diagnostics)


@pytest.mark.parametrize(
    "text",
    [
        "",
        "Model(",
        "LinearGraph(name: 1)",
        "\x00\xff\ufffd",
        "Model(name: \"x\", parameters: {}, inputs: {}, elements: {}, bonds: [])",
        (EXAMPLES / "mass_spring_damper.ron").read_text()[:200],
        (EXAMPLES / "rlc.lg.ron").read_text().replace('ground: "g"', 'ground: "gg"'),
        "Model(name: \"x\", parameters: {\"m\": (value: 1e999)}, inputs: {}, elements: {}, bonds: [])",
        # Deep nesting must be refused, not overflow the stack (which would kill Python).
        "Model(" + "[" * 100_000,
        'Model(name: "x", parameters: {"a": (value: 1.0)}, inputs: {}, elements: {"s": Se(effort: "'
        + "(" * 100_000 + "a" + ")" * 100_000 + '")}, bonds: [])',
    ],
)
def test_malformed_text_raises_bondgraph_error_only(text):
    with pytest.raises(bondgraph.BondGraphError):
        bondgraph.loads(text, "fuzz.ron")


def test_missing_file():
    with pytest.raises(bondgraph.BondGraphError, match="cannot read"):
        bondgraph.load("no/such/model.ron")


def test_error_is_an_exception_subclass():
    assert issubclass(bondgraph.BondGraphError, Exception)


MSD = EXAMPLES.parent / "teaching" / "mass_spring_damper.ron"


@pytest.mark.parametrize(
    "answer,line",
    [
        (
            'Answer(\n    states: ["p_mass", "q_spring"],\n    A: [["-b/m", "-k"],\n'
            '        ["1/m", "0 + zeta"]],\n    B: [["1"], ["0"]],\n)\n',
            4,
        ),
        ('Answer(\n  A: [["0"]],\n  B: 3,\n)\n', 3),
    ],
    ids=["unknown-symbol", "not-a-matrix"],
)
def test_a_bad_answer_is_located_in_its_file(cli, tmp_path, answer, line):
    path = tmp_path / "answer.ron"
    path.write_text(answer)
    model = bondgraph.load(rel(MSD))
    with pytest.raises(bondgraph.BondGraphError) as caught:
        model.compare(path)
    done = cli.run("compare", rel(MSD), str(path), ok=False)
    assert done.returncode == 2
    assert str(caught.value) == done.stderr.strip()
    (diagnostic,) = caught.value.diagnostics
    assert (diagnostic.file, diagnostic.line) == (str(path), line)
    assert cli_locations(done.stderr) == [(str(path), line, diagnostic.column)]
    # Given as text, the answer is the file "<answer>".
    with pytest.raises(bondgraph.BondGraphError) as caught:
        model.compare(answer)
    assert [(d.file, d.line) for d in caught.value.diagnostics] == [("<answer>", line)]


def test_a_nonlinear_model_has_no_answer_to_compare():
    pendulum = bondgraph.load(rel(EXAMPLES / "nonlinear" / "pendulum.ron"))
    with pytest.raises(bondgraph.BondGraphError, match="is nonlinear"):
        pendulum.compare('Answer(A: [["0"]], B: [["0"]])')


SHORT = """Model(
    name: "short",
    parameters: { "R": (value: 0.0), "C": (value: 1.0) },
    inputs: { "E": () },
    elements: {
        "source": Se(effort: "E"),
        "j": One,
        "wire": R(resistance: "R"),
        "cap": C(compliance: "C"),
    },
    bonds: [("source", "j"), ("j", "wire"), ("j", "cap")],
)
"""


def test_an_underivable_mode_is_explained_as_far_as_it_goes(cli, tmp_path):
    # A source straight across a zero resistance: the causality can be assigned (the
    # resistor in conductance causality) but its flow E/R cannot be formed.
    path = tmp_path / "short.ron"
    path.write_text(SHORT)
    model = bondgraph.load(path)
    with pytest.raises(bondgraph.BondGraphError) as caught:
        model.explain()
    done = cli.run("explain", str(path), ok=False)
    assert done.returncode == 1
    assert caught.value.explanation == done.stdout
    assert str(caught.value) == done.stderr.strip()
    (diagnostic,) = caught.value.diagnostics
    assert (diagnostic.file, diagnostic.line, diagnostic.element) == (str(path), 8, "wire")
    assert "resistance is zero" in diagnostic.message
    # The same mode's graph is refused, as `check` refuses the model.
    with pytest.raises(bondgraph.BondGraphError, match="resistance is zero"):
        model.graph()
    assert bondgraph.BondGraphError("by hand").explanation is None


@pytest.mark.parametrize(
    "call,message",
    [
        (lambda m: m.explain(format="html"), 'format must be "text" or "markdown", not "html"'),
        (lambda m: m.graph(format="png"), 'format must be "text" or "dot" or "svg", not "png"'),
        (lambda m: m.explain(mode="nobody=stuck"), "nobody"),
        (lambda m: m.graph(mode="nobody=stuck"), "nobody"),
        (lambda m: m.compare("no/such/answer.ron"), "cannot read"),
        (lambda m: m.analyze(at="nobody=1"), "nobody"),
    ],
)
def test_bad_teaching_arguments_raise(call, message):
    model = bondgraph.load(rel(EXAMPLES / "mass_spring_damper.ron"))
    with pytest.raises(bondgraph.BondGraphError) as caught:
        call(model)
    assert message in str(caught.value)
    assert caught.value.diagnostics
