"""The wheel carries the third-party notices (docs/THIRD_PARTY.md) for the code compiled or linked
into what it installs: THIRD_PARTY.md itself and, in facet/licenses/, the Debian copyright file of
each component the table says is compiled or linked in (static, compiled in) and the licence texts
the table names (Apache-2.0, LGPL-2.1, the GCC Runtime Library Exception). Read from the wheel
install_wheel built (the file users get) and from the package installed from it."""
import os
import re
import sys
import zipfile
from pathlib import Path

import pytest

import facet

ROOT = Path(__file__).resolve().parents[2]
THIRD_PARTY = ROOT / "docs" / "THIRD_PARTY.md"
LICENSES = ROOT / "packaging" / "licenses"
# Licence texts carried in full, by how the table's licence column names them.
LICENCE_TEXTS = {"Apache-2.0": "Apache-2.0", "LGPL-2.1": "LGPL-2.1", "GCC Runtime Library Exception": "GCC-exception-3.1"}


def named_notices(text: str) -> set:
    """The files in licenses/ that THIRD_PARTY.md's table asks for: `<component>.copyright` for each
    component compiled or linked into facet's files (its first word, lower case: Highway ->
    highway.copyright), `<component>.copyright` for code under the (L)GPL used dynamically (the
    copyright file names what users may relink), and the licence texts named in the licence column."""
    notices = set()
    rows = [line for line in text.splitlines() if line.startswith("| ") and not line.startswith("| component")]
    rows = [[cell.strip() for cell in row.strip("|").split("|")] for row in rows]
    rows = [r for r in rows if len(r) == 4 and not set(r[0]) <= set("-")]
    assert len(rows) >= 10, "THIRD_PARTY.md's table of components was not found"
    for component, _package, licence, use in rows:
        for name, text_file in LICENCE_TEXTS.items():
            if name in licence:
                notices.add(text_file)
        in_the_files = re.search(r"\b(static|compiled in)\b", use) is not None
        if (in_the_files or re.search(r"\bL?GPL\b", licence)) and "GCC Runtime Library Exception" not in licence:
            if "glibc" in component:
                continue  # the system's C library, under LGPL-2.1+: its text is LGPL-2.1
            notices.add(re.split(r"[ (,]", component)[0].lower() + ".copyright")
    return notices


def test_the_table_names_the_notices_of_the_code_in_the_files():
    notices = named_notices(THIRD_PARTY.read_text())
    # The module's own compiled-in code and the statically linked archives, at least.
    for expected in ("pybind11.copyright", "highway.copyright", "zlib.copyright", "libseccomp.copyright",
                     "Apache-2.0", "LGPL-2.1", "GCC-exception-3.1"):
        assert expected in notices, (expected, sorted(notices))
    for name in notices:
        assert (LICENSES / name).is_file(), f"THIRD_PARTY.md asks for {name}, which packaging/licenses/ does not hold"


def built_wheel() -> Path:
    # install_wheel: OUT_DIR/dist holds the wheel, OUT_DIR/venv the environment these tests run in.
    wheels = sorted((Path(sys.prefix).parent / "dist").glob("facet-*.whl"))
    if os.environ.get("FACET_TEST_INSTALLED") != "1" or not wheels:
        pytest.skip("not run against a wheel built by tests/python/install_wheel")
    return wheels[-1]


def test_the_wheel_carries_third_party_md_and_each_notice_it_names():
    with zipfile.ZipFile(built_wheel()) as wheel:
        files = set(wheel.namelist())
        assert "facet/THIRD_PARTY.md" in files, "the wheel has no facet/THIRD_PARTY.md"
        assert wheel.read("facet/THIRD_PARTY.md") == THIRD_PARTY.read_bytes()
        wanted = named_notices(THIRD_PARTY.read_text()) | {p.name for p in LICENSES.iterdir()}
        missing = sorted(name for name in wanted if f"facet/licenses/{name}" not in files)
        assert not missing, f"the wheel has no facet/licenses/ {missing}"
        for name in wanted:
            assert wheel.read(f"facet/licenses/{name}") == (LICENSES / name).read_bytes(), name


def test_the_installed_package_holds_them_too():
    built_wheel()
    package = Path(facet.__file__).resolve().parent
    assert (package / "THIRD_PARTY.md").read_bytes() == THIRD_PARTY.read_bytes()
    for name in named_notices(THIRD_PARTY.read_text()):
        assert (package / "licenses" / name).stat().st_size > 0, name
