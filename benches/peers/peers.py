"""What the side-by-side scripts in this folder share: a virtual environment of their own
with scipy from PyPI, and criterion's median of a bondgraph bench."""

import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
VENV = os.path.join(HERE, ".venv")


def ensure_venv():
    """Runs the calling script again in benches/peers/.venv (made, with scipy, if missing)."""
    python = os.path.join(VENV, "bin", "python")
    if sys.executable != python:
        if not os.path.exists(python):
            subprocess.check_call([sys.executable, "-m", "venv", VENV])
            subprocess.check_call([python, "-m", "pip", "install", "--quiet", "scipy"])
        os.execv(python, [python] + sys.argv)


def criterion_median(name):
    """The median of criterion's last run of bench `name`, in seconds (None if not run)."""
    path = os.path.join(ROOT, "target", "criterion", name, "new", "estimates.json")
    try:
        with open(path) as f:
            return json.load(f)["median"]["point_estimate"] / 1e9
    except OSError:
        return None
