"""`python3 -m facet ...` runs facet's command line (`facet render`, `facet thumbs`,
`facet view`), the executable installed with the package."""
import os
import sys
from pathlib import Path


def main() -> int:
    exe = Path(__file__).resolve().parent / "bin" / "facet"
    if not exe.is_file():
        print(f"facet: the command line is not installed with this package ({exe} is missing)", file=sys.stderr)
        return 1
    sys.stdout.flush()
    sys.stderr.flush()
    os.execv(exe, [str(exe)] + sys.argv[1:])
    return 1  # not reached


if __name__ == "__main__":
    sys.exit(main())
