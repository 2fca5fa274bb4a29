"""Measured data: discover on the flagship, against the command line's JSON."""

import bondgraph
from conftest import EVERSION, rel


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
