"""Shared fixtures: a context on the tests' device ($CLRASTER_DEVICE, as the C++ tests take it), the
command line to compare pictures with, and assimp's test models (scripts/setup.sh installs them)."""

import os
import pathlib
import subprocess

import numpy as np
import pytest
from PIL import Image

import clraster

REPOSITORY = pathlib.Path(__file__).resolve().parents[2]
MODELS = pathlib.Path("/usr/share/assimp/models")


@pytest.fixture(scope="session")
def ctx():
    return clraster.Context()


@pytest.fixture(scope="session")
def cli():
    """The command line: $CLRASTER_CLI, else the build's (scripts/build.sh)."""
    path = pathlib.Path(os.environ.get("CLRASTER_CLI", REPOSITORY / "build" / "src" / "clraster"))
    if not path.is_file():
        pytest.fail(f"the command line {path} is not built: scripts/build.sh builds it, or set CLRASTER_CLI")
    return path


@pytest.fixture(scope="session")
def wuson():
    path = MODELS / "OBJ" / "WusonOBJ.obj"
    if not path.is_file():
        pytest.fail(f"{path} is missing: scripts/setup.sh installs assimp-testmodels")
    return path


def cli_picture(cli, tmp_path, *arguments):
    """What `clraster render ARGUMENTS` draws, as uint8 (H, W, 4)."""
    output = tmp_path / "cli.png"
    subprocess.run([str(cli), "render", *map(str, arguments), "--output", str(output)], check=True)
    with Image.open(output) as picture:
        return np.asarray(picture.convert("RGBA"))
