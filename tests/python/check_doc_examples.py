"""mypy --strict on the typed examples of docs/client-python.md (issue 32).

Each ```python block becomes a module: a block that imports gport runs as
it is written; the others are the body of a function given `gimbal`, as the
page introduces them. Exit status: mypy's (0 clean), 1 when the page has no
examples.
"""

import os
import pathlib
import subprocess
import sys
import tempfile
import textwrap

PRELUDE = "import time\n\nimport gport\n\n\ndef example(gimbal: gport.Client) -> None:\n"


def blocks(page: str) -> list[str]:
    found: list[str] = []
    lines: list[str] | None = None
    for line in page.splitlines():
        if line.startswith("```python"):
            lines = []
        elif line.startswith("```") and lines is not None:
            found.append("\n".join(lines) + "\n")
            lines = None
        elif lines is not None:
            lines.append(line)
    return found


def module(block: str) -> str:
    if block.startswith("import gport"):
        return block
    return PRELUDE + textwrap.indent(block, "    ")


def main() -> int:
    page, package = pathlib.Path(sys.argv[1]), sys.argv[2]
    examples = blocks(page.read_text(encoding="utf-8"))
    if not examples:
        print(f"{page}: no ```python examples", file=sys.stderr)
        return 1
    with tempfile.TemporaryDirectory() as work:
        paths = []
        for number, block in enumerate(examples, 1):
            path = pathlib.Path(work) / f"doc_example_{number}.py"
            path.write_text(module(block), encoding="utf-8")
            paths.append(str(path))
        command = [sys.executable, "-m", "mypy", "--strict", "--no-error-summary",
                   "--cache-dir", str(pathlib.Path(work) / "cache"), *paths]
        print(f"MYPYPATH={package}", " ".join(command))
        env = dict(os.environ, MYPYPATH=package)
        return subprocess.run(command, env=env, check=False).returncode


if __name__ == "__main__":
    sys.exit(main())
