"""Shared fixtures: the repository, the CLI binary the Python results are held against, and
../shared/data (tests that need it are skipped with a reason pytest prints in its summary)."""

import os
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
SHARED = REPO.parent / "shared" / "data"


def cli_binary():
    """The `pointshade` CLI: $POINTSHADE_CLI, else target/release/pointshade (built by the
    README's test command). Missing, it is a failure, not a skip: the comparisons are the point."""
    path = Path(os.environ.get("POINTSHADE_CLI", REPO / "target" / "release" / "pointshade"))
    if not path.is_file():
        pytest.fail(f"the CLI {path} is missing: run `cargo build --release` first or set POINTSHADE_CLI")
    return path


@pytest.fixture
def cli():
    binary = cli_binary()

    def run(*args):
        result = subprocess.run([str(binary), *map(str, args)], capture_output=True, text=True)
        assert result.returncode == 0, result.stderr
        return result

    return run


@pytest.fixture
def shared():
    if not SHARED.is_dir():
        pytest.skip("needs ../shared/data (the public test data; see README.md, 'Test data')")
    return SHARED
