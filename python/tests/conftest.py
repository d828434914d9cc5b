"""Shared fixtures: the repository, the CLI binary the Python results are held against, and
../shared/data (tests that need it are skipped with a reason pytest prints in its summary)."""

import os
import subprocess
from pathlib import Path

import numpy as np
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


def sphere(rows=12, cols=16):
    """A UV sphere as arrays: vertices, faces, normals, uvs."""
    theta = np.linspace(0, np.pi, rows + 1)
    phi = np.linspace(0, 2 * np.pi, cols + 1)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    v = np.stack([np.sin(t) * np.cos(p), np.cos(t), np.sin(t) * np.sin(p)], axis=-1).reshape(-1, 3)
    uv = np.stack([p / (2 * np.pi), 1 - t / np.pi], axis=-1).reshape(-1, 2)
    idx = np.arange((rows + 1) * (cols + 1)).reshape(rows + 1, cols + 1)
    a, b, c, d = idx[:-1, :-1], idx[:-1, 1:], idx[1:, 1:], idx[1:, :-1]
    faces = np.concatenate([np.stack([a, c, b], -1).reshape(-1, 3), np.stack([a, d, c], -1).reshape(-1, 3)])
    return v, faces, v.copy(), uv
