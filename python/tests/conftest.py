"""Shared fixtures of the Python package's tests: the ``muse`` binary, to compare the package
with the command line it mirrors."""

import os
import pathlib
import subprocess

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]


def muse_bin() -> pathlib.Path:
    """The ``muse`` binary: ``$MUSE_BIN``, else the debug build of this checkout."""
    path = pathlib.Path(os.environ.get("MUSE_BIN", REPO / "target" / "debug" / "muse"))
    if not path.is_file():
        pytest.fail(f"no muse binary at {path}: run `cargo build` or set MUSE_BIN")
    return path


@pytest.fixture(scope="session")
def muse_cli():
    """Runs the ``muse`` command line; returns the completed process (output as text)."""

    def run(*args, check=True):
        done = subprocess.run(
            [str(muse_bin()), *map(str, args)], capture_output=True, text=True
        )
        if check and done.returncode != 0:
            raise AssertionError(f"muse {' '.join(map(str, args))}: {done.stderr}")
        return done

    return run
