"""Simulations: the bindings' arrays and events against the command line's JSON, and
event times derived by hand."""

import math

import numpy as np
import pytest

import bondgraph
from conftest import EVERSION, EXAMPLES, SCENARIOS, rel

RUNS = [
    (EXAMPLES / "belt_friction.ron", SCENARIOS / "belt_stick_slip.ron"),
    (EVERSION / "robot.ron", SCENARIOS / "robot_growth.ron"),
    (EVERSION / "robot.ron", EVERSION / "fig6.ron"),
    (EVERSION / "paper.ron", EVERSION / "fig6.ron"),
    (EXAMPLES / "nonlinear" / "pendulum.ron", SCENARIOS / "nonlinear" / "pendulum_release.ron"),
    (EXAMPLES / "nonlinear" / "stick_slip_spring.ron", SCENARIOS / "nonlinear" / "stick_slip_spring.ron"),
    (EXAMPLES / "nonlinear" / "orifice_tank.ron", SCENARIOS / "nonlinear" / "tank_draining.ron"),
]


@pytest.mark.parametrize("model,scenario", RUNS, ids=lambda p: p.stem)
def test_simulation_is_the_command_lines(cli, model, scenario):
    ours = bondgraph.load(rel(model)).simulate(rel(scenario))
    theirs = cli.json("simulate", rel(model), "--scenario", rel(scenario))
    samples = theirs.pop("samples")
    assert ours.document == theirs
    np.testing.assert_array_equal(ours.t, [s["t"] for s in samples])
    expected = np.array(
        [[np.nan if s["values"][n] is None else s["values"][n] for n in ours.output_names]
         for s in samples],
        dtype=float,
    )
    np.testing.assert_array_equal(ours.values, expected)
    assert [ours.modes[k] for k in ours.mode] == [s["mode"] for s in samples]
    np.testing.assert_array_equal(ours.event_times, [e["t"] for e in theirs["events"]])


def test_belt_stick_slip_events_by_hand():
    # m = 1 kg, k = 100 N/m, F_S = 10 N, F_C = 6 N, belt at 0.1 m/s. Stuck, the spring
    # stretches at 0.1 m/s to F_S/k = 0.1 m: slip at t = 1 s. Slipping, x = 0.06 +
    # 0.04 cos(10 t) + 0.01 sin(10 t) (about F_C/k, at 10 rad/s, leaving at the belt's
    # speed); the block is back at the belt's speed when tan(5 t) = -4, after
    # (2 pi - 2 atan 4)/10 s, at x = 0.02 m; stuck, it takes 0.08/0.1 = 0.8 s back to 0.1 m.
    slip = (2 * math.pi - 2 * math.atan(4.0)) / 10
    expected = [1.0, 1.0 + slip, 1.8 + slip, 1.8 + 2 * slip]
    run = bondgraph.load(rel(EXAMPLES / "belt_friction.ron")).simulate(
        rel(SCENARIOS / "belt_stick_slip.ron")
    )
    np.testing.assert_allclose(run.event_times, expected, rtol=0, atol=1e-9)
    assert [e["to"] for e in run.events] == [
        "friction=slip+", "friction=stuck", "friction=slip+", "friction=stuck"
    ]


def test_robot_breaks_away_when_the_pressure_force_reaches_the_breakaway_force():
    # A P_s = F_S_ge with P_s = 1e6 t Pa, A = 1e-4 m^2, F_S_ge = 11.7 N: t = 0.117 s.
    run = bondgraph.load(rel(EVERSION / "robot.ron")).simulate(
        rel(SCENARIOS / "robot_growth.ron")
    )
    assert len(run.events) == 1
    assert run.events[0]["element"] == "fr_ge"
    assert abs(run.event_times[0] - 11.7 / (1e-4 * 1e6)) < 1e-12


def test_scenario_as_text_and_the_analytic_step_response():
    # A mass m = 2 kg on a spring k = 200 N/m and a damper b = 4 N s/m, pushed by F = 1 N
    # from rest: x(t) = (1/k) (1 - e^{-zeta w t} (cos(wd t) + zeta w / wd sin(wd t))), with
    # w = 10 rad/s, zeta = b / (2 sqrt(k m)) = 0.1, wd = w sqrt(1 - zeta^2).
    model = bondgraph.load(rel(EXAMPLES / "mass_spring_damper.ron"))
    run = model.simulate(
        'Scenario(name: "step", inputs: {"F": Constant(1.0)}, duration: 2.0,'
        ' record: ["effort:spring"], sample: 0.01)'
    )
    w, zeta = 10.0, 0.1
    wd = w * math.sqrt(1 - zeta**2)
    t = run.t
    x = (1 - np.exp(-zeta * w * t) * (np.cos(wd * t) + zeta * w / wd * np.sin(wd * t))) / 200
    np.testing.assert_allclose(run.outputs["effort:spring"], 200 * x, rtol=1e-6, atol=1e-9)
    assert run.events == [] and run.final["t"] == 2.0


def test_plots_are_svg():
    run = bondgraph.load(rel(EXAMPLES / "belt_friction.ron")).simulate(
        rel(SCENARIOS / "belt_stick_slip.ron")
    )
    assert run._repr_svg_().lstrip().startswith("<svg")
    assert run.plot().text == run._repr_svg_()
    lg = bondgraph.load(rel(EXAMPLES / "rlc.lg.ron"))
    assert lg._repr_svg_().lstrip().startswith("<svg")
    assert lg.diagram().text == lg._repr_svg_()


@pytest.mark.parametrize("model,scenario", RUNS, ids=lambda p: p.stem)
def test_csv_and_plot_are_the_command_lines(cli, tmp_path, model, scenario):
    ours = bondgraph.load(rel(model)).simulate(rel(scenario))
    plot = tmp_path / "plot.svg"
    csv = cli.run("simulate", rel(model), "--scenario", rel(scenario), "--plot", str(plot)).stdout
    assert ours.to_csv() == csv
    assert ours.plot().text == plot.read_text()
    assert ours._repr_svg_() == plot.read_text()


def test_panels_are_the_command_lines(cli, tmp_path):
    # The teaching folder's mass-spring-damper release, in three panels as its README draws it.
    teaching = EXAMPLES.parent / "teaching"
    model, scenario = rel(teaching / "mass_spring_damper.ron"), rel(teaching / "scenarios" / "msd_release.ron")
    panels = ["flow:mass", "effort:spring", "energy:mass,energy:spring,energy:stored,energy:dissipated"]
    plot = tmp_path / "plot.svg"
    args = [arg for panel in panels for arg in ("--panel", panel)]
    cli.run("simulate", model, "--scenario", scenario, "--plot", str(plot), *args)
    run = bondgraph.load(model).simulate(scenario)
    assert run.plot(panels).text == plot.read_text()
    as_lists = [["flow:mass"], ["effort:spring"], panels[2].split(",")]
    assert run.plot(as_lists).text == plot.read_text()
    with pytest.raises(bondgraph.BondGraphError, match="nobody"):
        run.plot(["flow:nobody"])
