"""`python -m soadyn.check FILE [options]`: the same as `soadyn check FILE [options]`."""
import sys

from ..apps.cli import main

sys.exit(main(["check", *sys.argv[1:]]))
