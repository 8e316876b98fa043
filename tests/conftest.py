"""The suite's one conftest. Test modules sit in folders that mirror the package (dynamics/, io/, loops/, ...)
and are imported by pytest with --import-mode=importlib (pyproject.toml), so two folders may hold modules
of the same name and no folder needs an __init__.py. What tests share is imported from this folder:
support/ (builders, oracle mappings, fixtures) and fuzz/ (the fuzz cases), as `from support.trees import ...`."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
