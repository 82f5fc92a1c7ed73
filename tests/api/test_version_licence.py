"""`hydro --version`, the licence file and the licence declared in pyproject.toml."""
import tomllib
from pathlib import Path

from typer.testing import CliRunner

import hydrocli
from hydrocli.cli.main import app

ROOT = Path(__file__).resolve().parents[2]


def test_version_option_prints_the_package_version():
    res = CliRunner().invoke(app, ["--version"])
    assert res.exit_code == 0
    assert res.output.strip() == f"hydrocli {hydrocli.__version__}"


def test_version_matches_pyproject_and_licence_is_apache():
    meta = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert meta["version"] == hydrocli.__version__
    assert meta["license"] == {"text": "Apache-2.0"}
    text = (ROOT / "LICENSE").read_text()
    assert "Apache License" in text and "Version 2.0, January 2004" in text
    assert "END OF TERMS AND CONDITIONS" in text
