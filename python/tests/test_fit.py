"""Measured data: discover on the flagship, against the command line's JSON."""

import json

import pytest

import bondgraph
from bondgraph import Document
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


def split_csv(path, folder, parts=2):
    """``path``'s rows in ``parts`` files under ``folder``, each with the header: joined
    again, they are the same data."""
    header, *rows = path.read_text().splitlines(keepends=True)
    step = -(-len(rows) // parts)
    files = []
    for k in range(parts):
        part = folder / f"{path.stem}_{k}.csv"
        part.write_text(header + "".join(rows[k * step : (k + 1) * step]))
        files.append(str(part))
    return files


def test_calibrate_joins_several_data_files(cli, tmp_path):
    motor = EXAMPLES / "geared_motor"
    model, experiment = rel(motor / "geared_motor.ron"), rel(motor / "experiment.ron")
    whole = rel(motor / "data" / "steady.csv")
    parts = split_csv(motor / "data" / "steady.csv", tmp_path)
    ours = bondgraph.calibrate(model, parts, experiment=experiment)
    args = [a for p in parts for a in ("--data", p)]
    assert ours == cli.json("calibrate", "--model", model, *args, "--experiment", experiment)
    # The same rows in two files are the same least-squares problem: the same optimum.
    one = bondgraph.calibrate(model, whole)
    assert ours["rows"] == one["rows"] == 22
    for name, estimate in one["params"].items():
        assert ours["params"][name]["value"] == pytest.approx(estimate["value"], rel=1e-9), name


def test_discover_takes_several_files_an_experiment_and_an_extensions_folder(cli, tmp_path):
    # Table III in two files, the experiment named, a library of one candidate: the
    # bindings' document is the command line's, evaluations included.
    library = tmp_path / "library"
    library.mkdir()
    (library / "ac-fluid-displacement.ron").write_text(
        (EVERSION / "extensions" / "ac-fluid-displacement.ron").read_text()
    )
    model, experiment = rel(EVERSION / "robot.ron"), rel(EVERSION / "experiment.ron")
    parts = split_csv(EVERSION / "data" / "table3.csv", tmp_path)
    out = tmp_path / "ours"
    ours = bondgraph.discover(model, parts, experiment=experiment, extensions=library, out=out)
    theirs_out = tmp_path / "theirs"
    args = [a for p in parts for a in ("--data", p)]
    theirs = cli.json(
        "discover", "--model", model, *args, "--experiment", experiment,
        "--extensions", str(library), "--out", str(theirs_out),
    )
    assert ours == theirs
    assert [r["id"] for r in ours.ranking] == ["ac-fluid-displacement"]
    # Each fit reports its cost: at least one prediction of each of the 27 rows.
    assert ours.baseline["evaluations"] >= 27
    assert all(r["evaluations"] >= 27 for r in ours.ranking)
    written = sorted(p.name for p in out.iterdir())
    assert written == sorted(p.name for p in theirs_out.iterdir())
    assert "discover.json" in written and "residuals_before.svg" in written
    assert Document.of(json.loads((out / "discover.json").read_text())) == ours


def test_discover_names_a_bad_extension(tmp_path):
    library = tmp_path / "library"
    library.mkdir()
    (library / "broken.ron").write_text("Extension(\n    id: 3,\n)\n")
    with pytest.raises(bondgraph.BondGraphError) as error:
        bondgraph.discover(rel(EVERSION / "robot.ron"), rel(EVERSION / "data" / "table3.csv"), extensions=library)
    located = [d for d in error.value.diagnostics if d.file == str(library / "broken.ron")]
    assert located and located[0].line is not None


def test_a_bad_data_cell_names_its_file_row_and_column(cli, tmp_path):
    data = tmp_path / "bad.csv"
    data.write_text("V_V,tau_mNm,w_rad_s\n1,,0.7\n2,,abc\n")
    model = rel(EXAMPLES / "geared_motor" / "geared_motor.ron")
    with pytest.raises(bondgraph.BondGraphError) as error:
        bondgraph.calibrate(model, data)
    theirs = cli.run("calibrate", "--model", model, "--data", str(data), ok=False)
    assert theirs.returncode != 0
    # The message is the command line's: the file, the line (3) and the column.
    assert str(error.value) == theirs.stderr.strip()
    assert f"{data}:3" in str(error.value) and "w_rad_s" in str(error.value)


def test_no_data_file_is_an_error():
    with pytest.raises(bondgraph.BondGraphError, match="no data file"):
        bondgraph.calibrate(rel(EXAMPLES / "geared_motor" / "geared_motor.ron"), [])
