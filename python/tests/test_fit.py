"""Measured data: discover on the flagship, against the command line's JSON."""

import pytest

import bondgraph
from conftest import EVERSION, EXAMPLES, rel


def test_discover_on_table3_is_the_command_lines(cli):
    model, data = rel(EVERSION / "robot.ron"), rel(EVERSION / "data" / "table3.csv")
    ours = bondgraph.discover(model, data)
    theirs = cli.json("discover", "--model", model, "--data", data)
    assert ours["selected"] == theirs["selected"]
    assert [r["id"] for r in ours["ranking"]] == [r["id"] for r in theirs["ranking"]]
    assert ours["indistinguishable"] == theirs["indistinguishable"]
    assert ours == theirs
    # Attribute access reads the same document.
    assert ours.baseline == theirs["baseline"]
    assert len(ours.ranking) == 8


def test_calibrate_is_the_command_lines(cli):
    # The geared motor's data were made by data/generate.py with K = 0.05 N m/A,
    # b = 0.05 N m s/rad, T_C = 0.15 N m, T_S = 0.3 N m (see its data/README.md).
    motor = EXAMPLES / "geared_motor"
    model, data = rel(motor / "geared_motor.ron"), rel(motor / "data" / "steady.csv")
    ours = bondgraph.calibrate(model, data)
    assert ours == cli.json("calibrate", "--model", model, "--data", data)
    assert ours == bondgraph.calibrate(model, [data], experiment=rel(motor / "experiment.ron"))


def test_calibrate_names_a_missing_experiment(tmp_path):
    model = tmp_path / "m.ron"
    model.write_text((EXAMPLES / "mass_spring_damper.ron").read_text())
    data = tmp_path / "d.csv"
    data.write_text("F,v\n1,2\n")
    with pytest.raises(bondgraph.BondGraphError) as error:
        bondgraph.calibrate(str(model), str(data))
    assert "experiment.ron" in str(error.value)


def test_reproduce_is_the_command_lines(cli, tmp_path):
    ours = bondgraph.reproduce()
    theirs = cli.json("reproduce", "--out", str(tmp_path))
    assert ours == theirs
    assert len(ours.table3) == 27 and len(ours.table6) == 6
