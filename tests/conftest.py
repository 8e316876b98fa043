import sys
from pathlib import Path

# The helpers shared by the tests (trees.py) live beside them.
sys.path.insert(0, str(Path(__file__).parent))
