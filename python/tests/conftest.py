"""Shared helpers: the repository's files and the command line whose JSON the bindings
must reproduce.

The command line is the binary named by ``BONDGRAPH_BIN``, or else the release or debug
build under ``target/`` (``.ci/run`` sets the variable to the binary ``cargo test`` built).
"""

import json
import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "models" / "examples"
SCENARIOS = ROOT / "models" / "scenarios"
EVERSION = ROOT / "models" / "eversion"


def _binary() -> Path:
    named = os.environ.get("BONDGRAPH_BIN")
    if named:
        return Path(named)
    for profile in ("release", "debug"):
        candidate = ROOT / "target" / profile / "bondgraph"
        if candidate.exists():
            return candidate
    raise RuntimeError("no bondgraph binary: build it or set BONDGRAPH_BIN")


class Cli:
    """Runs ``bondgraph`` from the repository root."""

    def __init__(self) -> None:
        self.binary = _binary()

    def run(self, *args: str, ok: bool = True) -> subprocess.CompletedProcess:
        done = subprocess.run(
            [str(self.binary), *args], cwd=ROOT, capture_output=True, text=True, timeout=600
        )
        if ok and done.returncode != 0:
            raise AssertionError(f"bondgraph {' '.join(args)} failed:\n{done.stderr}")
        return done

    def json(self, *args: str) -> dict:
        return json.loads(self.run(*args, "--format", "json").stdout)


@pytest.fixture(scope="session")
def cli() -> Cli:
    return Cli()


@pytest.fixture(autouse=True)
def at_root(monkeypatch):
    """Paths in the tests are relative to the repository root, as the CLI's are."""
    monkeypatch.chdir(ROOT)


def rel(path: Path) -> str:
    """``path`` relative to the root: file names in documents then match the CLI's."""
    return str(path.relative_to(ROOT))
