"""MkDocs hook: the command-line reference (reference/cli.md), written at build time from the parsers of
`soadyn` itself (soadyn.apps.cli.build_parser), so it says what the installed commands accept."""
from __future__ import annotations

import os

from mkdocs.structure.files import File

PAGE = "reference/cli.md"
WIDTH = "100"  # argparse wraps the help to $COLUMNS: a fixed width gives the same page everywhere


def cli_reference() -> str:
    os.environ["COLUMNS"] = WIDTH
    from soadyn.apps.cli import build_parser

    parser, commands = build_parser()
    parts = ["# Command line\n",
             "Generated from the parsers of `soadyn` when this manual is built: what `soadyn --help` and "
             "`soadyn COMMAND --help` print.\n",
             "```text\n" + parser.format_help() + "```\n"]
    for name, command in commands.items():
        parts += [f"## soadyn {name}\n", "```text\n" + command.format_help() + "```\n"]
    return "\n".join(parts)


def on_files(files, config):
    files.append(File.generated(config, PAGE, content=cli_reference()))
    return files
