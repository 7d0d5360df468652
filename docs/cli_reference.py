"""Write ``docs/cli.md``: the help text of ``mjrft`` and of each of its commands, exactly as printed.

    python docs/cli_reference.py          # rewrite docs/cli.md
    python docs/cli_reference.py --check  # exit 1 when docs/cli.md is out of date

The help is formatted at a fixed width (``COLUMNS`` = 100), so the page does not depend on the terminal.
``tests/test_docs.py`` checks that the page matches.
"""

from __future__ import annotations

import contextlib
import io
import os
import sys
from pathlib import Path

OUT = Path(__file__).resolve().parent / "cli.md"
WIDTH = "100"
#: commands that have subcommands of their own (the commands themselves come from ``mjrft.tools.cli.COMMANDS``)
NESTED = {"rig": ("plate", "leg")}

HEADER = """# Command-line reference

Every `mjrft` command with its options, as `mjrft <command> --help` prints them. This page is generated
by `python docs/cli_reference.py`; `tests/test_docs.py` checks that it matches the installed commands.
The user guide explains the commands: [index](index.md).
"""


def help_text(argv: list[str]) -> str:
    """What ``mjrft *argv --help`` prints, at ``WIDTH`` columns."""
    from mjrft.tools.cli import main

    old = os.environ.get("COLUMNS")
    os.environ["COLUMNS"] = WIDTH
    out = io.StringIO()
    try:
        with contextlib.redirect_stdout(out), contextlib.suppress(SystemExit):
            main([*argv, "--help"])
    finally:
        if old is None:
            os.environ.pop("COLUMNS", None)
        else:
            os.environ["COLUMNS"] = old
    return out.getvalue().rstrip() + "\n"


def commands() -> list[str]:
    from mjrft.tools.cli import COMMANDS

    return list(COMMANDS)


def render() -> str:
    """The page."""
    parts = [HEADER, "## mjrft\n", "```text\n" + help_text([]) + "```\n"]
    for name in commands():
        parts += [f"## mjrft {name}\n", "```text\n" + help_text([name]) + "```\n"]
        for sub in NESTED.get(name, ()):
            parts += [f"### mjrft {name} {sub}\n", "```text\n" + help_text([name, sub]) + "```\n"]
    return "\n".join(parts)


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    text = render()
    if "--check" in argv:
        current = OUT.read_text() if OUT.exists() else ""
        print("docs/cli.md is " + ("current" if current == text else "out of date: run python docs/cli_reference.py"))
        return 0 if current == text else 1
    OUT.write_text(text)
    print(f"wrote {OUT}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
