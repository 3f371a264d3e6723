"""Fixtures of the Python package's tests: real meshes (Debian's libcgal-demo and
assimp-testmodels, which scripts/setup installs; a test that needs them skips, saying so, when
they are missing), the facet executable installed with the package, and a check that the package
under test is the installed one, not the sources."""
import os
import sys
import tarfile
from pathlib import Path

import pytest

import facet

CGAL_DATA = Path("/usr/share/doc/libcgal-dev/data.tar.gz")
ASSIMP_MODELS = Path("/usr/share/assimp/models")


def pytest_sessionstart(session):
    # CTest runs these against the wheel installed in a virtual environment (tests/python/install_wheel).
    installed = Path(facet.__file__).resolve()
    if os.environ.get("FACET_TEST_INSTALLED") == "1" and not str(installed).startswith(str(Path(sys.prefix).resolve())):
        raise pytest.UsageError(f"facet is imported from {installed}, not from the installed package in {sys.prefix}")


@pytest.fixture(scope="session")
def meshes(tmp_path_factory) -> Path:
    """The directory holding CGAL's bunny00.off and elephant.off."""
    if not CGAL_DATA.exists():
        pytest.skip(f"{CGAL_DATA} is missing: install Debian's libcgal-demo (scripts/setup does)")
    out = tmp_path_factory.mktemp("cgal")
    with tarfile.open(CGAL_DATA) as tar:
        for name in ("bunny00.off", "elephant.off"):
            member = tar.getmember(f"data/meshes/{name}")
            member.name = name
            tar.extract(member, out)
    return out


@pytest.fixture(scope="session")
def bunny(meshes) -> Path:
    return meshes / "bunny00.off"


@pytest.fixture(scope="session")
def assimp_models() -> Path:
    if not ASSIMP_MODELS.is_dir():
        pytest.skip(f"{ASSIMP_MODELS} is missing: install Debian's assimp-testmodels (scripts/setup does)")
    return ASSIMP_MODELS


@pytest.fixture(scope="session")
def facet_exe() -> Path:
    """The command line installed with the package (what `python3 -m facet` runs)."""
    exe = Path(facet.__file__).resolve().parent / "bin" / "facet"
    assert exe.is_file(), f"{exe} is missing from the installed package"
    return exe
