"""Builds facet's Python package with CMake (pyproject.toml says how to call it).

The extension module facet._facet and the facet executables come from the CMake project in
this directory (target facet_python, python/CMakeLists.txt), built in build/pip, or, when
FACET_CMAKE_BUILD_DIR names a configured build tree (CI: build/release), taken from there after
an incremental build. Nothing is downloaded.
"""
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent
# The executables `python3 -m facet` runs: facet, and facet-view beside it for `facet view`.
EXECUTABLES = ["facet", "facet-view"]


def project_version() -> str:
    m = re.search(r"project\(facet VERSION ([0-9.]+)", (ROOT / "CMakeLists.txt").read_text())
    if not m:
        raise RuntimeError("setup.py: no version in CMakeLists.txt's project()")
    return m.group(1)


def build_dir() -> Path:
    given = os.environ.get("FACET_CMAKE_BUILD_DIR")
    return Path(given).resolve() if given else ROOT / "build" / "pip"


class CMakeBuild(build_ext):
    """Configures (unless given a build tree) and builds the CMake targets, then copies the
    module and the executables into the package."""

    def build_extension(self, ext: Extension) -> None:
        out = build_dir()
        if not os.environ.get("FACET_CMAKE_BUILD_DIR"):
            args = [
                "cmake", "-S", str(ROOT), "-B", str(out), "-G", "Ninja",
                "-DCMAKE_BUILD_TYPE=Release",
                f"-DPython_EXECUTABLE={sys.executable}",
                "-DFACET_BUILD_PYTHON=ON", "-DFACET_BUILD_TESTS=OFF",
                "-DFACET_BUILD_EXAMPLES=OFF", "-DFACET_BUILD_BENCH=OFF",
            ]
            try:
                import pybind11  # Debian's python3-pybind11: the same pybind11-dev CMake files

                args.append(f"-Dpybind11_DIR={pybind11.get_cmake_dir()}")
            except ImportError:
                pass
            subprocess.run(args, check=True)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 1))
        subprocess.run(["cmake", "--build", str(out), "-j", jobs, "--target", "facet_python", "facet_cli",
                        "facet_view"], check=True)
        module = Path(self.get_ext_fullpath(ext.name))
        module.parent.mkdir(parents=True, exist_ok=True)
        built = sorted((out / "python" / "facet").glob("_facet*.so"))
        if not built:
            raise RuntimeError(f"setup.py: no _facet module in {out / 'python' / 'facet'}")
        shutil.copy2(built[-1], module)
        bin_dir = module.parent / "bin"
        bin_dir.mkdir(exist_ok=True)
        for name in EXECUTABLES:
            shutil.copy2(out / "bin" / name, bin_dir / name)
        # facet's modules (libfacet_assimp.so: assimp's formats, OBJ and glTF; libfacet_exr.so:
        # --float-format exr), which the extension and the executables look for beside themselves.
        for built_module in sorted((out / "lib" / "facet").glob("libfacet_*.so")):
            for folder in (module.parent, bin_dir):
                shutil.copy2(built_module, folder / built_module.name)
        # The third-party code in these files and the licence texts it asks to be carried with them.
        shutil.copy2(ROOT / "docs" / "THIRD_PARTY.md", module.parent / "THIRD_PARTY.md")
        # Copied afresh: setuptools' scratch folder outlives a build, and a notice dropped from
        # packaging/licenses/ must not stay in the next wheel.
        shutil.rmtree(module.parent / "licenses", ignore_errors=True)
        shutil.copytree(ROOT / "packaging" / "licenses", module.parent / "licenses")


# setuptools' own scratch (build/, *.egg-info) goes beside the CMake build, not into the sources.
scratch = build_dir() / "setuptools"
scratch.mkdir(parents=True, exist_ok=True)
setup(
    version=project_version(),
    ext_modules=[Extension("facet._facet", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    options={"build": {"build_base": str(scratch)}, "egg_info": {"egg_base": str(scratch)}},
)
